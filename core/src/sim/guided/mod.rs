//! Entry guidance flown against the truth: with perfect navigation, with a navigation filter in
//! the loop, and the Monte Carlo of delivery at deployment (issue 28). It lives in `sim` because
//! it reads the truth (the deployment trigger, the references), which the guidance layer may not.
//!
//! * [`guided_flight`] — perfect navigation and the unguided constant bank, the references, on
//!   the engine's [`TruthPropagator`](crate::sim::engine::TruthPropagator);
//! * [`guided_loop`] — [`GuidedLoop`]: a filter in the guidance loop, one truth step at a time
//!   (the guided FMU steps the same struct); [`loop_inputs`] — the accelerometer triad it reads
//!   (the sensed drag) and its guidance period;
//! * [`guided_run`] — a whole run flown with [`GuidedLoop`] ([`fly_with_filter`]);
//! * [`deployment`] — where a flight deployed ([`Delivery`]); [`guided_run_error`] — why it did
//!   not ([`GuidedRunError`]);
//! * [`delivery`] — the delivery Monte Carlo (`entrynav guidance deliver`), and
//!   [`delivery_shard`] — its sharded form (`trade --shard`, `trade merge`).

pub mod delivery;
pub mod delivery_shard;
pub mod deployment;
pub mod guided_flight;
pub mod guided_loop;
pub mod guided_run;
pub mod guided_run_error;
pub mod loop_inputs;

pub use delivery::{DeliveryReport, DeliveryRow, run_delivery};
pub use delivery_shard::{DeliveryShard, deliver_runs, merge_delivery_shards};
pub use deployment::{Delivery, DeployNavError, within_rate_limit};
pub use guided_flight::{GuidedFlight, GuidedFlightSettings, fly_perfect_navigation};
pub use guided_loop::{GuidedLoop, GuidedStep};
pub use guided_run::{fly_with_filter, fly_with_filter_recorded};
pub use guided_run_error::GuidedRunError;
pub use loop_inputs::{accel_slots, guidance_every};
