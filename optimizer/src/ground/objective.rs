//! [`GroundObjective`]: what the ground search optimises, its name and units.

use entrynav::observability::Method;

/// What the ground search maximises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroundObjective {
    /// `min_t δ(t)` (seed 002 eq. 49) with this observability method; `scaled` picks the scaled δ
    /// of [`Scaling`](entrynav::observability::Scaling) instead of the raw-SI one.
    MinDelta {
        /// How the observability matrix is computed.
        method: Method,
        /// Use the scaled δ (else raw SI, the paper's convention).
        scaled: bool,
    },
    /// `∫ log det F dt` of the range FIM [s · ln m⁻⁶].
    LogDet,
    /// `min_t λ_min(F(t))` [m⁻²].
    MinEig,
    /// Time-averaged position PCRLB along the nominal trajectory \[m\] (minimised).
    PcrlbAvg,
    /// Final position PCRLB along the nominal trajectory \[m\] (minimised).
    PcrlbFinal,
    /// `½ (avg/avg_input + final/final_input)` of the nominal position PCRLB (minimised).
    Navigation,
}

impl GroundObjective {
    /// Name used on the command line and in reports: `min-delta`, `logdet`, `min-eig`.
    pub fn name(self) -> &'static str {
        match self {
            GroundObjective::MinDelta { .. } => "min-delta",
            GroundObjective::LogDet => "logdet",
            GroundObjective::MinEig => "min-eig",
            GroundObjective::PcrlbAvg => "pcrlb-avg",
            GroundObjective::PcrlbFinal => "pcrlb-final",
            GroundObjective::Navigation => "nav",
        }
    }

    /// Whether the objective is the nominal position bound (needs
    /// [`GroundProblem::with_reference`](super::GroundProblem::with_reference) for [`GroundObjective::Navigation`]).
    pub fn is_bound(self) -> bool {
        matches!(
            self,
            GroundObjective::PcrlbAvg | GroundObjective::PcrlbFinal | GroundObjective::Navigation
        )
    }

    /// Unit and meaning of the objective value.
    pub fn units(self) -> String {
        match self {
            GroundObjective::MinDelta { method, scaled } => format!(
                "min over the trajectory of delta = sigma_min/sigma_max of the {} observability \
                 matrix, {} (dimensionless)",
                method.name(),
                if scaled {
                    "scaled (states in characteristic units, rows per noise sigma)"
                } else {
                    "raw SI (states in m, rad, m/s; outputs in m; the papers' convention)"
                }
            ),
            GroundObjective::LogDet => {
                "integral over time of ln det F, F = sum sigma^-2 n n^T the \
                 range FIM of the vehicle position [m^-2]; value in s * ln(m^-6)"
                    .into()
            }
            GroundObjective::MinEig => {
                "min over the trajectory of lambda_min(F), F the range FIM [m^-2]".into()
            }
            GroundObjective::PcrlbAvg => {
                "time average of the position PCRLB along the nominal trajectory (dynamics, \
                 prior, every sensor and the ranges to the sites) [m], minimised"
                    .into()
            }
            GroundObjective::PcrlbFinal => {
                "position PCRLB at the last epoch of the nominal trajectory [m], minimised".into()
            }
            GroundObjective::Navigation => {
                "1/2 (pcrlb-avg / input's pcrlb-avg + pcrlb-final / input's pcrlb-final): the \
                 nominal position bound relative to the input design (1 = as good; lower is \
                 better), minimised"
                    .into()
            }
        }
    }
}
