//! The named choices of the design studies — objectives, criteria, the observability method — as
//! both front ends spell them (`nav`, `pcrlb-avg`, `min-delta`, …; the names of the optimizer's
//! and the core's `name()` methods), each with the one-line help a front end shows, and their
//! conversion into the optimizer's and the core's enums.

use crate::options::OptionError;
use entrynav::observability::Method;
use entrynav_optimizer::SelectionCriterion;
use entrynav_optimizer::{BoundFigure, GroundObjective, LinCovFigure, OrbiterObjective};

/// A closed set of named values: what a front end lists, parses and documents.
pub trait Choice: Copy + Sized + 'static {
    /// Every value, in the order a front end lists them.
    const ALL: &'static [Self];
    /// Its name.
    fn name(self) -> &'static str;
    /// One line saying what it is.
    fn help(self) -> &'static str;
    /// Other names accepted for it.
    fn aliases(self) -> &'static [&'static str];

    /// The value named `text` (a name or an alias) of option `option`.
    fn parse(option: &str, text: &str) -> Result<Self, OptionError> {
        Self::ALL
            .iter()
            .copied()
            .find(|c| c.name() == text || c.aliases().contains(&text))
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|c| c.name()).collect();
                OptionError::new(
                    option,
                    format!("'{text}'"),
                    format!("one of {}", names.join(", ")),
                )
            })
    }
}

/// An enum of named values with their help, deserialised from (and parsed by) those names.
macro_rules! choice {
    ($(#[$doc:meta])* $ty:ident {
        $($var:ident = $name:literal $(| $alias:literal)*: $help:literal,)*
    }) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
        pub enum $ty {
            $(#[doc = $help] #[serde(rename = $name $(, alias = $alias)*)] $var,)*
        }

        impl Choice for $ty {
            const ALL: &'static [Self] = &[$($ty::$var),*];
            fn name(self) -> &'static str {
                match self { $($ty::$var => $name),* }
            }
            fn help(self) -> &'static str {
                match self { $($ty::$var => $help),* }
            }
            fn aliases(self) -> &'static [&'static str] {
                match self { $($ty::$var => &[$($alias),*]),* }
            }
        }
    };
}

choice! {
    /// `objective` of the orbiter design (names of [`OrbiterObjective::name`] and the bounds').
    OrbiterObjectiveName {
        DetN3 = "det-n3": "The integral of det(N3) (eq. 57), three orbiters",
        Logdet = "logdet": "The integral of ln det of the FIM",
        Pcrlb = "pcrlb": "The final position PCRLB of Monte Carlo run 0 (minimised; polished from the geometric optimum)",
        PcrlbAvg = "pcrlb-avg": "The time-averaged nominal position bound (minimised, full global search)",
        PcrlbFinal = "pcrlb-final": "The final nominal position bound (minimised, full global search)",
        Nav = "nav": "Both nominal position bounds relative to the scenario's own orbiters, 1/2 (avg/avg_in + final/final_in), minimised",
        LincovAvg = "lincov-avg": "The filter's time-averaged position RMSE predicted by LinCov (the pcrlb-avg optimum polished on it)",
        LincovFinal = "lincov-final": "The filter's final position RMSE predicted by LinCov (the pcrlb-final optimum polished)",
        LincovNav = "lincov-nav": "1/2 (lincov-avg/input's + lincov-final/input's) (the nav optimum polished on it)",
    }
}

choice! {
    /// `objective` of the ground-site design (names of [`GroundObjective::name`]).
    GroundObjectiveName {
        MinDelta = "min-delta": "min over time of delta (eq. 49)",
        Logdet = "logdet": "The integral of ln det FIM",
        MinEig = "min-eig": "min over time of lambda_min(FIM)",
        PcrlbAvg = "pcrlb-avg": "The time-averaged position PCRLB along the nominal trajectory (minimised)",
        PcrlbFinal = "pcrlb-final" | "pcrlb": "The final position PCRLB along the nominal trajectory (minimised; alias `pcrlb`)",
        Nav = "nav": "Both position bounds relative to the input design's, 1/2 (avg/avg_in + final/final_in), minimised (the default: it serves navigation over the whole entry and at its end)",
        LincovAvg = "lincov-avg": "The filter's time-averaged position RMSE predicted by LinCov (the pcrlb-avg optimum polished on it)",
        LincovFinal = "lincov-final": "The filter's final position RMSE predicted by LinCov (the pcrlb-final optimum polished)",
        LincovNav = "lincov-nav": "1/2 (lincov-avg/input's + lincov-final/input's) (the nav optimum polished on it)",
    }
}

choice! {
    /// `method` of the observability degree δ (names of [`Method::name`]).
    DeltaMethod {
        Lie = "lie": "Exact Lie derivatives",
        Quadratic = "quadratic": "Quadratic approximation of the Lie derivatives",
        Linear = "linear": "Linearised system",
    }
}

choice! {
    /// `criterion` of the certified site selection (names of [`SelectionCriterion::name`]).
    Criterion {
        Logdet = "logdet": "D-optimal: ln det",
        MinEig = "min-eig": "E-optimal: lambda_min",
    }
}

choice! {
    /// `objective` of the site selection on the nominal bound (without it, `criterion`).
    SelectObjectiveName {
        Nav = "nav": "Both nominal position bounds relative to the input design",
        PcrlbAvg = "pcrlb-avg": "The time-averaged nominal position bound",
        PcrlbFinal = "pcrlb-final": "The final nominal position bound",
        LincovNav = "lincov-nav": "nav's selection, then exchanges on the filter's LinCov (both figures relative to the input's)",
        LincovAvg = "lincov-avg": "pcrlb-avg's selection, then exchanges on the filter's time-averaged LinCov RMSE",
        LincovFinal = "lincov-final": "pcrlb-final's selection, then exchanges on the filter's final LinCov RMSE",
    }
}

impl OrbiterObjectiveName {
    /// The geometric objective this names (`None` for the bound objectives: `pcrlb` polishes
    /// the default one, the nominal-bound ones use it for the search box only).
    pub fn geometric(self) -> Option<OrbiterObjective> {
        match self {
            OrbiterObjectiveName::DetN3 => Some(OrbiterObjective::DetN3),
            OrbiterObjectiveName::Logdet => Some(OrbiterObjective::LogDet),
            _ => None,
        }
    }

    /// The nominal-bound figure this names, if any.
    pub fn bound_figure(self) -> Option<BoundFigure> {
        use OrbiterObjectiveName as O;
        match self {
            O::PcrlbAvg | O::LincovAvg => Some(BoundFigure::Average),
            O::PcrlbFinal | O::LincovFinal => Some(BoundFigure::Final),
            O::Nav | O::LincovNav => Some(BoundFigure::Navigation),
            _ => None,
        }
    }

    /// The LinCov figure the bound's optimum is polished on (lincov-*), if any.
    pub fn lincov_figure(self) -> Option<LinCovFigure> {
        match self {
            OrbiterObjectiveName::LincovAvg => Some(LinCovFigure::Average),
            OrbiterObjectiveName::LincovFinal => Some(LinCovFigure::Final),
            OrbiterObjectiveName::LincovNav => Some(LinCovFigure::Navigation),
            _ => None,
        }
    }
}

impl GroundObjectiveName {
    /// The search's objective (for lincov-*, the bound of the same figure); `method` and
    /// `scaled` are min-delta's.
    pub fn search(self, method: Method, scaled: bool) -> GroundObjective {
        use GroundObjectiveName as G;
        match self {
            G::MinDelta => GroundObjective::MinDelta { method, scaled },
            G::Logdet => GroundObjective::LogDet,
            G::MinEig => GroundObjective::MinEig,
            G::PcrlbAvg | G::LincovAvg => GroundObjective::PcrlbAvg,
            G::PcrlbFinal | G::LincovFinal => GroundObjective::PcrlbFinal,
            G::Nav | G::LincovNav => GroundObjective::Navigation,
        }
    }

    /// The figure the bound's optimum is polished on (lincov-*), if any.
    pub fn lincov_figure(self) -> Option<LinCovFigure> {
        match self {
            GroundObjectiveName::LincovAvg => Some(LinCovFigure::Average),
            GroundObjectiveName::LincovFinal => Some(LinCovFigure::Final),
            GroundObjectiveName::LincovNav => Some(LinCovFigure::Navigation),
            _ => None,
        }
    }
}

impl From<DeltaMethod> for Method {
    fn from(m: DeltaMethod) -> Method {
        match m {
            DeltaMethod::Lie => Method::Lie,
            DeltaMethod::Quadratic => Method::Quadratic,
            DeltaMethod::Linear => Method::Linear,
        }
    }
}

impl From<Criterion> for SelectionCriterion {
    fn from(c: Criterion) -> SelectionCriterion {
        match c {
            Criterion::Logdet => SelectionCriterion::LogDet,
            Criterion::MinEig => SelectionCriterion::MinEig,
        }
    }
}

impl SelectObjectiveName {
    /// The ground objective it names.
    pub fn ground(self) -> GroundObjective {
        use SelectObjectiveName as S;
        match self {
            S::Nav | S::LincovNav => GroundObjective::Navigation,
            S::PcrlbAvg | S::LincovAvg => GroundObjective::PcrlbAvg,
            S::PcrlbFinal | S::LincovFinal => GroundObjective::PcrlbFinal,
        }
    }

    /// The LinCov figure the exchanges use (lincov-*), if any.
    pub fn lincov(self) -> Option<LinCovFigure> {
        match self {
            SelectObjectiveName::LincovNav => Some(LinCovFigure::Navigation),
            SelectObjectiveName::LincovAvg => Some(LinCovFigure::Average),
            SelectObjectiveName::LincovFinal => Some(LinCovFigure::Final),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_with_their_aliases_and_an_unknown_name_lists_the_valid_ones() {
        assert_eq!(
            GroundObjectiveName::parse("objective", "pcrlb"),
            Ok(GroundObjectiveName::PcrlbFinal)
        );
        assert_eq!(
            OrbiterObjectiveName::parse("objective", "det-n3"),
            Ok(OrbiterObjectiveName::DetN3)
        );
        assert_eq!(
            Criterion::parse("criterion", "max")
                .unwrap_err()
                .to_string(),
            "criterion = 'max' is out of range: must be one of logdet, min-eig"
        );
        let m: DeltaMethod = serde_json::from_str("\"quadratic\"").unwrap();
        assert_eq!(Method::from(m).name(), "quadratic");
        for o in SelectObjectiveName::ALL {
            let name = o.lincov().map_or_else(|| o.ground().name(), |f| f.name());
            assert_eq!(name, o.name());
        }
    }
}
