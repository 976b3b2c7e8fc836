//! The outputs the guided FMU `MarsEntryNavGuided` adds to the combined model's.

use super::builder::Builder;
use crate::vars::slot::Key;
use crate::vars::var::Type;

/// What `MarsEntryNavGuided` adds to the combined model's outputs: its guidance and how the
/// guided flight ended. The bank it flew over the last step is the truth output
/// `truth_bank_angle`.
pub(super) fn guided_outputs(b: &mut Builder) {
    use Type::*;
    b.out(
        "guidance_command",
        Real,
        Some("rad"),
        "Command of the latest guidance cycle, computed from the filter's estimate, before the rate and acceleration limits (the reference bank before the first cycle)",
        Key::GuidanceCommand,
    );
    b.out(
        "bank_rate",
        Real,
        Some("rad/s"),
        "Bank rate of the actuator at this communication point",
        Key::GuidanceBankRate,
    );
    b.out(
        "guidance_cycles",
        Integer,
        None,
        "Guidance cycles run",
        Key::GuidanceCycles,
    );
    b.out(
        "sensed_drag",
        Real,
        Some("m/s2"),
        "Sensed drag of the last valid accelerometer triad, rotated to the wind frame, that the next guidance cycle is given (0 before the first)",
        Key::SensedDrag,
    );
    b.out(
        "guided_status",
        Integer,
        None,
        "The guided flight: 0 flying, 1 deployed (the trigger was reached on the truth; the delivery outputs are set), 2 ended without deployment (the truth stopped before the trigger, the filter or guidance failed: the log says which); after 1 or 2 the outputs hold and a step only advances time",
        Key::GuidedStatus,
    );
    b.out(
        "deployed",
        Boolean,
        None,
        "The deployment trigger was reached on the truth (guided_status = 1)",
        Key::Deployed,
    );
    b.out(
        "deploy_time",
        Real,
        Some("s"),
        "Deployment time, interpolated between the truth steps around the trigger (0 before deployment)",
        Key::DeployTime,
    );
    b.out(
        "deploy_altitude",
        Real,
        Some("m"),
        "Deployment altitude (0 before deployment)",
        Key::DeployAltitude,
    );
    b.out(
        "miss_distance",
        Real,
        Some("m"),
        "Surface distance from the deployment point to the guidance target (0 before deployment)",
        Key::MissDistance,
    );
    b.out(
        "miss_downrange",
        Real,
        Some("m"),
        "Along-track part of the miss, positive when the vehicle overflew the target (0 before deployment)",
        Key::MissDownrange,
    );
    b.out(
        "miss_crossrange",
        Real,
        Some("m"),
        "Cross-track part of the miss, positive when the target lies to the right (0 before deployment)",
        Key::MissCrossrange,
    );
}
