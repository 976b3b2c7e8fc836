//! Relay orbiters placed for navigation: `optimize orbiters --objective nav|pcrlb-avg|pcrlb-final`.
//!
//! The objective is the nominal-trajectory position bound of the scenario with the candidate
//! orbiters ([`entrynav::sim::bounds::nominal_bound`], moving sites: the trade's PCRLB recursion on the
//! nominal truth with the beacon-independent parts computed once, line of sight by seed 002
//! eq. 58–60): its time average (`pcrlb-avg`), its value at the last epoch (`pcrlb-final`), or
//! `nav` = ½ (avg / avg_input + final / final_input) relative to the scenario's own orbiters.
//! A candidate costs tens of microseconds, so the full global search of [`crate::orbiters`]
//! (particle swarm + restarted Nelder–Mead over (Ω, i, f) per orbiter) runs on it directly.
//! Hidden orbiters give no information, so no visibility penalty is needed.

use crate::error::OptimizerError;
use crate::orbiters::OrbitElements;
use crate::orbiters::problem::OrbiterProblem;
use crate::progress::Progress;
use crate::search::minimize;
use crate::search_options::{SearchOptions, SearchResult};
use entrynav::scenario::Scenario;
use entrynav::sim::bounds::nominal_bound::{NominalBound, NominalBoundSeries};
use std::time::Instant;

/// Which figure of the nominal position bound is minimised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundFigure {
    /// Time average \[m\].
    Average,
    /// At the last epoch \[m\].
    Final,
    /// ½ (avg / avg_input + final / final_input).
    Navigation,
}

impl BoundFigure {
    /// Name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            BoundFigure::Average => "pcrlb-avg",
            BoundFigure::Final => "pcrlb-final",
            BoundFigure::Navigation => "nav",
        }
    }
}

/// The orbiter problem on the nominal position bound.
#[derive(Debug, Clone)]
pub struct OrbiterNavProblem {
    geometry: OrbiterProblem,
    bound: NominalBound,
    figure: BoundFigure,
    sigma_m: f64,
    /// `(sin, cos)` of n·t at the bound's epochs.
    phase: Vec<(f64, f64)>,
    radius: f64,
    reference: Option<(f64, f64)>,
}

/// The bound-optimal constellation.
#[derive(Debug, Clone)]
pub struct OrbiterNavSolution {
    /// Canonical elements.
    pub elements: Vec<OrbitElements>,
    /// The objective's value.
    pub value: f64,
    /// The bound along the entry at `elements`.
    pub series: NominalBoundSeries,
    /// Search statistics (cost: log10 of the value).
    pub search: SearchResult,
    /// Wall time \[s\].
    pub elapsed_s: f64,
}

impl OrbiterNavProblem {
    /// `geometry`'s orbiters (count, altitude, search box) scored by the nominal bound of
    /// `scenario` (which must measure ranges to its beacons) with range noise `sigma_m`.
    pub fn new(
        geometry: OrbiterProblem,
        scenario: &Scenario,
        sigma_m: f64,
        figure: BoundFigure,
    ) -> Result<OrbiterNavProblem, OptimizerError> {
        let bound = NominalBound::new(scenario)?;
        let planet = &geometry.trajectory().planet;
        let radius = planet.radius + geometry.altitude_m();
        let n = (planet.mu / radius.powi(3)).sqrt();
        let phase = bound
            .epoch_times()
            .iter()
            .map(|t| (n * t).sin_cos())
            .collect();
        Ok(OrbiterNavProblem {
            geometry,
            bound,
            figure,
            sigma_m,
            phase,
            radius,
            reference: None,
        })
    }

    /// The input design `elements` (the scenario's own orbiters) that `nav` is relative to.
    pub fn with_reference(
        mut self,
        elements: &[OrbitElements],
    ) -> Result<OrbiterNavProblem, OptimizerError> {
        let s = self.series(elements)?;
        let (avg, last) = (s.time_avg(), s.final_value());
        if !(avg.is_finite() && avg > 0.0 && last.is_finite() && last > 0.0) {
            return Err(OptimizerError::InvalidInput(format!(
                "the input orbiters' position bound ({avg} m averaged, {last} m final) cannot \
                 normalise the navigation objective"
            )));
        }
        self.reference = Some((avg, last));
        Ok(self)
    }

    /// The input design's (time-averaged, final) bound \[m\], when set.
    pub fn reference(&self) -> Option<(f64, f64)> {
        self.reference
    }

    /// The orbit geometry (count, altitude, search box).
    pub fn geometry(&self) -> &OrbiterProblem {
        &self.geometry
    }

    /// The minimised figure.
    pub fn figure(&self) -> BoundFigure {
        self.figure
    }

    /// The bound along the entry with orbiters on `elements` (any number).
    pub fn series(&self, elements: &[OrbitElements]) -> Result<NominalBoundSeries, OptimizerError> {
        let positions: Vec<Vec<[f64; 3]>> = elements
            .iter()
            .map(|el| {
                let (p, q) = el.basis();
                let (sf, cf) = el.true_anomaly.sin_cos();
                self.phase
                    .iter()
                    .map(|(sn, cn)| {
                        let c = cf * cn - sf * sn;
                        let s = sf * cn + cf * sn;
                        let r = self.radius;
                        [
                            r * (c * p[0] + s * q[0]),
                            r * (c * p[1] + s * q[1]),
                            r * (c * p[2] + s * q[2]),
                        ]
                    })
                    .collect()
            })
            .collect();
        let sigma = vec![self.sigma_m; elements.len()];
        Ok(self.bound.moving_sites(&sigma, &positions)?)
    }

    /// The objective at `elements`.
    pub fn value(&self, elements: &[OrbitElements]) -> Result<f64, OptimizerError> {
        let s = self.series(elements)?;
        Ok(match self.figure {
            BoundFigure::Average => s.time_avg(),
            BoundFigure::Final => s.final_value(),
            BoundFigure::Navigation => {
                let (avg, last) = self.reference.ok_or_else(|| {
                    OptimizerError::InvalidInput(
                        "the navigation objective needs the input orbiters (with_reference)".into(),
                    )
                })?;
                0.5 * (s.time_avg() / avg + s.final_value() / last)
            }
        })
    }

    /// The search cost at `x = [Ω₁, i₁, f₁, …]`: log10 of the value (NaN where the bound cannot
    /// be formed; the search replaces it by a large finite cost).
    pub fn cost(&self, x: &[f64]) -> f64 {
        self.value(&self.geometry.elements_from(x))
            .map_or(f64::NAN, |v| v.max(1e-300).log10())
    }

    /// Seeded particle swarm + Nelder–Mead over the geometry's box.
    pub fn optimize(
        &self,
        opts: &SearchOptions,
        progress: Progress<'_>,
    ) -> Result<OrbiterNavSolution, OptimizerError> {
        let started = Instant::now();
        let (lower, upper) = self.geometry.bounds();
        let cost = |x: &[f64]| self.cost(x);
        let search = minimize(&cost, &lower, &upper, opts, progress)?;
        let elements: Vec<OrbitElements> = self
            .geometry
            .elements_from(&search.x)
            .iter()
            .map(OrbitElements::canonical)
            .collect();
        let value = self.value(&elements)?;
        let series = self.series(&elements)?;
        Ok(OrbiterNavSolution {
            elements,
            value,
            series,
            search,
            elapsed_s: started.elapsed().as_secs_f64(),
        })
    }
}
