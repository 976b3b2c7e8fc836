//! Observability and Fisher information: exactness of the Lie-derivative matrix, agreement of the
//! three methods, the scenarios' δ(t), unobservable configurations, and seed 002 Table 1.

use entrynav::math::Real;
use entrynav::math::fd_jacobian;
use entrynav::observability::approx::output_jacobian;
use entrynav::observability::fisher::{det_by_triples, information, range_fim, summarize};
use entrynav::observability::*;
use entrynav::scenario::{Scenario, ScenarioConfig};
use nalgebra::{DMatrix, SMatrix, SVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

fn build(cfg: ScenarioConfig) -> Scenario {
    Scenario::build(cfg, &entrynav::files::no_files).unwrap()
}

fn scenario(name: &str) -> Scenario {
    build(ScenarioConfig::builtin(name).unwrap())
}

fn system<'a>(s: &'a Scenario, p: &AnalysisPoint) -> ScenarioSystem<'a> {
    ScenarioSystem {
        model: s.filter_model(),
        measurement: &s.measurement,
        channels: s.channels.iter().map(|c| c.channel).collect(),
        beacons: p.beacons.clone(),
        t: p.t,
        bank: s.truth_bank,
    }
}

/// Row-wise relative agreement of two matrices (each row against its own norm).
fn rows_close(a: &DMatrix<f64>, b: &DMatrix<f64>, rel: f64) -> bool {
    (0..a.nrows()).all(|r| {
        let scale = a.row(r).norm().max(b.row(r).norm()).max(1e-300);
        (a.row(r) - b.row(r)).norm() <= rel * scale
    })
}

/// `L_f^1 h(x) = J_h(x)·f(x)` by first-order AD only (an independent path to the first Lie
/// derivative).
fn first_lie<const N: usize>(sys: &ScenarioSystem, x: &SVector<f64, N>) -> DMatrix<f64> {
    let jh = output_jacobian::<_, N>(sys, x);
    let f = ObservedSystem::<N>::f(sys, x);
    &jh * DMatrix::from_column_slice(N, 1, f.as_slice())
}

fn check_lie_against_fd<const N: usize>(name: &str, t: f64) {
    let s = scenario(name);
    let points = analysis_points(&s, 1.0).unwrap();
    let p = points.iter().find(|p| (p.t - t).abs() < 1e-9).unwrap();
    let sys = system(&s, p);
    let m = sys.channels.len();
    let x0 = SVector::<f64, N>::from_column_slice(&p.state);
    let lie = lie_derivatives::<_, N>(&sys, &x0);
    // Steps of 1 % of each state's characteristic size (10 m, 1e-5 rad, 0.01 m/s, …): small
    // enough for the truncation error, large enough that rounding in |r| (1 ulp ≈ 5e-10 m) stays
    // negligible.
    let scaling = Scaling::characteristic(s.filter_model());
    let steps = SVector::<f64, N>::from_iterator(scaling.state.iter().map(|v| 1e-2 * v));

    // Order 0 values and order-0/1 rows against central differences.
    let h = |x: &SVector<f64, N>| {
        let mut y = vec![0.0; m];
        ObservedSystem::<N>::h(&sys, x, &mut y);
        DMatrix::from_column_slice(m, 1, &y)
    };
    let fd_rows = |g: &dyn Fn(&SVector<f64, N>) -> DMatrix<f64>| {
        let mut out = DMatrix::zeros(m, N);
        for i in 0..N {
            let (mut xp, mut xm) = (x0, x0);
            xp[i] += steps[i];
            xm[i] -= steps[i];
            out.set_column(i, &((g(&xp) - g(&xm)) / (2.0 * steps[i])).column(0));
        }
        out
    };
    let o0 = lie.matrix.rows(0, m).into_owned();
    let o1 = lie.matrix.rows(m, m).into_owned();
    let fd0 = fd_rows(&h);
    assert!(
        rows_close(&o0, &fd0, 1e-5),
        "{name}: ∇L⁰h vs FD\n{o0:e}\n{fd0:e}"
    );
    assert!(
        rows_close(&o1, &fd_rows(&|x| first_lie::<N>(&sys, x)), 1e-4),
        "{name}: ∇L¹h vs FD of J_h·f"
    );
    // L¹ and L² values: along-flow differences of h and of L¹h.
    let f0 = ObservedSystem::<N>::f(&sys, &x0);
    let eps = 1e-3;
    let along = |g: &dyn Fn(&SVector<f64, N>) -> DMatrix<f64>| {
        (g(&(x0 + f0 * eps)) - g(&(x0 - f0 * eps))) / (2.0 * eps)
    };
    let l1_fd = along(&h);
    let l2_fd = along(&|x| first_lie::<N>(&sys, x));
    for j in 0..m {
        let (l1, l2) = (lie.values[(1, j)], lie.values[(2, j)]);
        assert!(
            (l1 - l1_fd[j]).abs() <= 1e-6 * l1.abs().max(1e-9),
            "{name} L¹h_{j}: {l1} vs {}",
            l1_fd[j]
        );
        assert!(
            (l2 - l2_fd[j]).abs() <= 1e-5 * l2.abs().max(1e-9),
            "{name} L²h_{j}: {l2} vs {}",
            l2_fd[j]
        );
    }
    // The order-0 values are h itself.
    let h0 = h(&x0);
    assert!((lie.values.row(0).transpose() - &h0).norm() <= 1e-14 * h0.norm());
}

#[test]
fn exact_lie_matches_finite_differences_of_the_first_lie_derivatives() {
    check_lie_against_fd::<6>("ground-beacons-3", 100.0);
    check_lie_against_fd::<8>("four-beacon-fusion-paper", 50.0);
    check_lie_against_fd::<11>("four-beacon-fusion", 50.0);
    check_lie_against_fd::<6>("msl-pressure-orbiter", 30.0);
    check_lie_against_fd::<8>("msl-airdata", 60.0);
}

/// ẋ = A x + b, y = C x (+ a quadratic output when `quadratic`).
struct Affine {
    a: SMatrix<f64, 4, 4>,
    b: SVector<f64, 4>,
    c: SMatrix<f64, 2, 4>,
    quadratic: bool,
}

impl ObservedSystem<4> for Affine {
    fn outputs(&self) -> usize {
        if self.quadratic { 3 } else { 2 }
    }
    fn f<T: Real>(&self, x: &SVector<T, 4>) -> SVector<T, 4> {
        SVector::from_fn(|i, _| {
            (0..4).fold(T::from(self.b[i]), |acc, j| acc + x[j] * self.a[(i, j)])
        })
    }
    fn h<T: Real>(&self, x: &SVector<T, 4>, out: &mut [T]) {
        for (r, o) in out.iter_mut().take(2).enumerate() {
            *o = (0..4).fold(T::from(0.0), |acc, j| acc + x[j] * self.c[(r, j)]);
        }
        if self.quadratic {
            out[2] = x[0] * x[0] * 0.5 + x[1] * x[2] - x[3] * x[3];
        }
    }
}

fn affine(quadratic: bool) -> Affine {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut z = || -> f64 { StandardNormal.sample(&mut rng) };
    Affine {
        a: SMatrix::from_fn(|_, _| 0.5 * z()),
        b: SVector::from_fn(|_, _| z()),
        c: SMatrix::from_fn(|_, _| z()),
        quadratic,
    }
}

#[test]
fn three_methods_agree_exactly_on_a_linear_system() {
    let sys = affine(false);
    let x0 = SVector::from([0.3, -1.2, 0.7, 2.0]);
    let lie = lie_matrix(&sys, &x0);
    let quad = quadratic_matrix(&sys, &x0);
    let lin = linear_matrix(&sys, &x0);
    // Reference [C; CA; CA²; CA³].
    let mut reference = DMatrix::zeros(8, 4);
    let mut block = sys.c;
    for k in 0..4 {
        reference.view_mut((2 * k, 0), (2, 4)).copy_from(&block);
        block *= sys.a;
    }
    for (o, name) in [(&lie, "lie"), (&quad, "quadratic"), (&lin, "linear")] {
        assert!(
            rows_close(o, &reference, 1e-13),
            "{name}:\n{o}\nvs\n{reference}"
        );
    }
    let d: Vec<f64> = [&lie, &quad, &lin]
        .iter()
        .map(|o| degree(o).unwrap().delta)
        .collect();
    assert!(d[0] > 0.0 && (d[1] - d[0]).abs() < 1e-12 * d[0] && (d[2] - d[0]).abs() < 1e-12 * d[0]);
}

#[test]
fn quadratic_method_is_exact_for_affine_dynamics_and_quadratic_output() {
    // With eq. 13's convention kept through the recursion (see `approx`), the quadratic method is
    // exact here; the linearisation is not.
    let sys = affine(true);
    let x0 = SVector::from([0.3, -1.2, 0.7, 2.0]);
    let lie = lie_matrix(&sys, &x0);
    let quad = quadratic_matrix(&sys, &x0);
    let lin = linear_matrix(&sys, &x0);
    assert!(
        rows_close(&quad, &lie, 1e-12),
        "quadratic:\n{quad}\nlie:\n{lie}"
    );
    assert!(!rows_close(&lin, &lie, 1e-3));
}

fn agree_within(a: f64, b: f64, factor: f64) -> bool {
    a > 0.0 && b > 0.0 && a / b < factor && b / a < factor
}

#[test]
fn ground_beacons_3_methods_agree_within_an_order_of_magnitude() {
    let s = scenario("ground-beacons-3");
    let points = analysis_points(&s, 1.0).unwrap();
    assert_eq!(points.len(), 241);
    let scaling = Scaling::characteristic(s.filter_model());
    let set = ChannelSet::centralised(&s);
    let series: Vec<DegreeSeries> = [Method::Lie, Method::Quadratic, Method::Linear]
        .into_iter()
        .map(|m| degree_series(&s, &points, &set, m, &scaling).unwrap())
        .collect();
    for k in 0..points.len() {
        let lie = series[0].samples[k];
        assert_eq!(lie.raw.rank, 6);
        for other in &series[1..] {
            let o = other.samples[k];
            assert!(
                agree_within(lie.raw.delta, o.raw.delta, 10.0),
                "raw t = {}",
                lie.t
            );
            assert!(
                agree_within(lie.scaled.delta, o.scaled.delta, 10.0),
                "scaled t = {}",
                lie.t
            );
        }
    }
    // Seed 002 §5.1: minimum at the start of the entry, 1.4e-8…2.9e-7 in SI units.
    let raw = series[0].summary(false).unwrap();
    assert_eq!(raw.t_min_s, 0.0);
    assert!(
        raw.min > 1e-9 && raw.min < 1e-7 && raw.max > 1e-7 && raw.max < 1e-6,
        "{raw:?}"
    );
}

#[test]
fn four_beacon_fusion_centralised_beats_every_subsystem() {
    // The paper's 8-state system and ours with the three accelerometer biases.
    for name in ["four-beacon-fusion-paper", "four-beacon-fusion"] {
        centralised_beats_every_subsystem(name);
    }
}

fn centralised_beats_every_subsystem(name: &str) {
    let s = scenario(name);
    let n = s.filter_model().state_dim();
    let points = analysis_points(&s, 1.0).unwrap();
    let scaling = Scaling::characteristic(s.filter_model());
    let central = degree_series(
        &s,
        &points,
        &ChannelSet::centralised(&s),
        Method::Lie,
        &scaling,
    )
    .unwrap();
    let subs = ChannelSet::subsystems(&s);
    assert_eq!(subs.len(), 4);
    for set in &subs {
        assert_eq!(set.channels.len(), 4, "3 accelerometer axes + 1 range");
        let sub = degree_series(&s, &points, set, Method::Lie, &scaling).unwrap();
        for (c, d) in central.samples.iter().zip(&sub.samples) {
            assert!(
                c.raw.delta > d.raw.delta && c.scaled.delta > d.scaled.delta,
                "{} t = {}",
                set.name,
                c.t
            );
            // IMU + one range on a non-rotating planet: rotating the whole state about the
            // planet-centre–beacon axis changes no measurement, so O has rank ≤ n − 1 exactly.
            assert!(d.scaled.rank < n && d.raw.rank < n, "{name}");
            assert_eq!(d.scaled.delta, 0.0);
        }
    }
}

#[test]
fn one_beacon_is_reported_unobservable_without_nan() {
    for name in ["four-beacon-fusion-paper", "four-beacon-fusion"] {
        one_beacon_unobservable(name);
    }
}

fn one_beacon_unobservable(name: &str) {
    let mut cfg = ScenarioConfig::builtin(name).unwrap();
    cfg.beacons.truncate(1);
    let s = build(cfg);
    let n = s.filter_model().state_dim();
    let points = analysis_points(&s, 20.0).unwrap();
    let scaling = Scaling::characteristic(s.filter_model());
    for m in [Method::Lie, Method::Quadratic, Method::Linear] {
        let ser = degree_series(&s, &points, &ChannelSet::centralised(&s), m, &scaling).unwrap();
        for d in &ser.samples {
            for g in [d.raw, d.scaled] {
                assert!(g.delta.is_finite() && g.sigma_ratio.is_finite());
                if m == Method::Lie {
                    assert_eq!(g.delta, 0.0, "{name}");
                    assert!(g.rank < n, "{name}");
                }
            }
        }
    }
    // Rank-deficient and empty matrices directly.
    let z = degree(&DMatrix::zeros(6, 6)).unwrap();
    assert_eq!((z.delta, z.rank), (0.0, 0));
    let thin = degree(&DMatrix::from_element(2, 6, 1.0)).unwrap();
    assert_eq!((thin.delta, thin.rank, thin.sigma_min), (0.0, 1, 0.0));
    assert!(degree(&DMatrix::from_element(6, 6, f64::NAN)).is_err());
    // One-beacon FIM: rank 1, no inverse, finite bounds (seed 002 eq. 29–32).
    let f = summarize(&[[0.0, 0.6, 0.8]], &[100.0]).unwrap();
    assert_eq!((f.rank, f.trace_inverse, f.det), (1, None, 0.0));
    assert!((f.trace_lower_bound - 3.0 * 100.0 * 100.0).abs() < 1e-6);
}

#[test]
fn max_det_over_free_unit_vectors_is_n_over_3_cubed() {
    // Seed 002 Table 1 (σ = 1): 1, 2.3704, 4.6296, 8, 12.7037, 18.963.
    let table = [1.0, 2.3704, 4.6296, 8.0, 12.7037, 18.963];
    for (n, paper) in (3..=8).zip(table) {
        let best = max_det_directions(n, 6, 42 + n as u64);
        let bound = max_det_bound(n);
        assert!(
            (best.det - bound).abs() <= 1e-6 * bound,
            "N = {n}: {} vs {bound}",
            best.det
        );
        assert!(
            (best.det - paper).abs() <= 1e-4 * paper,
            "N = {n}: Table 1 {paper}"
        );
        assert!(
            best.directions
                .iter()
                .all(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1.0).abs() < 1e-12)
        );
        let sigma = vec![1.0; n];
        assert!((det_by_triples(&best.directions, &sigma) - best.det).abs() < 1e-9 * bound);
    }
}

#[test]
fn fim_det_never_exceeds_the_bound_and_cauchy_binet_holds() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut z = || -> f64 { StandardNormal.sample(&mut rng) };
    for trial in 0..300 {
        let n = 3 + trial % 6;
        let dirs: Vec<[f64; 3]> = (0..n)
            .map(|_| {
                let v = [z(), z(), z()];
                let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                [v[0] / r, v[1] / r, v[2] / r]
            })
            .collect();
        let unit = vec![1.0; n];
        let det = information(&dirs, &unit).determinant();
        assert!(det <= max_det_bound(n) * (1.0 + 1e-12), "N = {n}: {det}");
        assert!((geometry_index(&dirs) - det).abs() < 1e-10 * det.max(1.0));
        // With unequal sigmas: eq. 37 equals det F, and eq. 38 bounds it.
        let sigma: Vec<f64> = (0..n).map(|_| 50.0 + 10.0 * z().abs()).collect();
        let s = summarize(&dirs, &sigma).unwrap();
        let f = information(&dirs, &sigma);
        assert!((det_by_triples(&dirs, &sigma) - f.determinant()).abs() < 1e-9 * s.det);
        assert!(
            s.det <= s.det_upper_bound * (1.0 + 1e-12)
                && s.det_upper_bound <= s.det_max * (1.0 + 1e-12)
        );
        let tr_inv = s.trace_inverse.unwrap();
        assert!(
            tr_inv > s.trace_lower_bound
                && s.trace_lower_bound >= s.trace_lower_bound_best * (1.0 - 1e-12)
        );
    }
    // Range FIM from positions equals the information of the unit directions.
    let f = range_fim(
        &[1.0, 2.0, 3.0],
        &[[4.0, 6.0, 3.0], [1.0, 2.0, 3.0]],
        &[2.0, 1.0],
    );
    assert!((f - information(&[[-0.6, -0.8, 0.0]], &[2.0])).norm() < 1e-15);
}

#[test]
fn ground_beacons_3_geometry_index_follows_delta() {
    // Seed 002 Fig. 5–6: δ(t) and I(t) share the trend; compare their ranks in time.
    let s = scenario("ground-beacons-3");
    let points = analysis_points(&s, 5.0).unwrap();
    let scaling = Scaling::characteristic(s.filter_model());
    let d = degree_series(
        &s,
        &points,
        &ChannelSet::centralised(&s),
        Method::Lie,
        &scaling,
    )
    .unwrap();
    let fim = range_fim_series(&s, &points, None).unwrap();
    let delta = d.deltas(false);
    let index: Vec<f64> = fim.iter().map(|e| e.geometry_index).collect();
    assert!(
        fim.iter()
            .all(|e| e.beacons.len() == 3 && e.geometry_index <= 1.0)
    );
    let rho = spearman(&delta, &index);
    assert!(rho > 0.5, "Spearman correlation of δ and I: {rho}");
    // No range beacons: a clear error.
    let air = scenario("msl-airdata");
    let pts = analysis_points(&air, 50.0).unwrap();
    assert!(matches!(
        range_fim_series(&air, &pts, None),
        Err(ObservabilityError::NoBeacons { .. })
    ));
    assert!(analysis_points(&air, 0.0).is_err());
}

fn spearman(a: &[f64], b: &[f64]) -> f64 {
    let rank = |v: &[f64]| {
        let mut idx: Vec<usize> = (0..v.len()).collect();
        idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
        let mut r = vec![0.0; v.len()];
        for (k, &i) in idx.iter().enumerate() {
            r[i] = k as f64;
        }
        r
    };
    let (ra, rb) = (rank(a), rank(b));
    let n = a.len() as f64;
    let mean = (n - 1.0) / 2.0;
    let cov: f64 = ra
        .iter()
        .zip(&rb)
        .map(|(x, y)| (x - mean) * (y - mean))
        .sum();
    let var: f64 = ra.iter().map(|x| (x - mean).powi(2)).sum();
    cov / var
}

#[test]
fn fd_helper_agrees_with_ad_on_the_filter_model() {
    // The crate's FD helper agrees with AD on the filter model (sanity of the step choice used above).
    let s = scenario("ground-beacons-3");
    let x = SVector::<f64, 6>::from_column_slice(&s.onboard.initial_estimate);
    let (_, j) = s.filter_model().jacobian(&x, 0.0);
    let steps = SVector::<f64, 6>::from_iterator(x.iter().map(|v| 1e-6 * v.abs().max(1e-3)));
    let fd = fd_jacobian(|y| s.filter_model().rhs(y, 0.0), &x, &steps);
    assert!((j - fd).abs().max() < 1e-4 * j.abs().max());
}

/// Pendulum ẋ1 = x2, ẋ2 = −sin x1, y = x1: closed-form Lie derivatives to order 4.
struct Pendulum;

impl ObservedSystem<5> for Pendulum {
    fn outputs(&self) -> usize {
        1
    }
    fn f<T: Real>(&self, x: &SVector<T, 5>) -> SVector<T, 5> {
        let z = T::from(0.0);
        SVector::from([x[1], -x[0].sin(), z, z, z])
    }
    fn h<T: Real>(&self, x: &SVector<T, 5>, out: &mut [T]) {
        out[0] = x[0];
    }
}

#[test]
fn exact_lie_derivatives_match_closed_form_to_order_four() {
    let (a, b) = (0.7_f64, -1.3_f64);
    let x0 = SVector::from([a, b, 0.0, 0.0, 0.0]);
    let lie = lie_derivatives(&Pendulum, &x0);
    let (s, c) = a.sin_cos();
    let values = [a, b, -s, -c * b, b * b * s + s * c];
    let grads = [
        [1.0, 0.0],
        [0.0, 1.0],
        [-c, 0.0],
        [s * b, -c],
        [b * b * c + c * c - s * s, 2.0 * b * s],
    ];
    for (k, (v, g)) in values.iter().zip(&grads).enumerate() {
        assert!((lie.values[(k, 0)] - v).abs() < 1e-14, "L^{k}");
        for (i, gi) in g.iter().enumerate() {
            assert!((lie.matrix[(k, i)] - gi).abs() < 1e-14, "∇L^{k}[{i}]");
        }
        assert!(lie.matrix[(k, 2)] == 0.0 && lie.matrix[(k, 4)] == 0.0);
    }
}
