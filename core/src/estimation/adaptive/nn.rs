//! The 1-H-1 tanh density network of seed 001 §IV.A (eq. 28–33), its gradients by
//! backpropagation, and the Adam optimiser (Kingma & Ba; seed 001 eq. 55–57).
//!
//! # Network and transforms
//!
//! The network maps planet-centric radius r to density (eq. 28) through
//!
//! ```text
//! i = (r − r̄)/σ_r                                  (eq. 30, input normalisation)
//! a = tanh(W⁽ⁱ⁾ i + b⁽ⁱ⁾)          a ∈ ℝᴴ           (eq. 32)
//! o = W⁽ᵒ⁾ a + b⁽ᵒ⁾                                 (eq. 33)
//! ϱ = σ_ϱ o + ϱ̄                                     (eq. 31 inverted)
//! ρ = 10^(𝓑 − ϱ²)                                   (eq. 29 inverted: ϱ = √(𝓑 − log₁₀ ρ))
//! ```
//!
//! with H = 100 and 𝓑 = 0 in the paper. The parameters ξ are stored flat, in the order
//! `[W⁽ⁱ⁾ (H), b⁽ⁱ⁾ (H), W⁽ᵒ⁾ (H), b⁽ᵒ⁾ (1)]` (3H + 1 = 301 values for H = 100).
//!
//! # Gradients
//!
//! [`DensityNetwork::density_gradient`] returns ∂ρ/∂ξ by reverse-mode differentiation written
//! out for this network (one forward pass, one backward pass, no tape):
//! `∂ρ/∂o = −2 ln10 · ρ · ϱ · σ_ϱ`, `∂o/∂W⁽ᵒ⁾ⱼ = aⱼ`, `∂o/∂b⁽ᵒ⁾ = 1`,
//! `∂o/∂b⁽ⁱ⁾ⱼ = W⁽ᵒ⁾ⱼ (1 − aⱼ²)`, `∂o/∂W⁽ⁱ⁾ⱼ = W⁽ᵒ⁾ⱼ (1 − aⱼ²) i`. The tests check it against
//! central finite differences.
//!
//! # Speed
//!
//! The filter evaluates the network about 100 times per step (19 sigma points × 4 RK4 stages,
//! plus the update and the adaptation), and the offline training a few hundred million times,
//! so tanh is computed by [`tanh_fast`]: an exp by range reduction and a degree-13 polynomial,
//! written so that the compiler vectorises the hidden layer. Its absolute error is below 3e-16
//! (tested against `f64::tanh`).

use super::error::NetworkError;
use serde::{Deserialize, Serialize};

/// Hidden-layer width used by seed 001 (§IV.A: "one hidden layer containing 100 neurons").
pub const SEED001_HIDDEN: usize = 100;

const LN10: f64 = std::f64::consts::LN_10;

/// `tanh(x)` to < 3e-16 absolute error, branch-free so that loops over it vectorise.
///
/// tanh(x) = sign(x)·(1 − 2/(e^{2|x|} + 1)); e^y for y = 2|x| ∈ [0, 40] is 2ᵏ·e^f with
/// k = round(y/ln2), f = y − k ln2 (Cody–Waite split), e^f by its Taylor series to degree 13
/// (|f| ≤ ln2/2, truncation < 1e-17), and 2ᵏ assembled from the exponent bits. Beyond |x| = 20
/// tanh is 1 to double precision.
#[inline(always)]
pub fn tanh_fast(x: f64) -> f64 {
    const LOG2E: f64 = std::f64::consts::LOG2_E;
    const LN2_HI: f64 = 6.931_471_803_691_238e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
    // 1.5·2⁵²: adding it rounds to an integer held in the low mantissa bits.
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    let ax = x.abs().min(20.0);
    let y = 2.0 * ax;
    let t = y * LOG2E + MAGIC;
    let k = t - MAGIC;
    let f = (y - k * LN2_HI) - k * LN2_LO;
    // e^f, Horner, degree 13.
    let mut p = 1.0 / 6_227_020_800.0;
    p = p * f + 1.0 / 479_001_600.0;
    p = p * f + 1.0 / 39_916_800.0;
    p = p * f + 1.0 / 3_628_800.0;
    p = p * f + 1.0 / 362_880.0;
    p = p * f + 1.0 / 40_320.0;
    p = p * f + 1.0 / 5_040.0;
    p = p * f + 1.0 / 720.0;
    p = p * f + 1.0 / 120.0;
    p = p * f + 1.0 / 24.0;
    p = p * f + 1.0 / 6.0;
    p = p * f + 0.5;
    p = p * f + 1.0;
    p = p * f + 1.0;
    // 2^k with k in [0, 58]: the low 12 bits of t's representation are k.
    let two_k = f64::from_bits((t.to_bits().wrapping_add(1023)) << 52);
    let e = p * two_k;
    let r = 1.0 - 2.0 / (e + 1.0);
    r.copysign(x)
}

/// Neurons per stack chunk in the buffer-free passes.
const CHUNK: usize = 64;

/// Σ aᵢbᵢ with four accumulators (vectorises; the order is fixed, so results are reproducible).
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Normalisation and output transform of a network (seed 001 eq. 29–31).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Normalisation {
    /// Mean r̄ of the training radii \[m\] (eq. 30).
    pub r_mean_m: f64,
    /// Standard deviation σ_r of the training radii \[m\] (eq. 30).
    pub r_std_m: f64,
    /// Mean ϱ̄ of the transformed training densities (eq. 31).
    pub out_mean: f64,
    /// Standard deviation σ_ϱ of the transformed training densities (eq. 31).
    pub out_std: f64,
    /// Shift 𝓑 of eq. 29 (0 in seed 001: densities in SI are below 1 kg/m³).
    pub shift: f64,
}

impl Normalisation {
    /// ϱ = √(𝓑 − log₁₀ ρ) (eq. 29).
    pub fn transform(&self, rho: f64) -> f64 {
        (self.shift - rho.log10()).max(0.0).sqrt()
    }

    /// ρ = 10^(𝓑 − ϱ²), the inverse of eq. 29.
    pub fn untransform(&self, varrho: f64) -> f64 {
        (LN10 * (self.shift - varrho * varrho)).exp()
    }
}

/// A 1-H-1 tanh network ρ̂ = NN(r, ξ) with its normalisation (seed 001 eq. 28–33).
#[derive(Debug, Clone, PartialEq)]
pub struct DensityNetwork {
    hidden: usize,
    /// Flat parameters ξ: `[W⁽ⁱ⁾, b⁽ⁱ⁾, W⁽ᵒ⁾, b⁽ᵒ⁾]`.
    xi: Vec<f64>,
    /// Input/output normalisation and transform.
    pub norm: Normalisation,
}

/// Hidden activations of one forward pass (reused buffer).
#[derive(Debug, Clone, Default)]
pub struct Activations {
    a: Vec<f64>,
}

impl DensityNetwork {
    /// A network with `hidden` neurons, parameters `xi` (length 3H + 1) and normalisation `norm`.
    /// Errors if the lengths do not match, a value is non-finite or a standard deviation ≤ 0.
    pub fn new(hidden: usize, xi: Vec<f64>, norm: Normalisation) -> Result<Self, NetworkError> {
        if hidden == 0 {
            return Err(NetworkError::NoHiddenNeurons);
        }
        if xi.len() != 3 * hidden + 1 {
            return Err(NetworkError::ParameterCount {
                given: xi.len(),
                hidden,
                expected: 3 * hidden + 1,
            });
        }
        if let Some(i) = xi.iter().position(|v| !v.is_finite()) {
            return Err(NetworkError::NonFiniteParameter(i));
        }
        let n = &norm;
        for (name, v) in [
            ("r_mean_m", n.r_mean_m),
            ("out_mean", n.out_mean),
            ("shift", n.shift),
        ] {
            if !v.is_finite() {
                return Err(NetworkError::NonFiniteNormalisation { name, value: v });
            }
        }
        for (name, v) in [("r_std_m", n.r_std_m), ("out_std", n.out_std)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(NetworkError::BadStandardDeviation { name, value: v });
            }
        }
        Ok(DensityNetwork { hidden, xi, norm })
    }

    /// Hidden-layer width H.
    pub fn hidden(&self) -> usize {
        self.hidden
    }

    /// Number of parameters 3H + 1.
    pub fn n_params(&self) -> usize {
        self.xi.len()
    }

    /// The flat parameters ξ.
    pub fn params(&self) -> &[f64] {
        &self.xi
    }

    /// Mutable flat parameters ξ.
    pub fn params_mut(&mut self) -> &mut [f64] {
        &mut self.xi
    }

    /// `(W⁽ⁱ⁾, b⁽ⁱ⁾, W⁽ᵒ⁾, b⁽ᵒ⁾)` views of ξ.
    pub fn layers(&self) -> (&[f64], &[f64], &[f64], f64) {
        let h = self.hidden;
        (
            &self.xi[..h],
            &self.xi[h..2 * h],
            &self.xi[2 * h..3 * h],
            self.xi[3 * h],
        )
    }

    /// Normalised input i of eq. 30 for radius `r_m`.
    #[inline]
    pub fn input(&self, r_m: f64) -> f64 {
        (r_m - self.norm.r_mean_m) / self.norm.r_std_m
    }

    /// Hidden activations into `act`, and the normalised output o (eq. 32–33).
    #[inline]
    pub fn forward(&self, i: f64, act: &mut Activations) -> f64 {
        let (w1, b1, w2, b2) = self.layers();
        act.a.resize(self.hidden, 0.0);
        // Two passes (affine, then tanh in place) so that both loops vectorise.
        for ((a, w), b) in act.a.iter_mut().zip(w1).zip(b1) {
            *a = w * i + b;
        }
        for a in act.a.iter_mut() {
            *a = tanh_fast(*a);
        }
        b2 + dot(&act.a, w2)
    }

    /// Normalised output o and, if `slope`, do/di, without a heap buffer (chunks of 64 neurons
    /// on the stack).
    #[inline]
    fn output_chunked(&self, i: f64, slope: bool) -> (f64, f64) {
        const C: usize = CHUNK;
        let (w1, b1, w2, b2) = self.layers();
        let (mut o, mut s) = (b2, 0.0);
        let mut z = [0.0; C];
        for ((w1, b1), w2) in w1.chunks(C).zip(b1.chunks(C)).zip(w2.chunks(C)) {
            let z = &mut z[..w1.len()];
            for ((z, w), b) in z.iter_mut().zip(w1).zip(b1) {
                *z = w * i + b;
            }
            for z in z.iter_mut() {
                *z = tanh_fast(*z);
            }
            o += dot(z, w2);
            if slope {
                s += z
                    .iter()
                    .zip(w2)
                    .zip(w1)
                    .map(|((a, v), w)| v * (1.0 - a * a) * w)
                    .sum::<f64>();
            }
        }
        (o, s)
    }

    /// Normalised output o and do/di in one pass (no heap buffer).
    #[inline]
    pub fn output_and_slope(&self, i: f64) -> (f64, f64) {
        self.output_chunked(i, true)
    }

    /// Normalised output o only.
    #[inline]
    pub fn output(&self, i: f64) -> f64 {
        self.output_chunked(i, false).0
    }

    /// ϱ = σ_ϱ o + ϱ̄ → ρ.
    #[inline]
    fn rho_of_output(&self, o: f64) -> (f64, f64) {
        let varrho = self.norm.out_std * o + self.norm.out_mean;
        (self.norm.untransform(varrho), varrho)
    }

    /// Density NN(r, ξ) [kg/m³] at radius `r_m` (eq. 28).
    pub fn density(&self, r_m: f64) -> f64 {
        self.rho_of_output(self.output(self.input(r_m))).0
    }

    /// Density and its radius derivative dρ/dr [kg/m⁴].
    pub fn density_and_slope(&self, r_m: f64) -> (f64, f64) {
        let (o, s) = self.output_and_slope(self.input(r_m));
        let (rho, varrho) = self.rho_of_output(o);
        let drho_do = -2.0 * LN10 * rho * varrho * self.norm.out_std;
        (rho, drho_do * s / self.norm.r_std_m)
    }

    /// Density at `r_m` and its gradient ∂ρ/∂ξ written into `grad` (length 3H + 1) scaled by
    /// `weight` and *added* (so that loss gradients accumulate): `grad += weight·∂ρ/∂ξ`.
    /// Returns ρ. Backpropagation as in the module documentation.
    pub fn density_gradient(
        &self,
        r_m: f64,
        weight: f64,
        grad: &mut [f64],
        act: &mut Activations,
    ) -> f64 {
        let i = self.input(r_m);
        let o = self.forward(i, act);
        let (rho, varrho) = self.rho_of_output(o);
        let g_o = weight * (-2.0 * LN10 * rho * varrho * self.norm.out_std);
        self.backward_output(i, g_o, grad, act);
        rho
    }

    /// Add `g_o·∂o/∂ξ` to `grad`, given the activations of the forward pass at input `i`.
    #[inline]
    pub fn backward_output(&self, i: f64, g_o: f64, grad: &mut [f64], act: &Activations) {
        let h = self.hidden;
        let w2 = &self.xi[2 * h..3 * h];
        let (gw1, rest) = grad.split_at_mut(h);
        let (gb1, rest) = rest.split_at_mut(h);
        let (gw2, gb2) = rest.split_at_mut(h);
        gb2[0] += g_o;
        for j in 0..h {
            let a = act.a[j];
            gw2[j] += g_o * a;
            let gz = g_o * w2[j] * (1.0 - a * a);
            gb1[j] += gz;
            gw1[j] += gz * i;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_tanh_matches_std() {
        let mut worst: f64 = 0.0;
        let mut x = -25.0;
        while x < 25.0 {
            worst = worst.max((tanh_fast(x) - x.tanh()).abs());
            x += 1.234e-3;
        }
        for x in [
            0.0, -0.0, 1e-300, -1e-20, 1e-8, 0.3465, 19.99, 20.0, 700.0, -1e300,
        ] {
            worst = worst.max((tanh_fast(x) - x.tanh()).abs());
        }
        assert!(worst < 3e-16, "{worst}");
        assert!(tanh_fast(f64::INFINITY) == 1.0 && tanh_fast(f64::NEG_INFINITY) == -1.0);
    }

    #[test]
    fn all_forward_passes_agree() {
        let h = 150; // more than one chunk
        let xi: Vec<f64> = (0..3 * h + 1)
            .map(|k| ((k * 37 % 101) as f64 - 50.0) / 40.0)
            .collect();
        let norm = Normalisation {
            r_mean_m: 3.45e6,
            r_std_m: 2e4,
            out_mean: 2.0,
            out_std: 0.4,
            shift: 0.0,
        };
        let net = DensityNetwork::new(h, xi, norm).unwrap();
        let mut act = Activations::default();
        for i in [-2.0, -0.3, 0.0, 0.7, 1.9] {
            // Same terms, summed in a different grouping: equal to round-off.
            let o = net.output(i);
            assert!((o - net.forward(i, &mut act)).abs() < 1e-13 * o.abs().max(1.0));
            assert_eq!(o, net.output_and_slope(i).0);
        }
    }
}
