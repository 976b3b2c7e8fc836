//! The simulation engine: the one place where the truth, the sensors and a navigation filter
//! advance. Every consumer drives it — the Monte Carlo trade, `simulate`, the observability
//! analysis points, seed 001's training trajectories and the three FMUs — so a filter feature or
//! a sensor rule is written once.
//!
//! # The engine's step
//!
//! 1. **Truth** ([`TruthPropagator`]): one fixed-step RK4 step at `timing.truth_step_s` with the
//!    commanded bank; stop on the ground, below `timing.stop_speed_mps`, or at the duration.
//! 2. **Sensors** ([`TruthSensors`]): if a channel of period P is due (t = P, 2P, …), one noise
//!    value per due channel is drawn in channel order *whether or not the sample is available*,
//!    and a radio sample is available when its beacon is commanded available, not in an outage
//!    and (unless visibility is ignored) above the horizon. The result is a
//!    [`MeasurementEpoch`](crate::sensors::MeasurementEpoch) with the truth sample at its time.
//! 3. **Navigation** ([`Navigator`]): the filter, built from the scenario's
//!    [`Onboard`](crate::estimation::Onboard) view only, predicts to the epoch with the onboard
//!    models at the commanded bank and updates with the available channels; a numerical failure
//!    freezes its estimate ([`NavStatus::Failed`]).
//! 4. **Judgement** ([`Judgement`], [`judge`]): the estimate beside the truth (error,
//!    NEES, position/velocity and deployment errors, density errors). Only the engine holds both.
//!
//! [`TruthSensors`] and [`Navigator`] advance by communication steps of any length (the FMI
//! co-simulation interface); [`EntryCoSim`] combines them. A batch run is a loop over the same
//! steps: [`simulate_truth`] runs the truth to its end, then one [`Navigator`] per
//! filter flies the recorded epochs ([`Navigator::fly`], the engine's one loop: process, stop on
//! failure, judge, hand to an [`Observer`]). The Monte Carlo, the replay of a run, the density
//! evaluation and `tune` are observers; none writes its own loop.
//!
//! # Randomness
//!
//! The truth generator is `ChaCha8Rng::seed_from_u64(seed)`, used for the dispersions (when
//! `dispersed`) and then for the measurement noise, as `entrynav simulate --seed` does; the filter
//! start (when `filter.sample_initial_from_p0`) is drawn from the same seed's ChaCha stream 1, so
//! it does not depend on how long the truth runs. With constant inputs (bank angle of the
//! scenario, every beacon available) the engine therefore reproduces `simulate_truth` bit for bit,
//! and with a fixed filter start it reproduces Monte Carlo run `r` of `trade --seed S` for
//! `seed = run_seed(S, r)`, `dispersed = true`.
//!
//! # Bank angle
//!
//! The commanded bank is known onboard, so the filter's onboard dynamics and measurement models
//! use it too (`NavFilter::set_bank_angle`). [`EntryCoSim::do_step`] gives the step's bank to
//! both the truth and the filter, and [`Navigator::do_step`] takes it as an input: the bank given
//! with the step from `t` is flown from `t` on, by the truth and by the filter. The filter starts
//! with the scenario's bank (`truth.bank_deg`). A [`Navigator`] holds the commands given since its
//! last epoch and, when it predicts to the next epoch, predicts piecewise: to the start of each
//! command with the bank before it, then on with that command. The filter's bank history is
//! therefore the truth's whatever the communication step (a guidance loop stepping 0.05 s against
//! 1 Hz sensors included); a command given at an epoch's own time is flown after that epoch's
//! update, as the truth flew the step ending there with the bank before. With a constant bank
//! nothing is held and the filter predicts in one piece from epoch to epoch, as it always did.
//! A [`Navigator`] stepped on its own ([`Navigator::do_step`], the navigation FMUs) is fed the
//! epochs of a separate [`TruthSensors`] one step late, with the bank the truth flew over that
//! previous step (its `truth_bank_angle`): that bank is flown from the previous step's start,
//! so the split system equals the combined one one step late, whatever the step.
//!
//! Everything is deterministic: the same parameters and the same sequence of `do_step` calls give
//! bit-identical outputs, which is what the FMU's state serialisation (a replay log) relies on.
//!
//! # Files
//!
//! `truth.rs` the truth's RK4 step ([`TruthPropagator`]); `truth_sensors.rs` the sensors'
//! schedule, noise and availability ([`TruthSensors`]); `navigator.rs` and `filter.rs` the filter
//! behind one object-safe interface ([`Navigator`]); `entry.rs` both together ([`EntryCoSim`]);
//! `flight.rs` the loop over a recorded run ([`Navigator::fly`], [`Observer`]); [`record`] a whole
//! truth run recorded and Monte Carlo run k's truth and filter start ([`record_run`], seeded by
//! [`run_seed`]); [`judge`] the estimate beside the truth; [`start`] a run's initial estimate;
//! `error.rs` [`EngineError`]; `step_check.rs` the communication-step checks.

mod entry;
mod error;
mod filter;
mod flight;
pub mod judge;
mod navigator;
pub mod record;
mod run_seed;
pub mod start;
mod step_check;
mod truth;
mod truth_sensors;

pub use entry::EntryCoSim;
pub use error::EngineError;
pub use filter::{BuildError, FilterFailure, Judgement, NavEstimate};
pub use flight::{FlightEnd, Observer};
pub use navigator::{NavStatus, Navigator};
pub use record::{
    Peak, Peaks, RecordedRun, RunError, TruthRun, channel_names, is_radio, record_run,
    record_run_following, simulate_truth, simulate_truth_with_peaks,
};
pub use run_seed::run_seed;
pub use start::initial_estimate;
pub use step_check::same_time;
pub use truth::{SimError, StopReason, TruthPropagator, TruthSample, TruthStep, truth_sample};
pub use truth_sensors::{StepReport, TruthOutputs, TruthSensors};

#[cfg(test)]
mod tests;
