//! The outputs of the navigation filter: its status, the estimate (state, 1σ, spherical
//! position and velocity, density) and what the last update saw (NIS, measurements, weights).

use super::builder::{Builder, SPH};
use crate::vars::enums::NAV_STATUS;
use crate::vars::sizes::{MAX_STATES, MAX_WEIGHTS};
use crate::vars::slot::Key;
use crate::vars::specific::Specific;
use crate::vars::var::Type;

/// The estimate outputs of a model with a filter.
pub(super) fn nav_outputs(b: &mut Builder, specific: Option<&Specific>) {
    nav_status(b);
    estimate(b, specific);
    update_info(b);
}

/// The epoch and status of the filter and its state dimension.
fn nav_status(b: &mut Builder) {
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
}

/// The estimate and its 1σ (named by slot, or by the specific FMU's states), and the spherical
/// position and velocity.
fn estimate(b: &mut Builder, specific: Option<&Specific>) {
    use Type::*;
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
}

/// The density estimate, the last update's NIS and measurement count, the fusion weights or model
/// probabilities.
fn update_info(b: &mut Builder) {
    use Type::*;
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
