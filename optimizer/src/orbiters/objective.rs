//! [`OrbiterObjective`]: what the orbiter search maximises (eq. 57, 62), its name and units,
//! and the floor inside its logarithm.

/// Smallest determinant taken inside the logarithm of [`OrbiterObjective::LogDet`].
pub const LOG_DET_FLOOR: f64 = 1e-9;

/// What is integrated along the trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrbiterObjective {
    /// `∫ det(N₃) dt` (seed 002 eq. 57, 62), three orbiters only.
    DetN3,
    /// `∫ log max(det F, 10⁻⁹) dt`, any number ≥ 3.
    LogDet,
}

impl OrbiterObjective {
    /// The paper's choice: [`OrbiterObjective::DetN3`] for three orbiters, else
    /// [`OrbiterObjective::LogDet`].
    pub fn default_for(count: usize) -> OrbiterObjective {
        if count == 3 {
            OrbiterObjective::DetN3
        } else {
            OrbiterObjective::LogDet
        }
    }

    /// Name used in reports: `integral-det-N3` or `integral-logdet-fim`.
    pub fn name(self) -> &'static str {
        match self {
            OrbiterObjective::DetN3 => "integral-det-N3",
            OrbiterObjective::LogDet => "integral-logdet-fim",
        }
    }

    /// Upper bound of the objective per second of trajectory: 1 for det(N₃), `3 log(n/3)` for
    /// log det (seed 002 eq. 40).
    pub fn max_rate(self, count: usize) -> f64 {
        match self {
            OrbiterObjective::DetN3 => 1.0,
            OrbiterObjective::LogDet => 3.0 * (count as f64 / 3.0).ln(),
        }
    }
}
