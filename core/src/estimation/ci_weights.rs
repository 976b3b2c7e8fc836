//! The optimal covariance-intersection weights (seed 000 §3.3): minimum normalised trace or
//! determinant of the fused covariance over the simplex `Σ ω_i = 1, ω_i ≥ 0`, by an active-set
//! projected Newton method on the scaled information matrices that [`super::ci`] prepares.

use super::ci_scaling::not_pd;
use super::error::EstimationError;
use super::spd::{cholesky, inverse_from_cholesky, lower_inverse};
use nalgebra::{Cholesky, Const, DMatrix, DVector, SMatrix};

/// Iteration cap of the optimal-weight Newton solver (it normally needs 3–10 iterations).
const MAX_ITER: usize = 60;

/// The Newton decrement `λ² = −gᵀd` at most which a full Newton step is followed by a chord
/// step (the same Hessian, a new gradient) instead of a Newton step (see [`optimal_weights`]).
const CHORD_DECREMENT: f64 = 1e-4;

/// The largest decrement (on the last Hessian) with which a chord step ends the search.
const CHORD_FINAL: f64 = 1e-7;

type Mat<const N: usize> = SMatrix<f64, N, N>;

/// Weights and, from the optimal-weight search, the Cholesky factor of `Σ ω_i Y_i` at them.
pub(super) type Weights<const N: usize> = (Vec<f64>, Option<Cholesky<f64, Const<N>>>);

/// Objective (and optionally gradient and Hessian in ω) of the optimal-weight problem on the
/// scaled information matrices. With `Y = Σ ω_i Y_i`, `M_i = Y⁻¹ Y_i`, `S_i = M_i Y⁻¹`:
/// * det: `f = −log det Y`, `∂f/∂ω_i = −tr(Y⁻¹Y_i) = −tr M_i`, `∂²f/∂ω_i∂ω_j = tr(M_i M_j)`;
/// * trace: `f = tr Y⁻¹`, `∂f/∂ω_i = −tr(Y⁻¹Y_iY⁻¹) = −tr S_i`,
///   `∂²f/∂ω_i∂ω_j = 2 tr(Y⁻¹Y_iY⁻¹Y_jY⁻¹) = 2 tr(M_i S_j)`.
///
/// The det derivatives are formed on the symmetric `B_i = T Y_i Tᵀ`, `T = L⁻¹` for the Cholesky
/// factor `Y = L Lᵀ` (so `Y⁻¹ = TᵀT`): `tr M_i = tr B_i` and `tr(M_i M_j) = ⟨B_i, B_j⟩_F`. With
/// `T` triangular and only `B_i`'s lower triangle formed, that is ≈ N³ (1/6 + 4/6 n) multiply–adds
/// and half-size Frobenius products, against N³ (1/3 + n) for `Y⁻¹` and the products `Y⁻¹Y_i`.
///
/// `m`, `s` (trace) and `b` (det, lower triangles by columns) are work space; `g`, `h` receive
/// the gradient and Hessian.
struct Problem<'a, const N: usize> {
    ys: &'a [Mat<N>],
    trace: bool,
    m: Vec<Mat<N>>,
    s: Vec<Mat<N>>,
    b: Vec<[[f64; N]; N]>,
    g: Vec<f64>,
    h: DMatrix<f64>,
}

/// Factorisation of `Y(ω)`: Cholesky factor, objective value and (trace objective) `Y⁻¹`.
struct Factor<const N: usize> {
    chol: Cholesky<f64, Const<N>>,
    f: f64,
    yinv: Option<Mat<N>>,
}

impl<'a, const N: usize> Problem<'a, N> {
    fn new(ys: &'a [Mat<N>], trace: bool) -> Self {
        let (n, z) = (ys.len(), Mat::<N>::zeros());
        let (g, h) = (vec![0.0; n], DMatrix::zeros(n, n));
        let (mats, lowers) = if trace { (n, 0) } else { (0, n) };
        Problem {
            ys,
            trace,
            m: vec![z; mats],
            s: vec![z; mats],
            b: vec![[[0.0; N]; N]; lowers],
            g,
            h,
        }
    }

    /// Factor `Y(ω)` and evaluate `f`; `None` if not positive definite.
    fn factor(&self, w: &[f64]) -> Option<Factor<N>> {
        // Σ ω_i Y_i accumulated in place, entry by entry: the same sums as adding the scaled
        // matrices, without the temporaries.
        let mut y = Mat::<N>::zeros();
        for (yi, wi) in self.ys.iter().zip(w) {
            for (acc, v) in y.as_mut_slice().iter_mut().zip(yi.as_slice()) {
                *acc += v * *wi;
            }
        }
        let chol = cholesky(&y)?;
        let yinv = self.trace.then(|| inverse_from_cholesky(chol.l_dirty()));
        let f = match &yinv {
            Some(yi) => yi.trace(),
            None => -2.0 * chol.l_dirty().diagonal().map(f64::ln).sum(),
        };
        f.is_finite().then_some(Factor { chol, f, yinv })
    }

    /// Gradient `g` and Hessian `h` at a factorisation.
    fn derivatives(&mut self, fac: &Factor<N>) {
        match &fac.yinv {
            Some(yinv) => self.trace_derivatives(yinv),
            None => self.det_derivatives(fac),
        }
    }

    /// The det objective's gradient alone, `g_i = −tr(Y⁻¹Y_i) = −⟨Y⁻¹, Y_i⟩_F` from `Y⁻¹`
    /// (≈ N³/3 + n N² multiply–adds against ≈ N³ (1/6 + 4/6 n) for the Hessian too); `h` keeps
    /// the last Hessian (a chord step, see [`optimal_weights`]). `false` for the trace
    /// objective, which has no cheaper gradient.
    fn det_gradient(&mut self, fac: &Factor<N>) -> bool {
        if fac.yinv.is_some() {
            return false;
        }
        let yinv = inverse_from_cholesky(fac.chol.l_dirty());
        for (g, yi) in self.g.iter_mut().zip(self.ys) {
            *g = -yinv.dot(yi);
        }
        true
    }

    /// The trace objective's derivatives from `Y⁻¹`.
    fn trace_derivatives(&mut self, yinv: &Mat<N>) {
        let (m, s) = (&mut self.m, &mut self.s);
        for i in 0..self.ys.len() {
            m[i] = yinv * self.ys[i];
            s[i] = m[i] * yinv;
            self.g[i] = -s[i].trace();
            let mt = m[i].transpose();
            for (j, sj) in s[..=i].iter().enumerate() {
                // 2 tr(M_i S_j) = 2 Σ (M_iᵀ)_kl (S_j)_kl.
                let hij = 2.0 * mt.dot(sj);
                (self.h[(i, j)], self.h[(j, i)]) = (hij, hij);
            }
        }
    }

    /// The det objective's derivatives from `B_i = T Y_i Tᵀ` (see [`Problem`]).
    #[allow(clippy::needless_range_loop)] // columns of several arrays at one index
    fn det_derivatives(&mut self, fac: &Factor<N>) {
        // t[k][r] = T_rk, zero for r < k.
        let t = lower_inverse(fac.chol.l_dirty());
        for i in 0..self.ys.len() {
            // y[c][k] = (Y_i)_kc.
            let y = &self.ys[i].data.0;
            // C = T Y_i by columns: C[:, c] = Σ_k T[:, k] (Y_i)_kc, T[:, k] non-zero from row k.
            let mut cm = [[0.0f64; N]; N];
            for c in 0..N {
                for k in 0..N {
                    let v = y[c][k];
                    for r in k..N {
                        cm[c][r] += t[k][r] * v;
                    }
                }
            }
            // B = C Tᵀ, lower triangle: B[r, s] = Σ_{k ≤ s} C[r, k] T_sk for r ≥ s.
            let b = &mut self.b[i];
            let mut trace = 0.0;
            for s in 0..N {
                b[s] = [0.0; N];
                for k in 0..=s {
                    let v = t[k][s];
                    for r in s..N {
                        b[s][r] += cm[k][r] * v;
                    }
                }
                trace += b[s][s];
            }
            self.g[i] = -trace;
            for j in 0..=i {
                // ⟨B_i, B_j⟩_F from the lower triangles: diagonal once, the rest twice.
                let (bi, bj) = (&self.b[i], &self.b[j]);
                let (mut diag, mut off) = (0.0, 0.0);
                for s in 0..N {
                    diag += bi[s][s] * bj[s][s];
                    for r in s + 1..N {
                        off += bi[s][r] * bj[s][r];
                    }
                }
                let hij = diag + 2.0 * off;
                (self.h[(i, j)], self.h[(j, i)]) = (hij, hij);
            }
        }
    }
}

/// Newton direction on the face `{Σ_{i∈free} d_i = 0}`: solve the KKT system
/// `[H_FF + δI, 1; 1ᵀ, 0] [d; λ] = [−g_F; 0]` (δ a 1e-12 relative damping for flat directions).
/// `None` if the solve fails.
fn newton_direction(free: &[usize], g: &[f64], h: &DMatrix<f64>) -> Option<Vec<f64>> {
    let m = free.len();
    let hmax = free.iter().map(|&i| h[(i, i)]).fold(0.0, f64::max);
    let delta = 1e-12 * hmax + f64::MIN_POSITIVE;
    let mut k = DMatrix::<f64>::zeros(m + 1, m + 1);
    let mut rhs = DVector::<f64>::zeros(m + 1);
    for (r, &i) in free.iter().enumerate() {
        for (c, &j) in free.iter().enumerate() {
            k[(r, c)] = h[(i, j)] + if r == c { delta } else { 0.0 };
        }
        k[(r, m)] = 1.0;
        k[(m, r)] = 1.0;
        rhs[r] = -g[i];
    }
    let sol = k.lu().solve(&rhs)?;
    sol.iter()
        .all(|v| v.is_finite())
        .then(|| sol.rows(0, m).iter().copied().collect())
}

/// Active-set projected Newton method on the simplex for the convex objectives of
/// [`Problem`]. Starts from `start` (renormalised; its zero weights start inactive) or uniform
/// weights; on each face takes damped Newton steps with an
/// Armijo backtracking line search and a ratio test that drops weights reaching 0; when the
/// face is stationary (projected gradient ≤ 1e-13 ‖g‖∞, Newton step ≤ 1e-12, or a final full
/// Newton step with decrement ≤ 1e-12 (1 + |f|)), re-admits the zero weight whose KKT
/// multiplier is most violated. A full Newton step (exact derivatives) of decrement
/// ≤ [`CHORD_DECREMENT`] is followed by a chord step (the same Hessian, the gradient at the new
/// point), which ends the search when its own decrement is ≤ [`CHORD_FINAL`] and its full step
/// stays in the simplex (otherwise that point gets exact derivatives). Weights are accurate to
/// ~1e-7 (a test compares them with the pure Newton search's, ~1e-9), far below the 1e-6 the
/// other tests demand. At the iteration cap the current (feasible) iterate is returned: CI is
/// consistent for any admissible ω, so this is safe.
///
/// Also returns the Cholesky factor of `Σ ω_i Y_i` at the returned weights (`None` for one
/// estimate), which the fusion reuses.
pub(super) fn optimal_weights<const N: usize>(
    ys: &[Mat<N>],
    trace: bool,
    start: Option<&[f64]>,
) -> Result<Weights<N>, EstimationError> {
    search(ys, trace, start, CHORD_DECREMENT)
}

/// [`optimal_weights`] with chord steps after full Newton steps of decrement ≤
/// `chord_decrement` (none for 0).
fn search<const N: usize>(
    ys: &[Mat<N>],
    trace: bool,
    start: Option<&[f64]>,
    chord_decrement: f64,
) -> Result<Weights<N>, EstimationError> {
    let n = ys.len();
    if n == 1 {
        return Ok((vec![1.0], None));
    }
    let mut prob = Problem::new(ys, trace);
    let mut w = vec![1.0 / n as f64; n];
    if let Some(s) = start {
        let sum: f64 = s.iter().sum();
        w = s.iter().map(|v| v / sum).collect();
    }
    let (mut trial, mut active) = (vec![0.0; n], w.iter().map(|v| *v > 0.0).collect::<Vec<_>>());
    let not_pd_sum = || not_pd("CI weighted information".into());
    let mut fac = prob.factor(&w).ok_or_else(not_pd_sum)?;
    // Whether the last iteration took a full Newton step, with exact derivatives, whose
    // decrement was at most CHORD_DECREMENT: the next one is then a chord step.
    let mut chord = false;
    for _ in 0..MAX_ITER {
        let chord_step = chord && prob.det_gradient(&fac);
        if !chord_step {
            prob.derivatives(&fac);
        }
        chord = false;
        let (f, g) = (fac.f, prob.g.clone());
        let free: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
        let gmax = g.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
        let mean_g = |set: &[usize]| set.iter().map(|&i| g[i]).sum::<f64>() / set.len() as f64;
        let mu = mean_g(&free);
        let pg = free.iter().map(|&i| (g[i] - mu).abs()).fold(0.0, f64::max);
        let tilted = free.len() > 1 && pg > 1e-13 * gmax;
        let dir = tilted
            .then(|| newton_direction(&free, &g, &prob.h))
            .flatten();
        let mut stationary = dir.is_none();
        if let Some(d) = dir {
            let slope: f64 = free.iter().zip(&d).map(|(&i, di)| g[i] * di).sum();
            let dmax = d.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
            let (mut amax, mut block) = (f64::INFINITY, None);
            for (&i, &di) in free.iter().zip(&d) {
                if di < 0.0 && -w[i] / di < amax {
                    amax = -w[i] / di;
                    block = Some(i);
                }
            }
            let small = -slope <= 1e-12 * (1.0 + f.abs());
            // A chord step ends the search when its decrement is tiny and its full step stays
            // inside the simplex; otherwise this point gets exact derivatives after all.
            let certified = chord_step && slope < 0.0 && -slope <= CHORD_FINAL && amax > 1.0;
            if chord_step && !certified && !small {
                continue;
            }
            stationary = small || certified || dmax <= 1e-12 || slope.is_nan() || slope >= 0.0;
            if !stationary || small || certified {
                // Near the optimum (`small`) the full Newton step is taken without a line search,
                // whose Armijo test would only see round-off.
                let mut alpha = amax.min(1.0);
                let mut accepted = false;
                for _ in 0..40 {
                    trial.copy_from_slice(&w);
                    for (&i, di) in free.iter().zip(&d) {
                        trial[i] = (w[i] + alpha * di).max(0.0);
                    }
                    let hit = (alpha == amax).then_some(block).flatten();
                    if let Some(b) = hit {
                        trial[b] = 0.0;
                    }
                    let sum: f64 = trial.iter().sum();
                    trial.iter_mut().for_each(|t| *t /= sum);
                    let cand = prob
                        .factor(&trial)
                        .filter(|c| small || certified || c.f <= f + 1e-4 * alpha * slope);
                    if let Some(c) = cand {
                        fac = c;
                        w.copy_from_slice(&trial);
                        if let Some(b) = hit {
                            active[b] = false;
                        }
                        accepted = true;
                        chord = !chord_step
                            && !small
                            && alpha == 1.0
                            && hit.is_none()
                            && -slope <= chord_decrement;
                        break;
                    }
                    alpha *= 0.5;
                }
                stationary |= !accepted;
            }
        }
        if stationary {
            let mu = mean_g(&(0..n).filter(|&i| active[i]).collect::<Vec<_>>());
            let worst = (0..n)
                .filter(|&i| !active[i])
                .min_by(|&i, &j| g[i].total_cmp(&g[j]));
            match worst {
                Some(j) if g[j] < mu - 1e-12 * gmax => active[j] = true,
                _ => break,
            }
        }
    }
    Ok((w, Some(fac.chol)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    fn spd(seed: f64) -> Matrix3<f64> {
        let a = Matrix3::from_fn(|r, c| ((r * 3 + c) as f64 * seed).sin());
        a * a.transpose() + Matrix3::identity() * 0.3
    }

    /// Warm-started searches (from a perturbed optimum, as the filter starts each epoch from the
    /// last one) with chord steps reach the optimum of the search without them to 1e-7.
    #[test]
    fn chord_steps_reach_the_newton_optimum() {
        // Four estimates, each much the most informative along its own axis: every weight is
        // positive at the optimum.
        let ys: Vec<SMatrix<f64, 5, 5>> = (0..4)
            .map(|i| {
                let g = SMatrix::<f64, 5, 5>::from_fn(|r, c| ((r * 5 + c + 7 * i) as f64).sin());
                let mut y = g * g.transpose() * 0.2 + SMatrix::<f64, 5, 5>::identity() * 0.3;
                y[(i, i)] += 6.0;
                y
            })
            .collect();
        let (exact, _) = search(&ys, false, None, 0.0).unwrap();
        let mut worst = 0.0f64;
        for k in 0..40 {
            let tilt = |i: usize| 1.0 + 0.02 * ((k * 7 + i * 3) as f64).sin();
            let start: Vec<f64> = exact.iter().enumerate().map(|(i, w)| w * tilt(i)).collect();
            let (chord, _) = search(&ys, false, Some(&start), CHORD_DECREMENT).unwrap();
            let (newton, _) = search(&ys, false, Some(&start), 0.0).unwrap();
            for (a, b) in chord.iter().zip(&newton) {
                worst = worst.max((a - b).abs());
            }
        }
        assert!(worst < 1e-7, "chord vs Newton weights differ by {worst:e}");
        assert!(
            exact.iter().all(|w| *w > 0.01),
            "an interior optimum: {exact:?}"
        );
    }

    #[test]
    fn analytic_gradient_and_hessian_match_finite_differences() {
        let ys = [spd(1.3), spd(2.1), spd(0.7)];
        for trace in [false, true] {
            let mut prob = Problem::new(&ys, trace);
            let mut deriv = |w: &[f64]| {
                let fac = prob.factor(w).unwrap();
                prob.derivatives(&fac);
                (fac.f, prob.g.clone(), prob.h.clone())
            };
            let (w, eps) = ([0.5, 0.3, 0.2], 1e-6);
            let (_, g, h) = deriv(&w);
            for i in 0..3 {
                let (mut wp, mut wm) = (w, w);
                (wp[i], wm[i]) = (w[i] + eps, w[i] - eps);
                let ((fp, gp, _), (fm, gm, _)) = (deriv(&wp), deriv(&wm));
                let fd = (fp - fm) / (2.0 * eps);
                assert!(
                    (fd - g[i]).abs() < 1e-6 * (1.0 + g[i].abs()),
                    "{fd} vs {}",
                    g[i]
                );
                for j in 0..3 {
                    let fd = (gp[j] - gm[j]) / (2.0 * eps);
                    assert!(
                        (fd - h[(i, j)]).abs() < 1e-5 * (1.0 + fd.abs()),
                        "hess {i}{j}"
                    );
                }
            }
        }
    }
}
