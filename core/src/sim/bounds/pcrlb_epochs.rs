//! One run's PCRLB inputs, stored compactly until they are folded into the run sums
//! ([`super::pcrlb_sums::BoundSums`]).
//!
//! Per epoch: the transition F (row-major; rows that are exactly identity rows, the constant
//! states', are not stored but flagged), and the upper triangles of the symmetric I, JₚᵀJₚ and
//! JᵥᵀJᵥ (the latter two only on the kinematic block, where J is non-zero). For the 11-state
//! four-beacon-fusion filter that is 180 numbers an epoch instead of 2·11² + 2·6².

use nalgebra::SMatrix;

/// The leading block of JₚᵀJₚ and JᵥᵀJᵥ that can be non-zero: the tables' position and velocity
/// depend on the six kinematic states only.
pub(super) const KIN: usize = 6;

/// What one run contributes to the bound: per epoch its time, F, I, JₚᵀJₚ and JᵥᵀJᵥ (with Jₚ, Jᵥ
/// the 3×N position and velocity maps), in one buffer.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundRunData {
    n: usize,
    pub(super) times: Vec<f64>,
    /// Per epoch: where its numbers start in `data`, and which rows of F are stored (bit i).
    starts: Vec<usize>,
    stored_rows: Vec<u32>,
    data: Vec<f64>,
}

impl BoundRunData {
    /// An empty record for `epochs` epochs of an `n`-state filter (n ≤ 32).
    pub(super) fn with_capacity(n: usize, epochs: usize) -> Self {
        let tri = |k: usize| k * (k + 1) / 2;
        BoundRunData {
            n,
            times: Vec::with_capacity(epochs),
            starts: Vec::with_capacity(epochs),
            stored_rows: Vec::with_capacity(epochs),
            data: Vec::with_capacity(epochs * (n * n + tri(n) + 2 * tri(KIN))),
        }
    }

    /// State dimension N.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Number of epochs.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether the run has no epochs.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// Append an epoch (`pos`, `vel` are the kinematic blocks of JₚᵀJₚ, JᵥᵀJᵥ).
    pub(super) fn push<const N: usize>(
        &mut self,
        t: f64,
        phi: &SMatrix<f64, N, N>,
        info: &SMatrix<f64, N, N>,
        pos: &SMatrix<f64, KIN, KIN>,
        vel: &SMatrix<f64, KIN, KIN>,
    ) {
        self.times.push(t);
        self.starts.push(self.data.len());
        let mut rows = 0u32;
        for i in 0..N {
            let identity = (0..N).all(|j| phi[(i, j)] == if i == j { 1.0 } else { 0.0 });
            if !identity {
                rows |= 1 << i;
                self.data.extend((0..N).map(|j| phi[(i, j)]));
            }
        }
        self.stored_rows.push(rows);
        push_upper(&mut self.data, info);
        push_upper(&mut self.data, pos);
        push_upper(&mut self.data, vel);
    }

    /// Add epoch `i` into full row-major N×N sums of F, I, JₚᵀJₚ and JᵥᵀJᵥ. Every element gets
    /// exactly the value the full matrix holds there (an identity row adds its ones and zeros),
    /// so the sums are those of the full matrices.
    pub(super) fn add_epoch_into(
        &self,
        i: usize,
        phi: &mut [f64],
        info: &mut [f64],
        pos: &mut [f64],
        vel: &mut [f64],
    ) {
        let n = self.n;
        let mut data = &self.data[self.starts[i]..];
        let rows = self.stored_rows[i];
        for r in 0..n {
            let sum = &mut phi[r * n..(r + 1) * n];
            if rows & (1 << r) != 0 {
                for (x, y) in sum.iter_mut().zip(&data[..n]) {
                    *x += y;
                }
                data = &data[n..];
            } else {
                sum[r] += 1.0;
            }
        }
        data = add_upper(info, n, n, data);
        data = add_upper(pos, n, KIN, data);
        add_upper(vel, n, KIN, data);
    }
}

/// Append the upper triangle (row by row) of the symmetric `m`.
fn push_upper<const K: usize>(out: &mut Vec<f64>, m: &SMatrix<f64, K, K>) {
    for a in 0..K {
        out.extend((a..K).map(|b| m[(a, b)]));
    }
}

/// Add a stored upper triangle of a symmetric k×k block into the leading block of the row-major
/// n×n `sum`, both halves; returns the rest of `data`.
fn add_upper<'a>(sum: &mut [f64], n: usize, k: usize, mut data: &'a [f64]) -> &'a [f64] {
    for a in 0..k {
        for b in a..k {
            sum[a * n + b] += data[b - a];
            if b != a {
                sum[b * n + a] += data[b - a];
            }
        }
        data = &data[k - a..];
    }
    data
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_epoch_adds_the_full_matrices() {
        let phi = SMatrix::<f64, 8, 8>::from_fn(|i, j| {
            if i >= 6 {
                f64::from(u8::from(i == j))
            } else {
                (i * 8 + j) as f64 * 0.5 - 3.0
            }
        });
        let g = SMatrix::<f64, 8, 3>::from_fn(|i, j| (i as f64 - 2.5) * (j as f64 + 1.0));
        let info = g * g.transpose();
        let j = SMatrix::<f64, 3, KIN>::from_fn(|i, j| (i + 2 * j) as f64 - 4.0);
        let (pos, vel) = (j.transpose() * j, (j * 2.0).transpose() * (j * 2.0));
        let mut run = BoundRunData::with_capacity(8, 1);
        run.push(1.0, &phi, &info, &pos, &vel);
        assert_eq!(
            run.stored_rows[0], 0b11_1111,
            "the two identity rows are not stored"
        );
        let mut sums = [vec![0.5; 64], vec![0.5; 64], vec![0.5; 64], vec![0.5; 64]];
        let [a, b, c, d] = &mut sums;
        run.add_epoch_into(0, a, b, c, d);
        for r in 0..8 {
            for s in 0..8 {
                let kin =
                    |m: &SMatrix<f64, KIN, KIN>| if r < KIN && s < KIN { m[(r, s)] } else { 0.0 };
                assert_eq!(sums[0][r * 8 + s], 0.5 + phi[(r, s)]);
                assert_eq!(sums[1][r * 8 + s], 0.5 + info[(r, s)]);
                assert_eq!(sums[2][r * 8 + s], 0.5 + kin(&pos));
                assert_eq!(sums[3][r * 8 + s], 0.5 + kin(&vel));
            }
        }
    }
}
