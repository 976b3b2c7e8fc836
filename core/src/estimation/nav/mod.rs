//! Navigation filters: estimators wired to a scenario's dynamics and sensors.
//!
//! Every filter implements [`NavFilter`]: predict to the next measurement epoch, update with the
//! channels available there, and expose its estimate. A filter is built from an
//! [`Onboard`](crate::estimation::Onboard) value and a [`FilterStart`] only, so it cannot see the
//! truth; the simulation engine (`sim::engine`) drives it and judges it against the truth.

pub mod bank;
pub mod build;
pub mod ekf_nav;
mod ensemble;
mod epoch_linearization;
pub mod fit;
mod fused_estimate;
pub mod fusion;
mod fusion_exact;
mod fusion_pass;
pub mod fusion_setup;
pub mod gate;
pub mod gate_report;
pub mod kind;
mod local_update;
pub mod nav_filter;
mod prior_information;
pub mod start;
pub mod step_info;
pub mod ukf_ac;
pub mod ukf_cm;
mod ukf_common;
pub mod ukf_nav;
pub mod uskf_nn;

pub use bank::BankNav;
pub use build::build_filter;
pub use ekf_nav::EkfNav;
pub use fusion::FusionNav;
pub(crate) use fusion_exact::fuse_exact_with_gains;
pub use gate::GatedNav;
pub use gate_report::GateReport;
pub use kind::{FilterKind, NavError};
pub(crate) use local_update::local_update;
pub use nav_filter::{FilterCore, NavFilter, NavFilterClone};
pub use start::FilterStart;
pub use step_info::StepInfo;
pub use ukf_nav::UkfNav;
