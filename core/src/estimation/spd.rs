//! The inverse of a symmetric positive-definite matrix from its Cholesky factor, in about a third
//! of the work of nalgebra's `Cholesky::inverse`.
//!
//! With `A = L Lᵀ`, `A⁻¹ = L⁻ᵀ L⁻¹ = Tᵀ T` for the lower-triangular `T = L⁻¹`:
//!
//! ```text
//! T_jj = 1 / L_jj,   T_ij = −(Σ_{k=j}^{i−1} L_ik T_kj) / L_ii   (i > j),
//! (A⁻¹)_ij = Σ_{k=max(i,j)}^{N−1} T_ki T_kj.
//! ```
//!
//! The triangular inverse costs N³/6 multiply–adds and the product, of which only one triangle
//! is formed and mirrored, another N³/6; `Cholesky::inverse` solves `A X = I` column by column
//! (N³, none of the zeros of `I` skipped). The result is exactly symmetric. It differs from
//! `Cholesky::inverse` by round-off only (the tests bound the difference); the fusion filters'
//! Monte Carlo statistics changed accordingly (docs/results.md, *Monte Carlo speed*).

use nalgebra::SMatrix;

/// `A⁻¹` from the Cholesky factor `L` of `A` (only its lower triangle is read). Non-finite when
/// `L` has a zero diagonal; callers check the result.
pub fn inverse_from_cholesky<const N: usize>(l: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    // T = L⁻¹, column-major: t[(i, j)] for i ≥ j.
    let mut t = SMatrix::<f64, N, N>::zeros();
    for j in 0..N {
        t[(j, j)] = 1.0 / l[(j, j)];
        for i in j + 1..N {
            let mut s = 0.0;
            for k in j..i {
                s += l[(i, k)] * t[(k, j)];
            }
            t[(i, j)] = -s / l[(i, i)];
        }
    }
    // A⁻¹ = Tᵀ T: entry (i, j), i ≤ j, is the dot product of columns i and j of T from row j on.
    let mut inv = SMatrix::<f64, N, N>::zeros();
    for j in 0..N {
        let cj = t.column(j);
        for i in 0..=j {
            let ci = t.column(i);
            let mut s = 0.0;
            for k in j..N {
                s += ci[k] * cj[k];
            }
            inv[(i, j)] = s;
            inv[(j, i)] = s;
        }
    }
    inv
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SMatrix;

    /// A badly scaled 11 × 11 SPD matrix like an entry filter's covariance (1e-12 next to 1e6).
    fn covariance(seed: f64) -> SMatrix<f64, 11, 11> {
        let a = SMatrix::<f64, 11, 11>::from_fn(|r, c| ((r * 11 + c) as f64 * seed).sin());
        let scale = SMatrix::<f64, 11, 11>::from_fn(|r, c| {
            if r == c {
                10f64.powi(r as i32 - 5)
            } else {
                0.0
            }
        });
        scale * (a * a.transpose() + SMatrix::identity() * 0.05) * scale
    }

    #[test]
    fn equals_nalgebras_inverse_to_round_off_and_is_symmetric() {
        for seed in [0.3, 1.1, 2.7, 5.9] {
            let a = covariance(seed);
            let chol = a.cholesky().unwrap();
            let ours = inverse_from_cholesky(&chol.l());
            let theirs = chol.inverse();
            assert_eq!(ours, ours.transpose(), "exactly symmetric");
            // Compare in the scaled metric: D (A⁻¹) D with D = diag(√A_kk) is O(1).
            let d = a.diagonal().map(f64::sqrt);
            let rel = SMatrix::<f64, 11, 11>::from_fn(|r, c| {
                (ours[(r, c)] - theirs[(r, c)]) * d[r] * d[c]
            })
            .abs()
            .max();
            assert!(rel < 1e-8, "seed {seed}: scaled difference {rel:e}");
            // And it is an inverse: A A⁻¹ = I in the same metric.
            let id = a * ours;
            let err = SMatrix::<f64, 11, 11>::from_fn(|r, c| {
                (id[(r, c)] - if r == c { 1.0 } else { 0.0 }) * d[c] / d[r]
            })
            .abs()
            .max();
            assert!(err < 1e-8, "seed {seed}: A A⁻¹ − I = {err:e}");
        }
    }

    #[test]
    fn reads_only_the_lower_triangle() {
        let a = covariance(0.7);
        let l = a.cholesky().unwrap().l();
        let mut dirty = l;
        for j in 1..11 {
            for i in 0..j {
                dirty[(i, j)] = f64::NAN;
            }
        }
        assert_eq!(inverse_from_cholesky(&l), inverse_from_cholesky(&dirty));
    }
}
