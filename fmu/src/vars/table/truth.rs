//! The outputs of the truth: its state and loads, the sensed acceleration, the beacons' ranges
//! and visibility, why it stopped and the bank it flew.

use super::builder::{Builder, SPH};
use crate::vars::enums::TRUTH_STOP;
use crate::vars::slot::Key;
use crate::vars::var::Type;

/// The truth outputs: the spherical state, atmosphere and loads, sensed acceleration, beacons.
pub(super) fn truth_outputs(b: &mut Builder, n_beacons: usize) {
    truth_state(b);
    truth_beacons_and_stop(b, n_beacons);
}

/// The truth's spherical state, altitude, density, dynamic pressure, heating, aerodynamic and
/// sensed acceleration.
fn truth_state(b: &mut Builder) {
    use Type::*;
    for (k, (n, u, d)) in SPH.iter().enumerate() {
        b.out(
            format!("truth_{n}"),
            Real,
            Some(u),
            format!("True {d} (planet-relative spherical)"),
            Key::TruthSph(k),
        );
    }
    b.out(
        "truth_altitude",
        Real,
        Some("m"),
        "True altitude",
        Key::TruthAltitude,
    );
    b.out(
        "truth_density",
        Real,
        Some("kg/m3"),
        "True atmospheric density",
        Key::TruthDensity,
    );
    b.out(
        "truth_dynamic_pressure",
        Real,
        Some("Pa"),
        "True dynamic pressure",
        Key::TruthDynamicPressure,
    );
    b.out(
        "truth_heating",
        Real,
        Some("W/m2"),
        "True convective heating rate (Sutton-Graves)",
        Key::TruthHeating,
    );
    b.out(
        "truth_aero_accel",
        Real,
        Some("m/s2"),
        "Magnitude of the aerodynamic acceleration",
        Key::TruthAeroAccel,
    );
    for k in 0..3 {
        b.out(
            format!("truth_sensed_accel_{}", ["x", "y", "z"][k]),
            Real,
            Some("m/s2"),
            format!(
                "Noiseless sensed acceleration (specific force), IMU axis {}",
                ["x", "y", "z"][k]
            ),
            Key::TruthSensedAccel(k),
        );
    }
}

/// The beacons' ranges and visibility, why the truth stopped, the bank it flew, the beacon count.
fn truth_beacons_and_stop(b: &mut Builder, n_beacons: usize) {
    use Type::*;
    for i in 0..n_beacons {
        b.out(
            format!("beacon_range_{}", i + 1),
            Real,
            Some("m"),
            format!("Geometric range to beacon {}", i + 1),
            Key::BeaconRange(i),
        );
        b.out(
            format!("beacon_visible_{}", i + 1),
            Boolean,
            None,
            format!("Beacon {} is above the horizon", i + 1),
            Key::BeaconVisible(i),
        );
    }
    b.enumeration(
        "truth_stop",
        &TRUTH_STOP,
        "Why the truth stopped: running, duration (reached), stop_speed (reached), ground (reached)",
        Key::TruthStop,
    );
    b.out(
        "truth_stop_code",
        Integer,
        None,
        "truth_stop as an Integer (0 running, 1 duration, 2 stop_speed, 3 ground), for importers without FMI 2.0 Enumeration support (libcosim ignores Enumeration variables)",
        Key::TruthStopCode,
    );
    b.out(
        "truth_bank_angle",
        Real,
        Some("rad"),
        "Bank angle the truth flew over its last step (0 before the first step): connected to MarsEntryNavFilter's bank_angle, it reaches the filter one step late with the measurements of that step",
        Key::TruthBankFlown,
    );
    b.out(
        "n_beacons",
        Integer,
        None,
        "Number of beacons of the scenario",
        Key::NBeacons,
    );
}
