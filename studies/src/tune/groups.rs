//! The factors `entrynav tune` searches ([`ParameterGroup`]): groups of the process-noise
//! diagonal, the load-scaled model's fractions and density error, the assumed noise per channel
//! kind; and the range of each factor a scenario accepts.

use crate::tune::search::THETA_BOUND;
use entrynav::estimation::{MAX_DENSITY_SIGMA, ProcessNoiseModel};
use entrynav::scenario::config::NoiseInflation;
use entrynav::scenario::config::{MAX_AERO_FRACTION, MAX_NOISE_INFLATION};
use entrynav::sensors::Channel;

/// One tuned factor.
#[derive(Debug, Clone, PartialEq)]
pub enum ParameterGroup {
    /// Process-noise entries (state indices) scaled together.
    Process {
        /// Name in reports, e.g. `q[v_mps]`.
        name: String,
        /// State indices.
        states: Vec<usize>,
    },
    /// Fractions of the aerodynamic-load-scaled process noise (`[filter.process_noise]`,
    /// `model = "aero-scaled"`) scaled together: the drag axis, or the side and lift axes.
    Aero {
        /// Name in reports, e.g. `aero[drag]`.
        name: String,
        /// Wind axes (0 drag, 1 side, 2 lift plane).
        axes: Vec<usize>,
    },
    /// The 1σ density error that drives an estimated density state (`density_sigma` of the
    /// aero-scaled model), `aero[density]`.
    Density,
    /// The assumed noise of every channel of one kind (e.g. all ranges).
    Noise {
        /// Name in reports, e.g. `r[range]`.
        name: String,
        /// A representative channel of the kind.
        kind: Channel,
    },
}

impl ParameterGroup {
    /// Its name in reports.
    pub fn name(&self) -> &str {
        match self {
            ParameterGroup::Process { name, .. }
            | ParameterGroup::Aero { name, .. }
            | ParameterGroup::Noise { name, .. } => name,
            ParameterGroup::Density => "aero[density]",
        }
    }
}

impl ParameterGroup {
    /// The range of θ (log₁₀ of the factor) the search may use for this group: ±[`THETA_BOUND`],
    /// narrowed so that a scaled value stays within what a scenario accepts (`model`: the
    /// filter's process-noise model now; `current`: its noise factors now).
    pub fn bounds(&self, model: &ProcessNoiseModel, current: &NoiseInflation) -> (f64, f64) {
        let room = |limit: f64, now: f64| (-THETA_BOUND, (limit / now).log10().min(THETA_BOUND));
        match (self, model) {
            (ParameterGroup::Aero { axes, .. }, ProcessNoiseModel::AeroScaled(a)) => {
                let largest = axes.iter().map(|&k| a.fraction[k]).fold(0.0, f64::max);
                room(MAX_AERO_FRACTION, largest)
            }
            (ParameterGroup::Density, ProcessNoiseModel::AeroScaled(a)) => {
                room(MAX_DENSITY_SIGMA, a.density_sigma)
            }
            (ParameterGroup::Noise { kind, .. }, _) => {
                room(MAX_NOISE_INFLATION, current.factor(*kind))
            }
            _ => (-THETA_BOUND, THETA_BOUND),
        }
    }
}
