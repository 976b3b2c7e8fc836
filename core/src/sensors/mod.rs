//! Onboard sensors: IMU specific force, air data (dynamic pressure, convective heating) and
//! two-way radio (range, range-rate) to beacons.
//!
//! Every measurement function is generic over [`crate::math::Real`] so measurement Jacobians
//! `∂h/∂x` come from forward-mode AD through the same code the truth simulator uses.

pub mod airdata;
pub mod channels;
pub mod config;
pub mod faults;
pub mod imu;
pub mod radio;
pub mod schedule;

pub use airdata::{dynamic_pressure, sutton_graves_heating};
pub use channels::{Channel, MeasurementModel};
pub use config::{SensorError, SensorsConfig};
pub use faults::{Fault, FaultConfig};
pub use imu::{ImuFrame, body_from_velocity};
pub use radio::{range, range_rate};
pub use schedule::{ChannelSpec, MeasurementEpoch, Noise};
