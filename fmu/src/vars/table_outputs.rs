//! The output variables of the truth, the filter and the judgement (see [`super::table`]).

use super::table::{Builder, SPH};
use super::*;

/// The truth outputs: the spherical state, atmosphere and loads, sensed acceleration, beacons.
pub(super) fn truth_outputs(b: &mut Builder, n_beacons: usize) {
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

/// The estimate outputs of a model with a filter.
pub(super) fn nav_outputs(b: &mut Builder, specific: Option<&Specific>) {
    use Type::*;
    b.out(
        "nav_time",
        Real,
        Some("s"),
        "Epoch of the estimate (the last measurement epoch processed; 0 before the first)",
        Key::NavTime,
    );
    b.enumeration(
        "nav_status",
        &NAV_STATUS,
        "Filter status: initial (no epoch yet), running, failed (estimate frozen, reason logged)",
        Key::NavStatus,
    );
    b.out(
        "nav_status_code",
        Integer,
        None,
        "nav_status as an Integer (0 initial, 1 running, 2 failed), for importers without FMI 2.0 Enumeration support (libcosim ignores Enumeration variables)",
        Key::NavStatusCode,
    );
    b.out(
        "n_states",
        Integer,
        None,
        "Filter state dimension N (slots past N read 0)",
        Key::NStates,
    );
    match specific {
        None => {
            for i in 0..MAX_STATES {
                b.out(
                    format!("est_x_{}", i + 1),
                    Real,
                    None,
                    format!("Estimate, filter state {} (filter-model coordinates: r lon lat v fpa heading or x y z vx vy vz, then augmented states)", i + 1),
                    Key::EstX(i),
                );
            }
            for i in 0..MAX_STATES {
                b.out(
                    format!("est_sigma_{}", i + 1),
                    Real,
                    None,
                    format!("1-sigma of filter state {}", i + 1),
                    Key::EstSigma(i),
                );
            }
        }
        Some(s) => {
            for (i, st) in s.states.iter().enumerate() {
                b.out(
                    format!("est.{}", st.name),
                    Real,
                    Some(st.unit),
                    format!(
                        "Estimate of the {} (filter state {})",
                        st.description,
                        i + 1
                    ),
                    Key::EstX(i),
                );
            }
            for (i, st) in s.states.iter().enumerate() {
                b.out(
                    format!("est_sigma.{}", st.name),
                    Real,
                    Some(st.unit),
                    format!("1-sigma of the {} estimate", st.description),
                    Key::EstSigma(i),
                );
            }
        }
    }
    for (k, (n, u, d)) in SPH.iter().enumerate() {
        b.out(
            format!("est_{n}"),
            Real,
            Some(u),
            format!("Estimated {d} (planet-relative spherical)"),
            Key::EstSph(k),
        );
    }
    b.out(
        "est_density",
        Real,
        Some("kg/m3"),
        "Filter's density estimate (0 when the filter does not estimate density)",
        Key::EstDensity,
    );
    b.out(
        "nis",
        Real,
        Some("1"),
        "Normalised innovation squared of the last update (0 while n_meas = 0: no measurement used yet)",
        Key::Nis,
    );
    b.out(
        "n_meas",
        Integer,
        None,
        "Scalar measurements used in the last update",
        Key::NMeas,
    );
    for i in 0..MAX_WEIGHTS {
        b.out(
            format!("weight_{}", i + 1),
            Real,
            Some("1"),
            format!(
                "Fusion weight (ci, dcifaif) or model probability (mmae, mmae-moe) {}",
                i + 1
            ),
            Key::Weight(i),
        );
    }
    b.out(
        "n_weights",
        Integer,
        None,
        "Number of fusion weights / model probabilities (0 for ekf and ukf)",
        Key::NWeights,
    );
}

/// The judgement of the estimate against the truth (the combined model).
pub(super) fn judgement_outputs(b: &mut Builder, specific: Option<&Specific>) {
    use Type::*;
    match specific {
        None => {
            for i in 0..MAX_STATES {
                b.out(
                    format!("truth_x_{}", i + 1),
                    Real,
                    None,
                    format!(
                        "Truth of filter state {} at the estimate's epoch (0 without a truth counterpart)",
                        i + 1
                    ),
                    Key::TruthX(i),
                );
            }
            for i in 0..MAX_STATES {
                b.out(
                    format!("err_{}", i + 1),
                    Real,
                    None,
                    format!(
                        "Estimation error est_x - truth_x of filter state {} (angles wrapped)",
                        i + 1
                    ),
                    Key::Err(i),
                );
            }
        }
        Some(s) => {
            for (i, st) in s.states.iter().enumerate() {
                b.out(
                    format!("truth_x.{}", st.name),
                    Real,
                    Some(st.unit),
                    format!(
                        "True {} at the estimate's epoch (0 without a truth counterpart)",
                        st.description
                    ),
                    Key::TruthX(i),
                );
            }
            for (i, st) in s.states.iter().enumerate() {
                b.out(
                    format!("err.{}", st.name),
                    Real,
                    Some(st.unit),
                    format!(
                        "Estimation error of the {} (angles wrapped)",
                        st.description
                    ),
                    Key::Err(i),
                );
            }
        }
    }
    b.out(
        "nees",
        Real,
        Some("1"),
        "Normalised estimation error squared over the states with a truth value (0 while nees_dof = 0)",
        Key::Nees,
    );
    b.out(
        "nees_dof",
        Integer,
        None,
        "Degrees of freedom of the NEES",
        Key::NeesDof,
    );
    b.out(
        "nav_truth_density",
        Real,
        Some("kg/m3"),
        "True density at the estimate's epoch",
        Key::NavTruthDensity,
    );
}
