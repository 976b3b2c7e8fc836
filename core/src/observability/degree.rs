//! Degree of observability δ = σ_min/σ_max of the observability matrix (seed 000 eq. 14,
//! seed 002 eq. 21), its numerical rank, and the unit scaling that makes δ comparable.
//!
//! **Units.** The entries of O mix metres, radians, m/s and the channels' units, and rows of Lie
//! order k carry an extra s⁻ᵏ, so the raw-SI δ depends on the units by orders of magnitude (a
//! rescaling of one state rescales one column). We report two numbers, always labelled:
//!
//! * **raw (SI)** — δ of O as computed in SI units (m, rad, m/s, kg/m³, s). This is what the
//!   papers print (seed 000: 1e-8…1e-7 centralised; seed 002: 1.4e-8…2.9e-7);
//! * **scaled** — δ of `W O D`, where D = diag(characteristic size of each state) expresses every
//!   state in a natural unit ([`Scaling::characteristic`]), and W divides each row by its channel's
//!   noise 1σ and multiplies a row of Lie order k by τᵏ (τ = 1 s): every entry becomes
//!   "noise sigmas of the k-th output derivative per characteristic unit of the state", a
//!   dimensionless number.
//!
//! **Rank.** Singular values count as non-zero when σ_i > max(rows, n)·ε·σ_max (the usual
//! numerical-rank tolerance). When the rank is below n, δ is reported as 0 together with the rank
//! (never NaN); `sigma_ratio` keeps the unthresholded σ_min/σ_max for reference.

use super::error::ObservabilityError;
use crate::dynamics::{AugmentedParam, EntryModel};
use nalgebra::DMatrix;

/// δ and the singular-value data behind it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Degree {
    /// Degree of observability σ_min/σ_max, or 0 when the numerical rank is below n.
    pub delta: f64,
    /// σ_min/σ_max without the rank test (0 if O has fewer rows than columns or σ_max = 0).
    pub sigma_ratio: f64,
    /// Smallest of the n singular values (0 if O has fewer than n rows).
    pub sigma_min: f64,
    /// Largest singular value.
    pub sigma_max: f64,
    /// Numerical rank.
    pub rank: usize,
    /// Number of states n (columns of O).
    pub states: usize,
}

/// δ of an observability matrix by SVD. Errors if O contains NaN or infinities.
pub fn degree(o: &DMatrix<f64>) -> Result<Degree, ObservabilityError> {
    let n = o.ncols();
    if o.iter().any(|v| !v.is_finite()) {
        return Err(ObservabilityError::NonFinite {
            what: "observability matrix".into(),
        });
    }
    if o.nrows() == 0 || n == 0 {
        return Ok(Degree {
            delta: 0.0,
            sigma_ratio: 0.0,
            sigma_min: 0.0,
            sigma_max: 0.0,
            rank: 0,
            states: n,
        });
    }
    let sv = o.clone().svd(false, false).singular_values;
    let sigma_max = sv.iter().copied().fold(0.0, f64::max);
    let tol = o.nrows().max(n) as f64 * f64::EPSILON * sigma_max;
    let rank = sv.iter().filter(|&&s| s > tol).count();
    let sigma_min = if sv.len() < n {
        0.0
    } else {
        sv.iter().copied().fold(f64::INFINITY, f64::min)
    };
    let sigma_ratio = if sigma_max > 0.0 {
        sigma_min / sigma_max
    } else {
        0.0
    };
    Ok(Degree {
        delta: if rank == n && sigma_max > 0.0 {
            sigma_ratio
        } else {
            0.0
        },
        sigma_ratio,
        sigma_min,
        sigma_max,
        rank,
        states: n,
    })
}

/// Characteristic sizes used for the scaled δ.
#[derive(Debug, Clone, PartialEq)]
pub struct Scaling {
    /// Size of each state in its SI unit (divides the state: x = D·x̃).
    pub state: Vec<f64>,
    /// Name of each state with its unit, e.g. `r_m`.
    pub state_names: Vec<String>,
    /// Time unit τ \[s\]: a row of Lie order k is multiplied by τᵏ.
    pub time_s: f64,
}

impl Scaling {
    /// The documented characteristic sizes for a model's state:
    ///
    /// | state | size |
    /// |---|---|
    /// | r (spherical) | 1 km |
    /// | longitude, latitude | 1e-3 rad (≈ 3.4 km on Mars) |
    /// | v | 1 m/s |
    /// | γ, ψ | 1e-3 rad |
    /// | x, y, z (Cartesian) | 1 km |
    /// | vx, vy, vz (Cartesian) | 1 m/s |
    /// | ρ0 | 1e-5 kg/m³ (5 % of the seed-000 value) |
    /// | L/D | 0.01 |
    /// | C_D S/m | 1e-3 m²/kg |
    ///
    /// and τ = 1 s.
    pub fn characteristic<A>(model: &EntryModel<A>) -> Scaling {
        let (mut state, mut names): (Vec<f64>, Vec<&str>) = if model.kind.is_cartesian() {
            (
                vec![1e3, 1e3, 1e3, 1.0, 1.0, 1.0],
                vec!["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"],
            )
        } else {
            (
                vec![1e3, 1e-3, 1e-3, 1.0, 1e-3, 1e-3],
                vec![
                    "r_m",
                    "lon_rad",
                    "lat_rad",
                    "v_mps",
                    "fpa_rad",
                    "heading_rad",
                ],
            )
        };
        for a in &model.augmented {
            state.push(match a {
                AugmentedParam::Rho0 => 1e-5,
                AugmentedParam::LiftToDrag => 1e-2,
                AugmentedParam::CdSOverM => 1e-3,
                AugmentedParam::DensityBias => 1e-2,
                AugmentedParam::AccelBiasX
                | AugmentedParam::AccelBiasY
                | AugmentedParam::AccelBiasZ => 1e-3,
            });
            names.push(a.name());
        }
        Scaling {
            state,
            state_names: names.into_iter().map(String::from).collect(),
            time_s: 1.0,
        }
    }

    /// `W O D` for an O with `m` outputs per Lie order and output noise 1σ `sigma` (length m).
    pub fn apply(
        &self,
        o: &DMatrix<f64>,
        sigma: &[f64],
    ) -> Result<DMatrix<f64>, ObservabilityError> {
        let m = sigma.len();
        let n = o.ncols();
        if self.state.len() != n || (m > 0 && o.nrows() % m != 0) || (m == 0 && o.nrows() > 0) {
            return Err(ObservabilityError::InvalidInput(format!(
                "scaling for {} states and {m} outputs does not fit a {}x{n} observability matrix",
                self.state.len(),
                o.nrows()
            )));
        }
        let mut s = o.clone();
        for r in 0..o.nrows() {
            let k = (r / m) as i32;
            let w = self.time_s.powi(k) / sigma[r % m];
            for c in 0..n {
                s[(r, c)] *= w * self.state[c];
            }
        }
        Ok(s)
    }
}
