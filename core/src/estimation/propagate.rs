//! The covariance time update's congruence `Φ P Φᵀ` (seed 000 eq. 17), using the structure of
//! an entry filter's transition matrix.
//!
//! The augmented states that are random constants (ρ0, L/D, accelerometer biases without a
//! Gauss–Markov time constant) have `ḃ = 0`, so their rows of Φ are unit rows `e_iᵀ`: row `i`
//! of `Φ P` is row `i` of `P`, and column `i` of `(Φ P) Φᵀ` is column `i` of `Φ P`. Only the
//! six kinematic rows need the products, about 6/11 of the dense work for the 11-state
//! four-beacon filter.
//!
//! The dense product sums `Σ_k Φ_ik P_kj` in increasing `k`; a unit row's sum is one term `P_ij`
//! plus exact zeros, and the kinematic rows are the same sums in the same order. The result is
//! therefore the dense product's, bit for bit (a test checks it), for finite `P`.

use nalgebra::SMatrix;

/// The leading kinematic states, whose rows of Φ are full.
const KIN: usize = 6;

/// Whether row `i` of `phi` is the unit row `e_iᵀ`.
fn unit_row<const N: usize>(phi: &SMatrix<f64, N, N>, i: usize) -> bool {
    (0..N).all(|j| phi[(i, j)] == if j == i { 1.0 } else { 0.0 })
}

/// `Φ P Φᵀ`: with every row of `phi` after the six kinematic ones a unit row, only the
/// kinematic rows and columns are multiplied; otherwise the dense product.
pub fn phi_p_phit<const N: usize>(
    phi: &SMatrix<f64, N, N>,
    p: &SMatrix<f64, N, N>,
) -> SMatrix<f64, N, N> {
    if N <= KIN || !(KIN..N).all(|i| unit_row(phi, i)) {
        return phi * p * phi.transpose();
    }
    let phi_kin = phi.fixed_rows::<KIN>(0);
    // A = Φ P: the kinematic rows by the product, the others P's rows.
    let mut a = *p;
    a.fixed_rows_mut::<KIN>(0).copy_from(&(phi_kin * p));
    // A Φᵀ: the kinematic columns by the product, the others A's columns.
    let left = a * phi_kin.transpose();
    a.fixed_columns_mut::<KIN>(0).copy_from(&left);
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    fn phi_and_p(tail: f64) -> (SMatrix<f64, 11, 11>, SMatrix<f64, 11, 11>) {
        let mut phi = SMatrix::<f64, 11, 11>::from_fn(|r, c| {
            let v = ((r * 11 + c) as f64 * 0.37).sin();
            if r == c { 1.0 + 0.1 * v } else { 0.05 * v }
        });
        for r in KIN..11 {
            phi.row_mut(r).fill(0.0);
            phi[(r, r)] = tail;
        }
        let a = SMatrix::<f64, 11, 11>::from_fn(|r, c| ((r * 7 + c * 3) as f64 * 0.91).cos());
        let scale = SMatrix::<f64, 11, 11>::from_diagonal(&nalgebra::SVector::from_fn(|r, _| {
            10f64.powi(r as i32 - 4)
        }));
        (phi, scale * (a * a.transpose()) * scale)
    }

    #[test]
    fn equals_the_dense_product_bit_for_bit() {
        // Constant augmented states (unit rows): the structured path.
        let (phi, p) = phi_and_p(1.0);
        assert_eq!(phi_p_phit(&phi, &p), phi * p * phi.transpose());
        // Gauss–Markov biases (diagonal 0.9, not unit rows): the dense path.
        let (phi, p) = phi_and_p(0.9);
        assert_eq!(phi_p_phit(&phi, &p), phi * p * phi.transpose());
        // A six-state filter has no augmented rows.
        let phi6 = phi.fixed_view::<6, 6>(0, 0).into_owned();
        let p6 = p.fixed_view::<6, 6>(0, 0).into_owned();
        assert_eq!(phi_p_phit(&phi6, &p6), phi6 * p6 * phi6.transpose());
    }
}
