//! The names of objectives, criteria and methods on the command line, each parsed once by clap
//! (an unknown name is a usage error listing the valid ones) and converted into the optimizer's
//! and the core's enums. The spellings are those of their `name()` methods.

use clap::ValueEnum;
use entrynav::observability::Method;
use entrynav_optimizer::{OrbiterObjective, SelectionCriterion};

/// `--objective` of `optimize orbiters` (names of [`OrbiterObjective::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum OrbiterObjectiveArg {
    /// The integral of det(N3) (eq. 57), three orbiters.
    #[value(name = "det-n3")]
    DetN3,
    /// The integral of ln det of the FIM.
    #[value(name = "logdet")]
    Logdet,
    /// The final position PCRLB of Monte Carlo run 0 (minimised; polished from the geometric
    /// optimum).
    #[value(name = "pcrlb")]
    Pcrlb,
    /// The time-averaged nominal position bound (minimised, full global search).
    #[value(name = "pcrlb-avg")]
    PcrlbAvg,
    /// The final nominal position bound (minimised, full global search).
    #[value(name = "pcrlb-final")]
    PcrlbFinal,
    /// Both nominal position bounds relative to the scenario's own orbiters,
    /// 1/2 (avg/avg_in + final/final_in), minimised.
    #[value(name = "nav")]
    Nav,
    /// The filter's time-averaged position RMSE predicted by LinCov (the pcrlb-avg optimum
    /// polished on it).
    #[value(name = "lincov-avg")]
    LincovAvg,
    /// The filter's final position RMSE predicted by LinCov (the pcrlb-final optimum polished).
    #[value(name = "lincov-final")]
    LincovFinal,
    /// 1/2 (lincov-avg/input's + lincov-final/input's) (the nav optimum polished on it).
    #[value(name = "lincov-nav")]
    LincovNav,
}

impl OrbiterObjectiveArg {
    /// The geometric objective this names (`None` for the bound objectives: `pcrlb` polishes
    /// the default one, the nominal-bound ones use it for the search box only).
    pub(super) fn geometric(self) -> Option<OrbiterObjective> {
        match self {
            OrbiterObjectiveArg::DetN3 => Some(OrbiterObjective::DetN3),
            OrbiterObjectiveArg::Logdet => Some(OrbiterObjective::LogDet),
            _ => None,
        }
    }

    /// The nominal-bound figure this names, if any.
    pub(super) fn bound_figure(self) -> Option<entrynav_optimizer::BoundFigure> {
        use entrynav_optimizer::BoundFigure;
        match self {
            OrbiterObjectiveArg::PcrlbAvg | OrbiterObjectiveArg::LincovAvg => {
                Some(BoundFigure::Average)
            }
            OrbiterObjectiveArg::PcrlbFinal | OrbiterObjectiveArg::LincovFinal => {
                Some(BoundFigure::Final)
            }
            OrbiterObjectiveArg::Nav | OrbiterObjectiveArg::LincovNav => {
                Some(BoundFigure::Navigation)
            }
            _ => None,
        }
    }

    /// The LinCov figure the bound's optimum is polished on (lincov-*), if any.
    pub(super) fn lincov_figure(self) -> Option<entrynav_optimizer::LinCovFigure> {
        use entrynav_optimizer::LinCovFigure;
        match self {
            OrbiterObjectiveArg::LincovAvg => Some(LinCovFigure::Average),
            OrbiterObjectiveArg::LincovFinal => Some(LinCovFigure::Final),
            OrbiterObjectiveArg::LincovNav => Some(LinCovFigure::Navigation),
            _ => None,
        }
    }
}

/// `--objective` of `optimize ground` (names of [`GroundObjective::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum GroundObjectiveArg {
    /// min over time of delta (eq. 49).
    #[value(name = "min-delta")]
    MinDelta,
    /// The integral of ln det FIM.
    #[value(name = "logdet")]
    Logdet,
    /// min over time of lambda_min(FIM).
    #[value(name = "min-eig")]
    MinEig,
    /// The time-averaged position PCRLB along the nominal trajectory (minimised).
    #[value(name = "pcrlb-avg")]
    PcrlbAvg,
    /// The final position PCRLB along the nominal trajectory (minimised; alias `pcrlb`).
    #[value(name = "pcrlb-final", alias = "pcrlb")]
    PcrlbFinal,
    /// Both position bounds relative to the input design's, 1/2 (avg/avg_in + final/final_in),
    /// minimised (the default: it serves navigation over the whole entry and at its end).
    #[value(name = "nav")]
    Nav,
    /// The filter's time-averaged position RMSE predicted by LinCov (the pcrlb-avg optimum
    /// polished on it).
    #[value(name = "lincov-avg")]
    LincovAvg,
    /// The filter's final position RMSE predicted by LinCov (the pcrlb-final optimum polished).
    #[value(name = "lincov-final")]
    LincovFinal,
    /// 1/2 (lincov-avg/input's + lincov-final/input's) (the nav optimum polished on it).
    #[value(name = "lincov-nav")]
    LincovNav,
}

/// `--method` (names of [`Method::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum MethodArg {
    /// Exact Lie derivatives.
    #[value(name = "lie")]
    Lie,
    /// Quadratic approximation of the Lie derivatives.
    #[value(name = "quadratic")]
    Quadratic,
    /// Linearised system.
    #[value(name = "linear")]
    Linear,
}

impl From<MethodArg> for Method {
    fn from(a: MethodArg) -> Method {
        match a {
            MethodArg::Lie => Method::Lie,
            MethodArg::Quadratic => Method::Quadratic,
            MethodArg::Linear => Method::Linear,
        }
    }
}

/// `--criterion` of `optimize select` (names of [`SelectionCriterion::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum CriterionArg {
    /// D-optimal: ln det.
    #[value(name = "logdet")]
    Logdet,
    /// E-optimal: lambda_min.
    #[value(name = "min-eig")]
    MinEig,
}

impl From<CriterionArg> for SelectionCriterion {
    fn from(a: CriterionArg) -> SelectionCriterion {
        match a {
            CriterionArg::Logdet => SelectionCriterion::LogDet,
            CriterionArg::MinEig => SelectionCriterion::MinEig,
        }
    }
}

/// `--objective` of `optimize select` (the nominal-bound objectives; without it, `--criterion`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum SelectObjectiveArg {
    /// Both nominal position bounds relative to the input design.
    #[value(name = "nav")]
    Nav,
    /// The time-averaged nominal position bound.
    #[value(name = "pcrlb-avg")]
    PcrlbAvg,
    /// The final nominal position bound.
    #[value(name = "pcrlb-final")]
    PcrlbFinal,
    /// nav's selection, then exchanges on the filter's LinCov (both figures relative to the
    /// input's).
    #[value(name = "lincov-nav")]
    LincovNav,
    /// pcrlb-avg's selection, then exchanges on the filter's time-averaged LinCov RMSE.
    #[value(name = "lincov-avg")]
    LincovAvg,
    /// pcrlb-final's selection, then exchanges on the filter's final LinCov RMSE.
    #[value(name = "lincov-final")]
    LincovFinal,
}

impl SelectObjectiveArg {
    /// The ground objective it names.
    pub(super) fn ground(self) -> entrynav_optimizer::GroundObjective {
        use entrynav_optimizer::GroundObjective;
        match self {
            SelectObjectiveArg::Nav | SelectObjectiveArg::LincovNav => GroundObjective::Navigation,
            SelectObjectiveArg::PcrlbAvg | SelectObjectiveArg::LincovAvg => {
                GroundObjective::PcrlbAvg
            }
            SelectObjectiveArg::PcrlbFinal | SelectObjectiveArg::LincovFinal => {
                GroundObjective::PcrlbFinal
            }
        }
    }

    /// The LinCov figure the exchanges use (lincov-*), if any.
    pub(super) fn lincov(self) -> Option<entrynav_optimizer::LinCovFigure> {
        use entrynav_optimizer::LinCovFigure;
        match self {
            SelectObjectiveArg::LincovNav => Some(LinCovFigure::Navigation),
            SelectObjectiveArg::LincovAvg => Some(LinCovFigure::Average),
            SelectObjectiveArg::LincovFinal => Some(LinCovFigure::Final),
            _ => None,
        }
    }

    /// Its name.
    pub(super) fn name(self) -> &'static str {
        self.lincov()
            .map_or_else(|| self.ground().name(), |f| f.name())
    }
}
