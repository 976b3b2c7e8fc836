//! The variables of `MarsEntryGuidance` (see [`super`]) and the guided scenario file every
//! generic FMU ships in `resources/`.
//!
//! Inputs carry the names of the outputs they connect to, so a system connects them 1:1: the
//! navigation FMUs' `est_x_1..12` (the kinematic states, then the augmented states),
//! `est_sigma_1..6`, `nav_time`, `nav_status_code`, and the truth FMU's accelerometer triad
//! `meas_accel_{x,y,z}` with its `_valid` flags (the sensed drag).

use super::builder::{Builder, SPH};
use super::params::allow_external_files;
use crate::vars::defaults::GUIDED_SCENARIO_FILE;
use crate::vars::enums::GUIDANCE_STATUS;
use crate::vars::sizes::MAX_STATES;
use crate::vars::slot::{Key, Slot};
use crate::vars::var::{Causality, Type, Value};
use entrynav::scenario::{Scenario, ScenarioConfig};

/// The text of [`GUIDED_SCENARIO_FILE`]: the built-in `msl-guided`.
pub fn guided_scenario_toml() -> String {
    entrynav::scenario::builtin_toml("msl-guided")
        .unwrap_or_default()
        .to_string()
}

/// The scenario of [`GUIDED_SCENARIO_FILE`] (it refers to no other file).
pub fn guided_scenario() -> Result<Scenario, entrynav::scenario::ScenarioError> {
    let cfg = ScenarioConfig::from_toml_str(&guided_scenario_toml(), GUIDED_SCENARIO_FILE)?;
    Scenario::build(cfg, &entrynav::files::no_files)
}

/// The start values of `est_x_1..`[`MAX_STATES`]: the default scenario's onboard nominal entry
/// (its kinematic states, then its filter's augmented states, 0 past its state dimension) (`msl-guided`'s filter start, `Onboard::initial_estimate`, in the filter
/// model's coordinates), the state [`Scenario::build_guidance`] builds the guidance from and the
/// navigation FMUs' `est_x_*` before their first measurement epoch. With these start values
/// (and `nav_time` = 0, `nav_status_code` = 0) the FMU simulates alone: every cycle flies the
/// entry state, a valid operating point, instead of refusing the radius 0 of all-zero inputs.
///
/// The guided scenario builds (tested in `vars::spec`), so the all-zero fallback is never taken.
/// Computed on each call (a built-in's parse, well under a millisecond), not cached: the library
/// keeps no global state.
pub fn entry_estimate() -> [f64; MAX_STATES] {
    let mut x = [0.0; MAX_STATES];
    if let Ok(s) = guided_scenario() {
        for (xi, e) in x.iter_mut().zip(&s.onboard.initial_estimate) {
            *xi = *e;
        }
    }
    x
}

/// The `scenario` parameter of the guidance FMU and of the guided FMU `MarsEntryNavGuided`: a
/// scenario with a `[guidance]` section, by default [`GUIDED_SCENARIO_FILE`].
pub(super) fn guided_scenario_param(b: &mut Builder) {
    b.add(
        "scenario",
        Type::String,
        Causality::Parameter,
        None,
        Some(Value::String(GUIDED_SCENARIO_FILE.into())),
        format!(
            "Scenario with a [guidance] section (refused without one): a TOML file in the FMU's resources folder (default {GUIDED_SCENARIO_FILE}, the built-in msl-guided: msl-airdata with Apollo guidance) or a built-in name ({}; msl-guided and four-beacon-fusion-guided have [guidance]); a file elsewhere only with allow_external_files = true",
            entrynav::scenario::BUILTIN_NAMES.join(", ")
        ),
        Key::Scenario,
    );
}

/// The guidance FMU's variables after its `scenario` parameter.
pub(super) fn guidance_vars(b: &mut Builder) {
    allow_external_files(b);
    guidance_inputs(b);
    guidance_outputs(b);
}

/// The guidance FMU's inputs: the navigation estimate and the accelerometer triad, named as the
/// outputs they connect to.
fn guidance_inputs(b: &mut Builder) {
    use Causality::*;
    use Type::*;
    b.add(
        "nav_time",
        Real,
        Input,
        Some("s"),
        Some(Value::Real(0.0)),
        "Epoch of the navigation estimate (connect the navigation FMU's nav_time); starts at 0, the epoch of the entry state est_x_1..6 start at",
        Key::NavTime,
    );
    b.add(
        "nav_status_code",
        Integer,
        Input,
        None,
        Some(Value::Integer(0)),
        "Navigation filter status, 0 initial, 1 running, 2 failed (connect nav_status_code); guidance refuses to fly a failed filter's estimate",
        Key::NavStatusCode,
    );
    for (i, start) in entry_estimate().into_iter().enumerate() {
        let what = match SPH.get(i) {
            Some((n, _, _)) => format!(
                "kinematic filter state {} (connect est_x_{}): spherical {n} when the scenario's filter model is spherical, else inertial Cartesian x y z vx vy vz",
                i + 1,
                i + 1
            ),
            None => format!(
                "filter state {} (connect est_x_{}), an augmented state: the range trigger reads the dynamic pressure with the filter's C_D S/m when the scenario's filter estimates it (cd-s-over-m in [filter] augment), else the onboard constant; other augmented states are not used",
                i + 1,
                i + 1
            ),
        };
        b.add(
            format!("est_x_{}", i + 1),
            Real,
            Input,
            None,
            Some(Value::Real(start)),
            format!(
                "Navigation estimate, {what}; starts at the default scenario's nominal entry (msl-guided's filter start, 0 past its state dimension)"
            ),
            Key::EstX(i),
        );
    }
    for i in 0..6 {
        b.add(
            format!("est_sigma_{}", i + 1),
            Real,
            Input,
            None,
            Some(Value::Real(0.0)),
            format!(
                "1-sigma of kinematic filter state {} (connect est_sigma_{}); must be >= 0; not used by the guidance laws",
                i + 1,
                i + 1
            ),
            Key::EstSigma(i),
        );
    }
    for k in 0..3u8 {
        let s = Slot::Accel(k);
        b.add(
            s.name(),
            Real,
            Input,
            Some(s.unit()),
            Some(Value::Real(0.0)),
            format!(
                "Measured {} of the last measurement epoch (connect the truth FMU's {}): the sensed drag",
                s.what(),
                s.name()
            ),
            Key::Meas(s),
        );
        b.add(
            format!("{}_valid", s.name()),
            Boolean,
            Input,
            None,
            Some(Value::Boolean(false)),
            format!(
                "{} is valid (the sensed drag is updated only when all three axes are)",
                s.name()
            ),
            Key::MeasValid(s),
        );
    }
}

/// The guidance FMU's outputs: the bank command through the actuator and the guidance state.
fn guidance_outputs(b: &mut Builder) {
    use Type::*;
    b.out(
        "bank_command",
        Real,
        Some("rad"),
        "Bank angle to fly, after the rate and acceleration limits (connect to the truth FMU's bank_angle): the actuator's bank at this communication point",
        Key::GuidanceBank,
    );
    b.out(
        "bank_rate",
        Real,
        Some("rad/s"),
        "Bank rate of the actuator at this communication point",
        Key::GuidanceBankRate,
    );
    b.out(
        "guidance_command",
        Real,
        Some("rad"),
        "Command of the latest guidance cycle, before the rate and acceleration limits (the reference bank before the first cycle)",
        Key::GuidanceCommand,
    );
    b.out(
        "guidance_time",
        Real,
        Some("s"),
        "Time of the latest guidance cycle (0 before the first)",
        Key::GuidanceTime,
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
        "Sensed drag of the last valid accelerometer triad (read at the start of each step), rotated to the wind frame; 0 before the first",
        Key::SensedDrag,
    );
    b.out(
        "range_to_go",
        Real,
        Some("m"),
        "Great-circle range from the navigated position to the target at the latest cycle",
        Key::RangeToGo,
    );
    b.out(
        "crossrange",
        Real,
        Some("m"),
        "Crossrange of the target from the navigated velocity's great circle at the latest cycle (positive: to the right)",
        Key::Crossrange,
    );
    b.out(
        "deploy_trigger",
        Real,
        None,
        "Deployment trigger function on the navigation estimate at the latest cycle (speed minus trigger speed [m/s], or dynamic pressure minus trigger pressure [Pa] in the onboard atmosphere): positive before deployment",
        Key::DeployTrigger,
    );
    b.out(
        "deployed",
        Boolean,
        None,
        "The trigger was reached on the navigation estimate (after having been positive): guidance stops cycling and the actuator holds the last command",
        Key::Deployed,
    );
    b.enumeration(
        "guidance_status",
        &GUIDANCE_STATUS,
        "Guidance state: waiting (no cycle yet, the reference bank), flying (cycles fly the estimate), deployed (the trigger was reached on the estimate; the actuator holds the last command)",
        Key::GuidanceStatus,
    );
    b.out(
        "guidance_status_code",
        Integer,
        None,
        "guidance_status as an Integer (0 waiting, 1 flying, 2 deployed), for importers without FMI 2.0 Enumeration support (libcosim ignores Enumeration variables)",
        Key::GuidanceStatusCode,
    );
}
