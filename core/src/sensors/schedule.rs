//! What a scenario's sensors produce: the channels with their schedules and noise, and the
//! measurement epoch (one value slot per channel) that the truth emits and a filter consumes.

use super::channels::Channel;

/// Noise of one channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Noise {
    /// Fixed 1σ in the channel's unit.
    Absolute(f64),
    /// 1σ as a fraction of the true reading.
    Relative(f64),
}

impl Noise {
    /// 1σ for a true reading `value`.
    pub fn sigma(&self, value: f64) -> f64 {
        match *self {
            Noise::Absolute(s) => s,
            Noise::Relative(f) => f * value.abs(),
        }
    }

    /// The same noise with its 1σ times `factor`.
    pub fn scaled(&self, factor: f64) -> Noise {
        match *self {
            Noise::Absolute(s) => Noise::Absolute(s * factor),
            Noise::Relative(f) => Noise::Relative(f * factor),
        }
    }
}

/// One measurement channel with its schedule and noise.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelSpec {
    /// What is measured.
    pub channel: Channel,
    /// Column name (SI unit suffix).
    pub name: String,
    /// Sample period \[s\].
    pub period_s: f64,
    /// Noise of the simulated sensor.
    pub noise: Noise,
    /// Noise the filters assume (differs from `noise` where the scenario says so).
    pub filter_noise: Noise,
    /// Constant bias added to the truth (accelerometers only).
    pub bias: f64,
}

/// Measurements taken at one instant: one slot per scenario channel.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasurementEpoch {
    /// Time \[s\].
    pub t: f64,
    /// `Some(value)` when the channel was sampled and available; `None` when it was not due,
    /// its beacon was in an outage, or (unless visibility is ignored) below the horizon.
    pub values: Vec<Option<f64>>,
}
