//! Entry guidance: the onboard layer that turns a navigation estimate into a bank command.
//!
//! Guidance sits beside `estimation`: it sees the onboard model (the filter's [`EntryModel`]:
//! planet, atmosphere, vehicle constants) and a navigation solution ([`NavState`]), never the
//! truth — it may not import `scenario` or `sim` (checked by `core/tests/architecture.rs`). Two
//! algorithms:
//!
//! * [`apollo::ApolloGuidance`]: Apollo final-phase entry guidance as adapted for MSL (Mendeck &
//!   Craig, AIAA 2011-6639), on a reference trajectory with adjoint gains ([`mod@reference`]);
//! * [`fnpeg::Fnpeg`]: the fully numerical predictor–corrector of Lu (J. Guid. Control Dyn.
//!   37(4), 2014), a bank profile linear in energy corrected every cycle.
//!
//! Either may be wrapped in the altitude safeguard ([`safeguard`], `min_deploy_altitude_m`),
//! which caps the bank magnitude when the predicted deployment altitude falls below a floor.
//! Both share the lateral logic ([`lateral`]: crossrange deadband, bank reversals). The bank the
//! vehicle flies is the command through the rate and acceleration limits ([`limits`]).
//!
//! [`EntryModel`]: crate::dynamics::EntryModel

pub mod algorithm;
pub mod apollo;
pub mod config;
pub mod deploy;
pub mod error;
pub mod fnpeg;
pub mod lateral;
pub mod limits;
pub mod longitudinal;
pub mod nav_state;
pub mod onboard_trigger;
pub mod reference;
pub mod safeguard;
pub mod target;

pub use algorithm::Guidance;
pub use config::{
    BuiltGuidance, GuidanceAlgorithm, GuidanceAtmosphere, GuidanceConfig, TargetConfig,
    build_guidance,
};
pub use deploy::{BoxViolations, DeployBox, OnboardDeploy, RangeTrigger, along_track_range_to_go};
pub use error::GuidanceError;
pub use limits::{BankActuator, BankLimits};
pub use longitudinal::Trigger;
pub use nav_state::NavState;
pub use onboard_trigger::onboard_trigger;
pub use target::{Target, bearing, central_angle, destination, range_crossrange};
