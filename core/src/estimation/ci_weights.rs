//! The optimal covariance-intersection weights (seed 000 §3.3): minimum normalised trace or
//! determinant of the fused covariance over the simplex `Σ ω_i = 1, ω_i ≥ 0`, by an active-set
//! projected Newton method on the scaled information matrices that [`super::ci`] prepares.

use super::ci_scaling::not_pd;
use super::ci_weight_problem::{Factor, Problem};
use super::error::EstimationError;
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
        let mu = mean_gradient(&g, &free);
        let pg = free.iter().map(|&i| (g[i] - mu).abs()).fold(0.0, f64::max);
        let tilted = free.len() > 1 && pg > 1e-13 * gmax;
        let dir = tilted
            .then(|| newton_direction(&free, &g, &prob.h))
            .flatten();
        let mut stationary = dir.is_none();
        if let Some(d) = dir {
            let step = Step::along(&free, &d, &g, &w, f, chord_step, chord_decrement);
            // A chord step ends the search when its decrement is tiny and its full step stays
            // inside the simplex; otherwise this point gets exact derivatives after all.
            if chord_step && !step.certified && !step.small {
                continue;
            }
            let dmax = d.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
            let slope = step.slope;
            stationary =
                step.small || step.certified || dmax <= 1e-12 || slope.is_nan() || slope >= 0.0;
            if !stationary || step.small || step.certified {
                match line_search(&prob, &step, &mut w, &mut trial) {
                    Some((c, hit, next_chord)) => {
                        fac = c;
                        if let Some(b) = hit {
                            active[b] = false;
                        }
                        chord = next_chord;
                    }
                    None => stationary = true,
                }
            }
        }
        if stationary && !release_one(&g, &mut active, gmax) {
            break;
        }
    }
    Ok((w, Some(fac.chol)))
}

/// The mean of the gradient `g` over the weights `set`.
fn mean_gradient(g: &[f64], set: &[usize]) -> f64 {
    set.iter().map(|&i| g[i]).sum::<f64>() / set.len() as f64
}

/// A Newton (or chord) step of the weight search: the direction `d` on the `free` weights, its
/// slope `gᵀd`, the longest step `amax` that stays in the simplex and the weight it zeroes.
struct Step<'a> {
    free: &'a [usize],
    d: &'a [f64],
    f: f64,
    slope: f64,
    amax: f64,
    block: Option<usize>,
    /// The decrement is at round-off level: the full step is taken without a line search.
    small: bool,
    /// A chord step whose tiny decrement and inside full step end the search.
    certified: bool,
    chord_step: bool,
    chord_decrement: f64,
}

impl<'a> Step<'a> {
    /// The step along `d` from the weights `w` (objective `f`, gradient `g`).
    fn along(
        free: &'a [usize],
        d: &'a [f64],
        g: &[f64],
        w: &[f64],
        f: f64,
        chord_step: bool,
        chord_decrement: f64,
    ) -> Self {
        let slope: f64 = free.iter().zip(d).map(|(&i, di)| g[i] * di).sum();
        let (mut amax, mut block) = (f64::INFINITY, None);
        for (&i, &di) in free.iter().zip(d) {
            if di < 0.0 && -w[i] / di < amax {
                amax = -w[i] / di;
                block = Some(i);
            }
        }
        let small = -slope <= 1e-12 * (1.0 + f.abs());
        let certified = chord_step && slope < 0.0 && -slope <= CHORD_FINAL && amax > 1.0;
        Step {
            free,
            d,
            f,
            slope,
            amax,
            block,
            small,
            certified,
            chord_step,
            chord_decrement,
        }
    }
}

/// The backtracking (Armijo) line search along `step` from `w`, renormalised onto the simplex.
/// Near the optimum (`small`) the full Newton step is taken without it, whose Armijo test would
/// only see round-off. On success `w` holds the new weights; returns their factorisation, the
/// weight the step zeroed and whether the next step is a chord step.
fn line_search<const N: usize>(
    prob: &Problem<'_, N>,
    step: &Step<'_>,
    w: &mut [f64],
    trial: &mut [f64],
) -> Option<(Factor<N>, Option<usize>, bool)> {
    let mut alpha = step.amax.min(1.0);
    for _ in 0..40 {
        trial.copy_from_slice(w);
        for (&i, di) in step.free.iter().zip(step.d) {
            trial[i] = (w[i] + alpha * di).max(0.0);
        }
        let hit = (alpha == step.amax).then_some(step.block).flatten();
        if let Some(b) = hit {
            trial[b] = 0.0;
        }
        let sum: f64 = trial.iter().sum();
        trial.iter_mut().for_each(|t| *t /= sum);
        let cand = prob
            .factor(trial)
            .filter(|c| step.small || step.certified || c.f <= step.f + 1e-4 * alpha * step.slope);
        if let Some(c) = cand {
            w.copy_from_slice(trial);
            let chord = !step.chord_step
                && !step.small
                && alpha == 1.0
                && hit.is_none()
                && -step.slope <= step.chord_decrement;
            return Some((c, hit, chord));
        }
        alpha *= 0.5;
    }
    None
}

/// At a stationary point of the current face: free the inactive weight whose gradient is most
/// below the active ones' mean. `false` when there is none (the optimum).
fn release_one(g: &[f64], active: &mut [bool], gmax: f64) -> bool {
    let n = g.len();
    let mu = mean_gradient(g, &(0..n).filter(|&i| active[i]).collect::<Vec<_>>());
    let worst = (0..n)
        .filter(|&i| !active[i])
        .min_by(|&i, &j| g[i].total_cmp(&g[j]));
    match worst {
        Some(j) if g[j] < mu - 1e-12 * gmax => {
            active[j] = true;
            true
        }
        _ => false,
    }
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
