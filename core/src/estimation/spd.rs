//! The Cholesky factorisation of a symmetric positive-definite matrix ([`cholesky`], nalgebra's
//! bit for bit in fewer instructions) and the inverse from its factor
//! ([`inverse_from_cholesky`]) by the explicit sums below instead of nalgebra's
//! `Cholesky::inverse`.
//!
//! With `A = L Lᵀ`, `A⁻¹ = L⁻ᵀ L⁻¹ = Tᵀ T` for the lower-triangular `T = L⁻¹`:
//!
//! ```text
//! T_jj = 1 / L_jj,   T_ij = −(Σ_{k=j}^{i−1} L_ik T_kj) / L_ii   (i > j),
//! (A⁻¹)_ij = Σ_{k=max(i,j)}^{N−1} T_ki T_kj.
//! ```
//!
//! Of these sums' N³/3 multiply–adds, [`inverse_from_cholesky`] runs the triangles' zeros too
//! (N³ in all), in whole-row `y += a·x` loops that the compiler vectorises and that need no
//! bounds checks; `Cholesky::inverse` solves `A X = I` column by column (N³ with its
//! triangular solves). The result is exactly symmetric. It differs from
//! `Cholesky::inverse` by round-off only (the tests bound the difference); the fusion filters'
//! Monte Carlo statistics changed accordingly (docs/results.md, *Monte Carlo speed*).

use nalgebra::{Cholesky, Const, SMatrix};

/// The Cholesky factorisation `A = L Lᵀ` of a symmetric positive-definite `A` (its lower
/// triangle is read), or `None` where nalgebra's `Matrix::cholesky` gives `None` (a pivot that
/// is zero, negative or NaN).
///
/// The same operations in the same order as nalgebra's (left-looking: column `j` less
/// `L_jk` times column `k` for every `k < j`, the pivot's square root, the column divided by it),
/// so the factor is bit-identical (a test checks it); it runs on the column-major slice
/// instead of matrix views, in about a third of the instructions on an 11 × 11. The strictly
/// upper triangle keeps `A`'s entries, as `Cholesky::l_dirty` does.
#[allow(
    clippy::needless_range_loop,
    clippy::assign_op_pattern,
    clippy::neg_cmp_op_on_partial_ord
)]
pub fn cholesky<const N: usize>(a: &SMatrix<f64, N, N>) -> Option<Cholesky<f64, Const<N>>> {
    let mut m = *a;
    // Columns as arrays (`c[j][i]` is entry (i, j)): every index is a loop variable below N, so
    // the loops carry no bounds checks. Written as nalgebra writes them (`y = a·x + y`, its
    // pivot test): iterator and `+=` forms measured 2–4 % more instructions per trade.
    let c = &mut m.data.0;
    for j in 0..N {
        for k in 0..j {
            let factor = -c[k][j];
            for i in j..N {
                c[j][i] = factor * c[k][i] + c[j][i];
            }
        }
        let diag = c[j][j];
        if diag == 0.0 || !(diag >= 0.0) {
            return None;
        }
        let denom = diag.sqrt();
        c[j][j] = denom;
        for i in j + 1..N {
            c[j][i] /= denom;
        }
    }
    Some(Cholesky::pack_dirty(m))
}

/// `T = L⁻¹` of a lower-triangular `L` (only its lower triangle is read), by columns:
/// `t[j][i] = T_ij` for `i ≥ j`, zero above the diagonal (the module doc's first sums).
/// Non-finite when `L` has a zero diagonal.
pub fn lower_inverse<const N: usize>(l: &SMatrix<f64, N, N>) -> [[f64; N]; N] {
    // Lᵀ's columns are L's rows (`lr[i][k]` = L_ik), so the sums run over contiguous memory.
    let lt = l.transpose();
    let lr = &lt.data.0;
    let mut t = [[0.0f64; N]; N];
    for j in 0..N {
        t[j][j] = 1.0 / lr[j][j];
        for i in j + 1..N {
            let mut s = 0.0;
            for k in j..i {
                s += lr[i][k] * t[j][k];
            }
            t[j][i] = -s / lr[i][i];
        }
    }
    t
}

/// `A⁻¹` from the Cholesky factor `L` of `A` (only its lower triangle is read). Non-finite when
/// `L` has a zero diagonal; callers check the result.
///
/// The module doc's sums, each in the same order (`k` ascending), so the result equals the
/// running sums bit for bit for a finite `L` (a test checks it); but both run as `y += a·x` over
/// whole rows of `T`, which the compiler unrolls and vectorises, instead of one dot product per
/// entry. The rows' zeros (`T_kj = 0` for `j > k`) only add `±0` to sums that are still `+0`, and
/// every entry of `Tᵀ T` is summed from its first non-zero term, so no mirroring is needed.
#[allow(clippy::needless_range_loop)] // rows of several arrays at one index
pub fn inverse_from_cholesky<const N: usize>(l: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    // lc[k][i] = L_ik.
    let lc = &l.data.0;
    // Rows of T = L⁻¹: t[i][j] = T_ij, zero for j > i. Row i: Σ_{k=j}^{i−1} L_ik T_kj for every
    // j < i at once, k ascending.
    let mut t = [[0.0f64; N]; N];
    for i in 0..N {
        let mut acc = [0.0f64; N];
        for k in 0..i {
            let lik = lc[k][i];
            for (a, v) in acc.iter_mut().zip(&t[k]) {
                *a += lik * v;
            }
        }
        let d = lc[i][i];
        for j in 0..i {
            t[i][j] = -acc[j] / d;
        }
        t[i][i] = 1.0 / d;
    }
    // A⁻¹ = Tᵀ T: column j's entry i is Σ_{k=max(i,j)}^{N−1} T_ki T_kj, k ascending, all i at once.
    let mut inv = SMatrix::<f64, N, N>::zeros();
    for (j, col) in inv.data.0.iter_mut().enumerate() {
        for k in j..N {
            let v = t[k][j];
            for (c, tki) in col.iter_mut().zip(&t[k]) {
                *c += tki * v;
            }
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
    fn cholesky_is_nalgebras_bit_for_bit_and_fails_where_it_fails() {
        for seed in [0.3, 0.7, 1.1, 2.7, 5.9] {
            let a = covariance(seed);
            let ours = cholesky(&a).unwrap();
            let theirs = a.cholesky().unwrap();
            assert_eq!(ours.l_dirty(), theirs.l_dirty(), "seed {seed}");
            let b = SMatrix::<f64, 11, 1>::from_fn(|r, _| (r as f64 * seed).cos());
            assert_eq!(ours.solve(&b), theirs.solve(&b));
        }
        // Not positive definite: a negative pivot, a zero pivot, a NaN, a negative eigenvalue.
        let mut bad = covariance(0.3);
        bad[(4, 4)] = -1.0;
        let mut zero = covariance(0.3);
        zero.row_mut(0).fill(0.0);
        zero.column_mut(0).fill(0.0);
        let mut nan = covariance(0.3);
        nan[(7, 2)] = f64::NAN;
        let indefinite = nalgebra::Matrix2::new(1.0, 2.0, 2.0, 1.0);
        for m in [bad, zero, nan] {
            assert!(m.cholesky().is_none() && cholesky(&m).is_none());
        }
        assert!(indefinite.cholesky().is_none() && cholesky(&indefinite).is_none());
    }

    /// The module doc's sums as written, one running sum per entry.
    fn inverse_by_running_sums(l: &SMatrix<f64, 11, 11>) -> SMatrix<f64, 11, 11> {
        let mut t = SMatrix::<f64, 11, 11>::zeros();
        for j in 0..11 {
            t[(j, j)] = 1.0 / l[(j, j)];
            for i in j + 1..11 {
                let mut s = 0.0;
                for k in j..i {
                    s += l[(i, k)] * t[(k, j)];
                }
                t[(i, j)] = -s / l[(i, i)];
            }
        }
        SMatrix::from_fn(|i, j| {
            let mut s = 0.0;
            for k in i.max(j)..11 {
                s += t[(k, i)] * t[(k, j)];
            }
            s
        })
    }

    #[test]
    fn equals_the_indexed_running_sums_bit_for_bit() {
        for seed in [0.3, 0.7, 1.1, 2.7, 5.9] {
            let l = covariance(seed).cholesky().unwrap().l();
            assert_eq!(inverse_from_cholesky(&l), inverse_by_running_sums(&l));
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
        let mut upper_nan = a;
        for j in 1..11 {
            for i in 0..j {
                upper_nan[(i, j)] = f64::NAN;
            }
        }
        let (c, c_nan) = (cholesky(&a).unwrap(), cholesky(&upper_nan).unwrap());
        assert_eq!(c.l(), c_nan.l());
    }
}
