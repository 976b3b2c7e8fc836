//! The fast ∞-norm CI weights of seed 000 eq. 21, on formed or scaled information matrices.

use super::ci_scaling::{Mat, Vect, nonfinite};
use super::error::EstimationError;

/// Seed 000 eq. 21 generalised to `n` estimates:
///
/// ```text
/// ω_i = (‖Y‖∞ − ‖Y − Y_i‖∞ + ‖Y_i‖∞) / (n‖Y‖∞ + Σ_j (‖Y_j‖∞ − ‖Y − Y_j‖∞)),   Y = Σ_j Y_j.
/// ```
///
/// The denominator is the sum of the numerators, so Σ ω_i = 1; every numerator is ≥ 0 by the
/// triangle inequality (round-off negatives are clamped to 0). For `n = 1`, ω = [1].
pub(super) fn fast_weights<const N: usize>(infos: &[Mat<N>]) -> Result<Vec<f64>, EstimationError> {
    fast_weights_scaled(infos, &Vect::<N>::repeat(1.0))
}

/// [`fast_weights`] of the informations `S Y'_i S` (`S = diag(s)`), without forming them: each
/// entry `Y'_i,rc s_r s_c`, their sum and every row's absolute sums are taken column by column,
/// with the same operations in the same order as on the formed matrices (`Y = Σ Y_i` from zero,
/// row sums from zero in column order), so the weights are the same to the bit.
pub(super) fn fast_weights_scaled<const N: usize>(
    ys: &[Mat<N>],
    s: &Vect<N>,
) -> Result<Vec<f64>, EstimationError> {
    // Column c of S Y'_i S (entry r: (Y'_i)_rc s_r s_c, as `congruence` forms it).
    let column = |yi: &Mat<N>, c: usize| -> [f64; N] {
        let col = &yi.data.0[c];
        std::array::from_fn(|r| col[r] * s[r] * s[c])
    };
    // Y = Σ_i S Y'_i S from zero, by columns.
    let mut y = [[0.0f64; N]; N];
    for yi in ys {
        for (c, yc) in y.iter_mut().enumerate() {
            for (acc, v) in yc.iter_mut().zip(column(yi, c)) {
                *acc += v;
            }
        }
    }
    // ‖·‖∞ from the rows' absolute sums, accumulated column by column (each row in column order).
    let max_row = |rows: &[f64; N]| rows.iter().fold(0.0, |m: f64, v| m.max(*v));
    let mut rows = [0.0f64; N];
    for yc in &y {
        for (acc, v) in rows.iter_mut().zip(yc) {
            *acc += v.abs();
        }
    }
    let ny = max_row(&rows);
    let (mut norm_i, mut norm_rest) = (Vec::with_capacity(ys.len()), Vec::with_capacity(ys.len()));
    for yi in ys {
        let (mut own, mut rest) = ([0.0f64; N], [0.0f64; N]);
        for (c, yc) in y.iter().enumerate() {
            for (((o, r), v), total) in own.iter_mut().zip(&mut rest).zip(column(yi, c)).zip(yc) {
                *o += v.abs();
                *r += (total - v).abs();
            }
        }
        norm_i.push(max_row(&own));
        norm_rest.push(max_row(&rest));
    }
    let num: Vec<f64> = norm_i
        .iter()
        .zip(&norm_rest)
        .map(|(ni, nr)| (ny - nr + ni).max(0.0))
        .collect();
    let den: f64 = num.iter().sum();
    if !den.is_finite() || den <= 0.0 {
        return Err(nonfinite("∞-norm CI weight denominator".into()));
    }
    Ok(num.iter().map(|v| v / den).collect())
}
