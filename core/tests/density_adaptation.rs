//! Density adaptation (seed 001): the network's gradients against finite differences, Adam,
//! covariance matching, reproducible training, the shipped network and onboard model, the three
//! filters' wiring and a short Monte Carlo check of the paper's qualitative result.

use entrynav::atmosphere::Atmosphere;
use entrynav::estimation::adaptive::*;
use entrynav::estimation::nav::ukf_ac::UkfAcNav;
use entrynav::estimation::nav::uskf_nn::UskfNnNav;
use entrynav::estimation::nav::{FilterKind, FilterStart, NavFilter, build_filter};
use entrynav::scenario::{DensityTrainingConfig, Scenario, ScenarioConfig};
use entrynav::sensors::channels::kinematics;
use entrynav::sim::density::density_eval::{DensityEvalOptions, evaluate_density_filters};
use entrynav::sim::density::training::{generate_data, train_density_networks};
use entrynav::sim::engine::start::initial_estimate;
use entrynav::sim::{run_seed, simulate_truth};
use nalgebra::SVector;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

fn scenario(name: &str) -> Arc<Scenario> {
    Arc::new(
        Scenario::build(
            ScenarioConfig::builtin(name).unwrap(),
            &entrynav::files::no_files,
        )
        .unwrap(),
    )
}

fn scenario_with(name: &str, edit: impl Fn(&mut ScenarioConfig)) -> Arc<Scenario> {
    let mut cfg = ScenarioConfig::builtin(name).unwrap();
    edit(&mut cfg);
    Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap())
}

/// Table 2's Q and Table 4's consider parameter: `msl-airdata-paper`'s filter noise (USKF-NN's own
/// load-scaled noise, `[filter.tuned.uskf-nn]`, dropped).
fn with_paper_noise(c: &mut ScenarioConfig) {
    let paper = ScenarioConfig::builtin("msl-airdata-paper").unwrap().filter;
    let (d, p) = (c.filter.density.as_mut().unwrap(), paper.density.unwrap());
    (d.consider_tau_s, d.consider_pss, d.consider_p0) =
        (p.consider_tau_s, p.consider_pss, p.consider_p0);
    c.filter.q_diag = paper.q_diag;
    c.filter.process_noise = paper.process_noise;
    c.filter.tuned = paper.tuned;
}

fn builtin_set(name: &str) -> DensityNetworkSet {
    NetworkFile::from_toml_str(builtin_network_toml(name).unwrap(), name)
        .unwrap()
        .to_set()
        .unwrap()
}

/// A random 1-20-1 network with the msl-airdata normalisation.
fn random_network(seed: u64) -> DensityNetwork {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let h = 20;
    let xi: Vec<f64> = (0..3 * h + 1)
        .map(|_| rng.random_range(-1.0..1.0))
        .collect();
    let norm = builtin_set(MSL_NET).nets[0].norm;
    DensityNetwork::new(h, xi, norm).unwrap()
}

const MSL_NET: &str = "msl-airdata-density-nn.toml";
const MSL_BANDS: &str = "msl-airdata-density-nn-bands.toml";

#[test]
fn density_gradient_by_backpropagation_matches_finite_differences() {
    for net in [random_network(3), builtin_set(MSL_NET).nets[0].clone()] {
        let mut act = Activations::default();
        for h_km in [15.0, 45.0, 80.0, 120.0] {
            let r = 3_396_200.0 + h_km * 1e3;
            let mut g = vec![0.0; net.n_params()];
            let rho = net.density_gradient(r, 1.0, &mut g, &mut act);
            assert!((rho / net.density(r) - 1.0).abs() < 1e-14);
            let gmax = g.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            for (k, &gk) in g.iter().enumerate() {
                let step = 1e-6;
                let mut p = net.clone();
                p.params_mut()[k] += step;
                let mut m = net.clone();
                m.params_mut()[k] -= step;
                let fd = (p.density(r) - m.density(r)) / (2.0 * step);
                assert!(
                    (fd - gk).abs() <= 1e-6 * gmax + 1e-7 * gk.abs(),
                    "h {h_km} km param {k}: backprop {gk} fd {fd}"
                );
            }
            // dρ/dr (used by the dual-number atmosphere).
            let (rho2, slope) = net.density_and_slope(r);
            let fd = (net.density(r + 1.0) - net.density(r - 1.0)) / 2.0;
            assert!((rho2 / rho - 1.0).abs() < 1e-14);
            assert!((slope - fd).abs() < 1e-6 * slope.abs(), "{slope} {fd}");
        }
    }
}

#[test]
fn network_atmosphere_gives_exact_values_and_first_derivatives() {
    let atm = NnAtmosphere {
        set: builtin_set(MSL_BANDS),
    };
    for h in [10e3, 39.9e3, 40.1e3, 65e3, 110e3] {
        let d = atm.density(num_dual::Dual64::new(h, 1.0));
        assert_eq!(d.re, atm.density(h));
        let fd = (atm.density(h + 0.5) - atm.density(h - 0.5)) / 1.0;
        assert!((d.eps - fd).abs() < 1e-6 * fd.abs(), "{h}: {} {fd}", d.eps);
    }
    // One network per band: 3 bands, each selected inside its own range.
    assert_eq!(atm.set.nets.len(), 3);
    assert_eq!(atm.set.band(5e3), 0);
    assert_eq!(atm.set.band(50e3), 1);
    assert_eq!(atm.set.band(125e3), 2);
    assert_eq!(atm.set.band(500e3), 2);
}

/// The loss of eq. 52 and its gradient (AD for ∂h/∂ρ, backpropagation for ∂NN/∂ξ) agree with
/// finite differences, for one term and for a window of terms.
#[test]
fn likelihood_loss_gradient_matches_finite_differences() {
    let s = scenario("msl-airdata");
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(5, 0));
    let draw = s.draw_truth(&mut rng);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let set = builtin_set(MSL_NET);
    let terms: Vec<LossTerm> = [40usize, 41, 42]
        .iter()
        .map(|&k| {
            let e = &truth.epochs[k];
            let smp = &truth.samples[k + 1];
            let mut x = SVector::<f64, 8>::zeros();
            for i in 0..6 {
                x[i] = smp.spherical[i];
            }
            x[0] += 150.0; // a prior off the truth, so the loss is not at its minimum
            x[6] = 7.0e-3;
            x[7] = 0.25;
            let slots: Vec<usize> = (0..e.values.len())
                .filter(|&c| e.values[c].is_some())
                .collect();
            LossTerm {
                x,
                kin: kinematics(s.filter_model(), &x, e.t),
                altitude: x[0] - s.planet.radius,
                z: slots.iter().map(|&c| e.values[c].unwrap()).collect(),
                r_inv: slots
                    .iter()
                    .map(|&c| {
                        s.channels[c]
                            .filter_noise
                            .sigma(e.values[c].unwrap())
                            .powi(-2)
                    })
                    .collect(),
                channels: slots.iter().map(|&c| s.channels[c].channel).collect(),
                beacons: vec![],
            }
        })
        .collect();
    let ctx = LossContext {
        measurement: &s.measurement,
        model: s.filter_model(),
        bank: 0.0,
    };
    let mut act = Activations::default();
    for n_terms in [1, 3] {
        let t = &terms[..n_terms];
        let mut g = vec![0.0; set.nets[0].n_params()];
        let l = ctx.loss(&set, t, 0, Some(&mut g), &mut act);
        assert!(l > 10.0, "loss {l}");
        // The gradient path sums the hidden layer in another grouping: equal to round-off.
        assert!((l / ctx.loss(&set, t, 0, None, &mut act) - 1.0).abs() < 1e-12);
        let gmax = g.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        for k in (0..g.len()).step_by(7) {
            let step = 1e-7;
            let mut p = set.clone();
            p.nets[0].params_mut()[k] += step;
            let mut m = set.clone();
            m.nets[0].params_mut()[k] -= step;
            let fd = (ctx.loss(&p, t, 0, None, &mut act) - ctx.loss(&m, t, 0, None, &mut act))
                / (2.0 * step);
            assert!(
                (fd - g[k]).abs() <= 1e-5 * gmax,
                "{n_terms} terms, param {k}: grad {} fd {fd} (max {gmax})",
                g[k]
            );
        }
    }
}

#[test]
fn algorithm2_lowers_the_loss_and_initialises_adam_as_seed001() {
    let s = scenario("msl-airdata");
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(9, 0));
    let draw = s.draw_truth(&mut rng);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let k = 200;
    let e = &truth.epochs[k];
    let smp = &truth.samples[k + 1];
    let mut x = SVector::<f64, 8>::zeros();
    for i in 0..6 {
        x[i] = smp.spherical[i];
    }
    x[6] = draw.model.vehicle.cd_s_over_m;
    x[7] = draw.model.vehicle.lift_to_drag;
    let term = LossTerm {
        x,
        kin: kinematics(s.filter_model(), &x, e.t),
        altitude: smp.altitude,
        z: vec![e.values[3].unwrap(), e.values[4].unwrap()],
        r_inv: vec![
            s.channels[3]
                .filter_noise
                .sigma(e.values[3].unwrap())
                .powi(-2),
            s.channels[4]
                .filter_noise
                .sigma(e.values[4].unwrap())
                .powi(-2),
        ],
        channels: vec![s.channels[3].channel, s.channels[4].channel],
        beacons: vec![],
    };
    let ctx = LossContext {
        measurement: &s.measurement,
        model: s.filter_model(),
        bank: 0.0,
    };
    let settings = MloSettings {
        beta1: 0.1,
        beta2: 0.9,
        epsilon: 1e-8,
        step: 0.01,
        patience: 1,
        threshold: 2.0,
        max_iterations: 500,
    };
    let mut set = builtin_set(MSL_NET);
    let mut act = Activations::default();
    let mut g0 = vec![0.0; set.nets[0].n_params()];
    ctx.loss(
        &set,
        std::slice::from_ref(&term),
        0,
        Some(&mut g0),
        &mut act,
    );
    let mut state = OnlineAdam::default();
    let out = maximise_likelihood(
        &ctx,
        &mut set,
        0,
        &mut state,
        std::slice::from_ref(&term),
        1e-4,
        &settings,
        &mut act,
    );
    assert!(out.initial_loss > 100.0, "{out:?}");
    assert!(
        out.accepted > 0 && out.final_loss < 0.01 * out.initial_loss,
        "{out:?}"
    );
    let adam = state.adam.as_ref().unwrap();
    assert!(!adam.bias_correction);
    // Moments start at ∇̄ = 0 and (∇̄)² = ∇²: after the first accepted step ∇̄ = (1 − β₁)∇₀.
    let mut fresh = OnlineAdam::default();
    let mut set2 = builtin_set(MSL_NET);
    let s1 = MloSettings {
        max_iterations: 1,
        ..settings
    };
    let o1 = maximise_likelihood(
        &ctx,
        &mut set2,
        0,
        &mut fresh,
        std::slice::from_ref(&term),
        1e-5,
        &s1,
        &mut act,
    );
    assert_eq!(o1.accepted, 1, "{o1:?}");
    let a = fresh.adam.unwrap();
    for ((m, v), g) in a.m.iter().zip(&a.v).zip(&g0) {
        assert!((m - 0.9 * g).abs() <= 1e-12 * g.abs().max(1e-300));
        let v_expected = 0.9 * g * g + 0.1 * g * g;
        assert!((v - v_expected).abs() <= 1e-12 * v_expected.max(1e-300));
    }
    // Below the threshold nothing runs.
    let mut idle = OnlineAdam::default();
    let big = MloSettings {
        threshold: 1e30,
        ..settings
    };
    let o = maximise_likelihood(
        &ctx,
        &mut set2,
        0,
        &mut idle,
        std::slice::from_ref(&term),
        1e-4,
        &big,
        &mut act,
    );
    assert_eq!(o.iterations, 0);
    assert!(idle.adam.is_none());
}

#[test]
fn adam_minimises_a_quadratic_and_candidate_is_eq_55_57() {
    let mut adam = Adam::new(2, 0.9, 0.999, 1e-8, true);
    let mut x = vec![3.0, -2.0];
    for _ in 0..3000 {
        let g = vec![2.0 * x[0], 20.0 * x[1]];
        adam.step(&mut x, &g, 1e-2);
    }
    assert!(x[0].abs() < 1e-3 && x[1].abs() < 1e-3, "{x:?}");
    let a = Adam {
        m: vec![0.5],
        v: vec![4.0],
        ..Adam::new(1, 0.1, 0.9, 1e-8, false)
    };
    let (mut xo, mut mo, mut vo) = ([0.0], [0.0], [0.0]);
    a.candidate(&[1.0], &[2.0], 0.01, &mut xo, &mut mo, &mut vo);
    let m = 0.1 * 0.5 + 0.9 * 2.0;
    let v = 0.9 * 4.0 + 0.1 * 4.0;
    assert_eq!(mo[0], m);
    assert_eq!(vo[0], v);
    assert!((xo[0] - (1.0 - 0.01 * m / (v.sqrt() + 1e-8))).abs() < 1e-15);
}

/// Myers–Tapley on a scalar random walk with a Kalman filter: starting from a Q 100× too small,
/// the adapted Q settles near the true one (the paper's batch of 10 is noisy, so a long batch
/// is used for the statistical check).
#[test]
fn covariance_matching_recovers_the_process_noise_of_a_random_walk() {
    use nalgebra::{SMatrix, SVector};
    let (q_true, r): (f64, f64) = (4.0, 1.0);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut normal = move || -> f64 {
        use rand_distr::{Distribution, StandardNormal};
        StandardNormal.sample(&mut rng)
    };
    let mut cm = CovarianceMatching::<1>::new(400);
    let (mut x, mut xh, mut p, mut q) = (0.0, 0.0, 1.0, 0.04);
    let mut sum = 0.0;
    let mut n = 0;
    for k in 0..20_000 {
        x += q_true.sqrt() * normal();
        let y = x + r.sqrt() * normal();
        let (xm, pm) = (xh, p + q);
        let kg = pm / (pm + r);
        xh = xm + kg * (y - xm);
        p = (1.0 - kg) * pm;
        let m = |v: f64| SMatrix::<f64, 1, 1>::new(v);
        cm.push(
            &SVector::<f64, 1>::new(xm),
            &m(pm),
            &m(q),
            &SVector::<f64, 1>::new(xh),
            &m(p),
        );
        if let Some(e) = cm.estimate() {
            q = e[(0, 0)];
            if k > 5000 {
                sum += q;
                n += 1;
            }
        }
    }
    let mean = sum / n as f64;
    assert!((mean / q_true - 1.0).abs() < 0.15, "mean adapted Q {mean}");
}

fn small_training() -> DensityTrainingConfig {
    DensityTrainingConfig {
        trajectories: 12,
        duration_s: 200.0,
        sample_interval_s: 1.0,
        hidden: 16,
        epochs: 30,
        batch_size: 64,
        ..DensityTrainingConfig::default()
    }
}

#[test]
fn training_is_reproducible_from_its_seed_on_any_thread_count() {
    let s = scenario("msl-airdata");
    let cfg = small_training();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| train_density_networks(&s, &cfg, &|_, _, _| {}).unwrap().0)
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.networks[0].w_in, b.networks[0].w_in);
    assert_eq!(a.networks[0].w_out, b.networks[0].w_out);
    assert_eq!(a.networks[0].b_out, b.networks[0].b_out);
    let t = &a.networks[0].training;
    assert!(t.train_samples > 4 * t.validation_samples / 2 && t.validation_samples > 0);
    // 30 epochs of a 16-neuron network already fit the exponential to a few per cent.
    assert!(t.validation_rel_err_p50_p99_max[0] < 0.05, "{t:?}");
    let mut other = cfg.clone();
    other.seed = 2;
    let c = train_density_networks(&s, &other, &|_, _, _| {}).unwrap().0;
    assert_ne!(a.networks[0].w_in, c.networks[0].w_in);
    // The file round-trips through TOML exactly.
    let text = a.to_toml_string();
    assert_eq!(NetworkFile::from_toml_str(&text, "t").unwrap(), a);
}

#[test]
fn training_data_follow_algorithm_1() {
    let s = scenario("msl-airdata");
    let cfg = small_training();
    let exp = fit_onboard_exponential(&s.truth_model.atmosphere, 0.0, 130.0).unwrap();
    let atm = BandedExponential {
        tops_m: vec![130e3],
        models: vec![exp],
    };
    let d = generate_data(&s, &atm, &cfg);
    // 12 trajectories × 201 samples (t = 0, 1, …, 200 s), ρ from the exponential.
    assert_eq!(d.r_m.len(), 12 * 201);
    for k in 0..d.r_m.len() {
        let h = d.r_m[k] - s.planet.radius;
        assert!((d.rho[k] / exp.density(h) - 1.0).abs() < 1e-14);
    }
    // Different trajectories start from different dispersed states.
    assert_ne!(d.r_m[0], d.r_m[201]);
}

/// The shipped network: the format parses, it was trained on the scenario's onboard model, the
/// onboard model is the least-squares fit to the truth mean profile, and its validation error
/// is that of seed 001 Fig. 5 (most errors below 1 %).
#[test]
fn shipped_network_and_onboard_model_are_the_least_squares_fit() {
    let s = scenario("msl-airdata");
    let fit = fit_onboard_exponential(&s.truth_model.atmosphere, 0.0, 130.0).unwrap();
    for h in [10e3_f64, 60e3, 126e3] {
        let onboard = s.filter_model().atmosphere.density(h);
        assert!(
            (onboard / fit.density(h) - 1.0).abs() < 2e-6,
            "{h}: {onboard} vs {}",
            fit.density(h)
        );
    }
    let file = NetworkFile::from_toml_str(builtin_network_toml(MSL_NET).unwrap(), MSL_NET).unwrap();
    assert_eq!(file.networks.len(), 1);
    let rec = &file.networks[0];
    assert_eq!(rec.w_in.len(), 100);
    assert!((rec.trained_on_exponential[0] / fit.rho_ref - 1.0).abs() < 1e-12);
    assert!(
        rec.training.validation_frac_below_1pct > 0.95,
        "{:?}",
        rec.training
    );
    let set = file.to_set().unwrap();
    for h_km in (15..=125).step_by(10) {
        let h = h_km as f64 * 1e3;
        let e = set.density_at_altitude(h) / fit.density(h) - 1.0;
        assert!(e.abs() < 0.02, "{h_km} km: {e}");
    }
    let bands =
        NetworkFile::from_toml_str(builtin_network_toml(MSL_BANDS).unwrap(), MSL_BANDS).unwrap();
    assert_eq!(bands.networks.len(), 3);
}

#[test]
fn density_filters_refuse_scenarios_without_their_layout() {
    // four-beacon-fusion augments rho0: not the seed-001 layout.
    let fb = scenario("four-beacon-fusion");
    for k in [FilterKind::UkfAc, FilterKind::UskfNn] {
        let msg = k.check_fits(&fb.onboard).unwrap_err().to_string();
        assert!(
            msg.contains("cd-s-over-m") && msg.contains(k.name()),
            "{msg}"
        );
    }
    assert!(FilterKind::UkfCm.check_fits(&fb.onboard).is_ok());
    // Cartesian scenario.
    let msg = FilterKind::UskfNn
        .check_fits(&scenario("msl-pressure").onboard)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("spherical"), "{msg}");
    // No [filter.density] section: uskf-nn has no network.
    let bare = scenario_with("msl-airdata", |c| c.filter.density = None);
    let msg = FilterKind::UskfNn
        .check_fits(&bare.onboard)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("filter.density"), "{msg}");
    assert!(FilterKind::UkfAc.check_fits(&bare.onboard).is_ok());
    // Unknown network name.
    let bad = scenario_with("msl-airdata", |c| {
        c.filter.density.as_mut().unwrap().network = "nope.toml".into()
    });
    let msg = FilterKind::UskfNn
        .check_fits(&bad.onboard)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("nope.toml") && msg.contains(MSL_NET), "{msg}");
    // build_filter for another state dimension than the onboard model's is refused, not a
    // panic, for every filter.
    let s = scenario("msl-airdata");
    let start = FilterStart::<7> {
        x0: SVector::zeros(),
        p0: nalgebra::SMatrix::identity(),
        q: nalgebra::SMatrix::zeros(),
    };
    for kind in FilterKind::ALL {
        let err = build_filter::<7, 8>(kind, &s.onboard, &start)
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("7-state") && err.contains("8 states"), "{err}");
    }
    // Names parse.
    for n in ["ukf-cm", "ukf-ac", "uskf-nn"] {
        assert_eq!(FilterKind::parse(n).unwrap().name(), n);
    }
}

/// The USKF-NN's consider parameter is never updated: ĉ stays 1 and its variance follows the
/// ECRV, Pss + (Pc0 − Pss)·e^{−2t/τ} (eq. 51, 67–68); UKF-AC starts from the truth-mean ratio.
#[test]
fn consider_parameter_is_an_unupdated_ecrv_and_ukf_ac_starts_from_the_mean_ratio() {
    let s = scenario("msl-airdata");
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(1, 3));
    let draw = s.draw_truth(&mut rng);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let x0 = initial_estimate(&s, &draw, &truth.samples[0], &mut rng);
    let start = FilterStart::<8>::with_estimate(&s.onboard, &x0);
    let mut nn = UskfNnNav::<8, 9>::new(&s.onboard, &start).unwrap();
    let ac = UkfAcNav::<8, 9>::new(&s.onboard, &start).unwrap();
    let h0 = start.x0[0] - s.planet.radius;
    let ratio = s.truth_model.atmosphere.density(h0) / s.filter_model().atmosphere.density(h0);
    assert!((ac.correction_factor().0 / ratio - 1.0).abs() < 1e-12);
    assert_eq!(ac.correction_factor().1, 1e-10);
    for e in &truth.epochs[..80] {
        nn.predict(e.t).unwrap();
        nn.update(e, &[]).unwrap();
    }
    let (xa, pa) = nn.augmented();
    assert!((xa[8] - 1.0).abs() < 1e-12, "c = {}", xa[8]);
    let t = truth.epochs[79].t;
    let d = ScenarioConfig::builtin("msl-airdata")
        .unwrap()
        .filter
        .density
        .unwrap();
    let (pss, p0) = (d.consider_pss, d.consider_p0);
    let expected = pss + (p0 - pss) * (-2.0 * t / d.consider_tau_s).exp();
    assert!(
        (pa[(8, 8)] / expected - 1.0).abs() < 1e-9,
        "{} vs {expected}",
        pa[(8, 8)]
    );
    // The state-consider cross-covariance is updated (not zero).
    assert!((0..8).any(|i| pa[(i, 8)] != 0.0));
    let st = nn.adaptation_stats();
    assert_eq!(st.epochs, 80);
    assert!(st.accepted > 0);
}

/// Seed 001's qualitative result on a few runs: USKF-NN's radius error and density-profile error
/// are an order of magnitude below UKF-AC's, and below 2 %; the options run.
#[test]
fn short_monte_carlo_reproduces_the_papers_ranking() {
    let s = scenario("msl-airdata");
    let kinds = [FilterKind::UkfCm, FilterKind::UkfAc, FilterKind::UskfNn];
    let opts = DensityEvalOptions {
        runs: 6,
        seed: 1,
        keep_runs: 2,
    };
    let r = evaluate_density_filters(&s, &kinds, None, &opts, &|_| {}).unwrap();
    assert!(r.iter().all(|x| x.failed == 0));
    let (ac, nn) = (&r[1], &r[2]);
    assert!(nn.rmspe_profile_pct < 2.0, "{nn:?}");
    assert!(ac.rmspe_profile_pct > 10.0 * nn.rmspe_profile_pct);
    assert_eq!(nn.sample_runs_profile_pct.len(), 2);
    let trade = entrynav::sim::run_trade(&s, &kinds, &entrynav::sim::McOptions::new(6, 1), &|_| {})
        .unwrap();
    let r_rmse = |i: usize| trade.filters[i].rmse_time_avg["r_m"].unwrap();
    assert!(
        r_rmse(2) * 10.0 < r_rmse(1),
        "{} vs {}",
        r_rmse(2),
        r_rmse(1)
    );
    assert_eq!(trade.filters[2].diverged, 0);
    // The §VI options: a window of measurements and one network per altitude band. The window is
    // checked with the paper's filter noise (Table 2's Q, Table 4's consider parameter, as
    // `msl-airdata-paper`; 2.83 % on these 2 runs), as before issue 49: with msl-airdata's re-sized
    // consider parameter (P_c0 = P_ss = 1e-4 over 60 s) it is 3.80 %, not re-tuned for it
    // (Table 4's c with the load-scaled Q: 0.94 %; the issue-49 c with Table 2's Q: 19 %). The
    // band networks keep msl-airdata's settings (0.14 %; 0.19 % with the paper's noise).
    for edit in [
        |c: &mut ScenarioConfig| {
            with_paper_noise(c);
            c.filter.density.as_mut().unwrap().window = 4;
        },
        |c: &mut ScenarioConfig| c.filter.density.as_mut().unwrap().network = MSL_BANDS.into(),
    ] {
        let s2 = scenario_with("msl-airdata", edit);
        let r = evaluate_density_filters(
            &s2,
            &[FilterKind::UskfNn],
            None,
            &DensityEvalOptions {
                runs: 2,
                seed: 1,
                keep_runs: 0,
            },
            &|_| {},
        )
        .unwrap();
        assert!(r[0].failed == 0 && r[0].rmspe_profile_pct < 3.0, "{r:?}");
    }
}

#[test]
fn density_settings_are_validated_with_the_field_name() {
    let text = entrynav::scenario::builtin_toml("msl-airdata").unwrap();
    for (from, to, field) in [
        ("cm_batch = 10", "cm_batch = 1", "filter.density.cm_batch"),
        (
            "adam_beta1 = 0.1",
            "adam_beta1 = 1.5",
            "filter.density.adam_beta1",
        ),
        (
            "consider_tau_s = 60.0",
            "consider_tau_s = -60.0",
            "filter.density.consider_tau_s",
        ),
        (
            "epochs = 100",
            "epochs = 0",
            "filter.density.training.epochs",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let err = ScenarioConfig::from_toml_str(&text.replace(from, to), "edited")
            .unwrap_err()
            .to_string();
        assert!(err.contains(field), "{err}");
    }
    let err = ScenarioConfig::from_toml_str(
        &text.replace("cm_batch = 10", "cm_batch = 10\nbogus = 1"),
        "edited",
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("bogus"), "{err}");
}

/// `entrynav train-density` with the scenario's settings regenerates both shipped network files
/// bit for bit: the single network (`msl-airdata-density-nn.toml`, used by `msl-airdata` and
/// `msl-airdata-paper`) and, with `--bands-km 0,40,70,130`, the band networks
/// (`msl-airdata-density-nn-bands.toml`). Same platform and libm; about a minute, so not in the
/// default test run: `cargo test --release --test density_adaptation -- --ignored`.
#[test]
#[ignore]
fn retraining_with_the_scenario_settings_reproduces_the_shipped_networks() {
    let s = scenario("msl-airdata");
    let single = s.config.filter.density.clone().unwrap().training;
    let bands = DensityTrainingConfig {
        bands_km: vec![0.0, 40.0, 70.0, 130.0],
        ..single.clone()
    };
    for (cfg, name, count) in [(single, MSL_NET, 1), (bands, MSL_BANDS, 3)] {
        let clock = std::time::Instant::now();
        let (file, _) = train_density_networks(&s, &cfg, &|_, _, _| {}).unwrap();
        let took = clock.elapsed().as_secs_f64();
        let shipped =
            NetworkFile::from_toml_str(builtin_network_toml(name).unwrap(), name).unwrap();
        assert_eq!(file.networks.len(), count, "{name}");
        assert_eq!(shipped.networks.len(), count, "{name}");
        for (a, b) in file.networks.iter().zip(&shipped.networks) {
            assert_eq!(a.altitude_band_km, b.altitude_band_km, "{name}");
            assert_eq!(a.normalisation, b.normalisation, "{name}");
            assert_eq!(a.w_in, b.w_in, "{name}");
            assert_eq!(a.b_in, b.b_in, "{name}");
            assert_eq!(a.w_out, b.w_out, "{name}");
            assert_eq!(a.b_out, b.b_out, "{name}");
        }
        // The budget is 60 s on 2 idle cores (docs/density.md: 14 s); wall time on a
        // shared machine is no test outcome, so it is printed, not asserted.
        eprintln!("{name}: retrained bit for bit in {took:.1} s wall");
    }
}
