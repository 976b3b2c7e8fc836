//! Designs scored by what the navigation filter will actually do: the `lincov-avg`,
//! `lincov-final` and `lincov-nav` objectives of `optimize ground` and `optimize orbiters`.
//!
//! The score of a beacon set is the position RMSE that the linear covariance analysis of the
//! actual filter predicts along the nominal entry ([`entrynav::sim::lincov`]: Maybeck vol. 1
//! ch. 6, Geller 2006), model mismatch and the filter's own gains included — unlike the PCRLB,
//! which bounds every estimator. The scenario is rebuilt with the candidate beacons
//! ([`Scenario::with_beacons`]: no file is read again) and the LinCov run on it.
//!
//! One LinCov costs whole truth runs (two per dispersed parameter), tens of milliseconds: too
//! much for the global search (thousands of candidates), so the CLI runs the global search on
//! the nominal bound of the same figure and polishes its optimum on this score
//! ([`crate::search::polish_from`]).

use crate::error::OptimizerError;
use entrynav::beacons::BeaconConfig;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::lincov::{EntryLinCov, entry_lincov, unsupported_reason};

/// Which figure of the predicted position RMSE is minimised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinCovFigure {
    /// Time average over the entry \[m\].
    Average,
    /// At the last epoch \[m\].
    Final,
    /// ½ (avg / avg_input + final / final_input).
    Navigation,
}

impl LinCovFigure {
    /// Name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            LinCovFigure::Average => "lincov-avg",
            LinCovFigure::Final => "lincov-final",
            LinCovFigure::Navigation => "lincov-nav",
        }
    }

    /// Unit and meaning of the value.
    pub fn units(self, filter: FilterKind) -> String {
        let f = filter.name();
        match self {
            LinCovFigure::Average => format!(
                "time average of the {f}'s position RMSE predicted by LinCov along the nominal \
                 entry [m], minimised"
            ),
            LinCovFigure::Final => format!(
                "the {f}'s position RMSE at the last epoch predicted by LinCov [m], minimised"
            ),
            LinCovFigure::Navigation => format!(
                "1/2 (lincov-avg / input's + lincov-final / input's) of the {f}'s predicted \
                 position RMSE (1 = as good as the input design; lower is better), minimised"
            ),
        }
    }
}

/// The predicted (time-averaged, final) position RMSE of one design \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinCovFigures {
    /// Time average \[m\].
    pub avg_m: f64,
    /// At the last epoch \[m\].
    pub final_m: f64,
    /// Predicted ANEES/dof (the filter's consistency on this design, by LinCov).
    pub nees_ratio: f64,
}

/// Scores beacon sets of one scenario by LinCov of one filter.
#[derive(Debug, Clone)]
pub struct LinCovScore {
    scenario: Scenario,
    filter: FilterKind,
    figure: LinCovFigure,
    reference: Option<LinCovFigures>,
}

impl LinCovScore {
    /// Score designs of `scenario` (its beacons are replaced by each design's) by LinCov of
    /// `filter`. Errors: a filter LinCov cannot analyse (the reason is named).
    pub fn new(
        scenario: &Scenario,
        filter: FilterKind,
        figure: LinCovFigure,
    ) -> Result<LinCovScore, OptimizerError> {
        if let Some(reason) = unsupported_reason(filter) {
            return Err(OptimizerError::InvalidInput(format!(
                "objective {} needs a filter LinCov can analyse; {} cannot be: {reason}",
                figure.name(),
                filter.name()
            )));
        }
        Ok(LinCovScore {
            scenario: scenario.clone(),
            filter,
            figure,
            reference: None,
        })
    }

    /// The input design (`beacons`) that `lincov-nav` is relative to.
    pub fn with_reference(mut self, beacons: Vec<BeaconConfig>) -> Result<Self, OptimizerError> {
        let f = self.figures(beacons)?;
        if !(f.avg_m > 0.0 && f.final_m > 0.0) {
            return Err(OptimizerError::InvalidInput(format!(
                "the input design's predicted position RMSE ({} m averaged, {} m final) cannot \
                 normalise {}",
                f.avg_m,
                f.final_m,
                self.figure.name()
            )));
        }
        self.reference = Some(f);
        Ok(self)
    }

    /// The input design's figures, when set.
    pub fn reference(&self) -> Option<LinCovFigures> {
        self.reference
    }

    /// The filter analysed.
    pub fn filter(&self) -> FilterKind {
        self.filter
    }

    /// The minimised figure.
    pub fn figure(&self) -> LinCovFigure {
        self.figure
    }

    /// The whole LinCov with `beacons` in place of the scenario's.
    pub fn lincov(&self, beacons: Vec<BeaconConfig>) -> Result<EntryLinCov, OptimizerError> {
        let scenario = self.scenario.with_beacons(beacons)?;
        entry_lincov(&scenario, self.filter)
            .map_err(|e| OptimizerError::InvalidInput(format!("LinCov failed: {e}")))
    }

    /// The predicted figures with `beacons` (finite, or an error).
    pub fn figures(&self, beacons: Vec<BeaconConfig>) -> Result<LinCovFigures, OptimizerError> {
        let l = self.lincov(beacons)?;
        let f = LinCovFigures {
            avg_m: l.time_avg(|e| e.pos_m),
            final_m: l.final_value(|e| e.pos_m),
            nees_ratio: l.nees_ratio_time_avg(),
        };
        if !(f.avg_m.is_finite() && f.final_m.is_finite()) {
            return Err(OptimizerError::InvalidInput(format!(
                "LinCov of {} gave a non-finite position RMSE ({} m averaged, {} m final)",
                self.filter.name(),
                f.avg_m,
                f.final_m
            )));
        }
        Ok(f)
    }

    /// The objective's value from a design's figures.
    pub fn value_of(&self, f: &LinCovFigures) -> Result<f64, OptimizerError> {
        Ok(match self.figure {
            LinCovFigure::Average => f.avg_m,
            LinCovFigure::Final => f.final_m,
            LinCovFigure::Navigation => {
                let r = self.reference.ok_or_else(|| {
                    OptimizerError::InvalidInput(
                        "lincov-nav is relative to the input design (with_reference)".into(),
                    )
                })?;
                0.5 * (f.avg_m / r.avg_m + f.final_m / r.final_m)
            }
        })
    }

    /// The search cost of `beacons`: log10 of the value (NaN where LinCov fails; the search
    /// replaces it by a large finite cost).
    pub fn cost(&self, beacons: Vec<BeaconConfig>) -> f64 {
        self.figures(beacons)
            .and_then(|f| self.value_of(&f))
            .map_or(f64::NAN, |v| v.max(1e-300).log10())
    }
}
