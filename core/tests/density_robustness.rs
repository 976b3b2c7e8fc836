//! USKF-NN robustness (issue 15): the default `msl-airdata` configuration against the paper's
//! (`msl-airdata-paper`), the runs where the paper's settings lock onto a wrong network, the
//! acceptance trade, and the synthetic test set of atmospheres (docs/density.md, "Robustness").

use entrynav::atmosphere::{
    Atmosphere, SyntheticSetSpec, generate_synthetic_set, mars_mean_profile,
    synthetic_set_gram_text,
};
use entrynav::estimation::nav::uskf_nn::UskfNnNav;
use entrynav::estimation::nav::{FilterKind, FilterStart, NavFilter};
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::monte_carlo::replay::replay_run;
use entrynav::sim::record_run;
use entrynav::sim::{McOptions, run_trade};
use std::sync::Arc;

fn config(name: &str) -> ScenarioConfig {
    ScenarioConfig::builtin(name).unwrap()
}

fn scenario(name: &str) -> Arc<Scenario> {
    Arc::new(Scenario::build(config(name), &entrynav::files::no_files).unwrap())
}

/// Runs of `trade --scenario msl-airdata-paper --filters uskf-nn --seed 1` (the first 200) that
/// end with NEES > 100 × 8 dof: the wrong-network lock-on of docs/density.md.
const PAPER_LOCK_ON_RUNS: [usize; 6] = [86, 125, 138, 142, 160, 173];

/// The two scenarios are the same but for USKF-NN's adaptation settings and, since issue 49, its
/// process noise (msl-airdata's `[filter.tuned.uskf-nn]`: load-scaled, no constant Q on the
/// kinematic states; the paper variant gives every filter Table 2's constant Q; the consider
/// parameter is one of the adaptation settings).
#[test]
fn paper_variant_differs_only_in_the_adaptation_settings_and_the_process_noise() {
    let (default, mut paper) = (config("msl-airdata"), config("msl-airdata-paper"));
    let (d, p) = (
        default.filter.density.as_ref().unwrap(),
        paper.filter.density.as_ref().unwrap(),
    );
    assert_eq!(p.network, "msl-airdata-density-nn.toml");
    assert_eq!((p.adam_step, p.patience), (0.01, 1), "Table 4");
    assert!(p.training.bands_km.is_empty());
    assert_ne!((d.adam_step, d.patience), (p.adam_step, p.patience));
    paper.name = default.name.clone();
    paper.description = default.description.clone();
    assert_eq!(
        (p.consider_tau_s, p.consider_pss, p.consider_p0),
        (5.0, 1e-3, 1e-10),
        "Table 4"
    );
    assert_eq!(paper.filter.q_diag[3], 1e-2, "Table 2");
    assert_eq!(paper.filter.process_noise, Default::default(), "constant Q");
    assert!(paper.filter.tuned.is_empty(), "one Q for every filter");
    let nn = &default.filter.tuned["uskf-nn"];
    assert!(nn.process_noise.is_some_and(|m| !m.is_constant()));
    paper.filter.density = default.filter.density.clone();
    paper.filter.tuned = default.filter.tuned.clone();
    assert_eq!(paper, default);
}

/// Root cause of the lock-on, on one of those runs: with Table 4's α = 0.01/k every epoch ends
/// after at most one accepted Adam step (the next candidate overshoots and p_max = 1 stops), so
/// the first update flies a network still far off at the entry interface while P_c,0 = 1e-10
/// calls the density exact: the update moves r̂ by > 100 m (≫ its 10.7 m σ) and the state never
/// recovers. Ten times smaller steps (`msl-airdata`'s α = 0.001/k, here without its local
/// correction) are accepted by the tens and keep the first radius error at a few metres; the
/// default with its local level-and-slope correction needs no Adam step at all in these epochs
/// (the correction takes the level) and keeps it at a few metres too.
#[test]
fn first_adam_steps_of_table_4_are_rejected_and_the_state_absorbs_the_density_error() {
    let mut small_steps = config("msl-airdata");
    small_steps.filter.density.as_mut().unwrap().slope_window = None;
    let configs = [
        config("msl-airdata-paper"),
        small_steps,
        config("msl-airdata"),
    ];
    let mut first = Vec::new();
    for cfg in configs {
        let s = Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap());
        let rec = record_run(&s, 1, PAPER_LOCK_ON_RUNS[0]).unwrap();
        let start = FilterStart::<8>::with_estimate(&s.onboard, &rec.x0);
        let mut nn = UskfNnNav::<8, 9>::new(&s.onboard, &start).unwrap();
        let (mut accepted, mut r_err) = (Vec::new(), 0.0);
        for (epoch, sample) in rec.truth.epochs_with_truth().take(4) {
            nn.predict(epoch.t).unwrap();
            let before = nn.adaptation_stats().accepted;
            nn.update(epoch, &[]).unwrap();
            accepted.push(nn.adaptation_stats().accepted - before);
            if accepted.len() == 1 {
                r_err = nn.estimate().0[0] - sample.state[0];
            }
        }
        first.push((accepted, r_err));
    }
    eprintln!(
        "accepted candidates in epochs 1-4 and r error after the first update: paper {:?}, α 0.001/k {:?}, default {:?}",
        first[0], first[1], first[2]
    );
    let (paper, small, default) = (&first[0], &first[1], &first[2]);
    // Table 4: at most one accepted step per epoch (measured: 1, 0, 0, 0); r̂ moves by 140 m.
    assert!(paper.0.iter().all(|&a| a <= 1), "paper: {paper:?}");
    assert!(paper.1.abs() > 100.0, "paper: {paper:?}");
    // α = 0.001/k: tens of small accepted steps (measured: 19, 33, 4, 6); r̂ moves by 3 m.
    assert!(small.0[0] >= 10, "α 0.001/k: {small:?}");
    assert!(small.1.abs() < 0.1 * paper.1.abs(), "{first:?}");
    // Default (measured: 0, 0, 0, 0 accepted; r̂ moves by 3.6 m).
    assert!(default.1.abs() < 0.1 * paper.1.abs(), "{first:?}");
}

/// Every lock-on run of the paper's settings ends confidently wrong; with the default settings
/// the same runs (same truth, noise and start) end consistent.
#[test]
fn lock_on_runs_of_the_paper_settings_end_consistent_with_the_default() {
    for (name, locked) in [("msl-airdata-paper", true), ("msl-airdata", false)] {
        let s = scenario(name);
        for run in PAPER_LOCK_ON_RUNS {
            let r = replay_run(&s, &[FilterKind::UskfNn], 1, run).unwrap();
            let last = r[0].epochs.last().unwrap();
            let (nees, dof) = last.nees.unwrap();
            assert!(r[0].failure.is_none());
            assert_eq!(
                nees > 100.0 * dof as f64,
                locked,
                "{name} run {run}: final NEES {nees}, position error {} m",
                last.pos_vel_err.0
            );
        }
    }
}

/// Issue 15 acceptance on one seed: `trade --scenario msl-airdata --filters ukf-ac,uskf-nn --runs
/// 40 --seed 1`: USKF-NN density RMSPE < 2 %, at least 10× below UKF-AC, no failed or diverged
/// run (docs/density.md lists seeds 1–5).
#[test]
fn acceptance_trade_of_issue_15() {
    let s = scenario("msl-airdata");
    let kinds = [FilterKind::UkfAc, FilterKind::UskfNn];
    let t = run_trade(&s, &kinds, &McOptions::new(40, 1), &|_| {}).unwrap();
    let (ac, nn) = (&t.filters[0], &t.filters[1]);
    let (ac_pct, nn_pct) = (ac.density_rmspe_pct.unwrap(), nn.density_rmspe_pct.unwrap());
    assert!(nn_pct < 2.0, "{nn_pct}");
    assert!(ac_pct > 10.0 * nn_pct, "{ac_pct} vs {nn_pct}");
    assert_eq!((nn.failed, nn.diverged), (0, 0));
}

/// The synthetic set as a truth table flying profile `profile` in every run.
fn synthetic_scenario(text: &str, profile: usize) -> Arc<Scenario> {
    let mut cfg = config("msl-airdata");
    cfg.truth.atmosphere = toml::from_str(&format!(
        "model = 'table'\nfile = 'set.txt'\nformat = 'mars-gram'\nprofile = {profile}"
    ))
    .unwrap();
    cfg.truth.perturbation = None;
    let load = |_: &str| Ok(text.to_string());
    Arc::new(Scenario::build(cfg, &load).unwrap())
}

/// The synthetic test set round-trips through the Mars-GRAM reader, and USKF-NN keeps its
/// density error within the bound measured on the whole set (docs/density.md) on its extreme
/// cases: 0.1× and 3× the mean above 80 km over 0.7× and 1.3× below.
#[test]
fn uskf_nn_on_the_extreme_cases_of_the_synthetic_set() {
    let spec = SyntheticSetSpec::default();
    let profiles = generate_synthetic_set(&mars_mean_profile(), &spec).unwrap();
    let text = synthetic_set_gram_text(&profiles, &spec, 3_396_200.0);
    let s0 = synthetic_scenario(&text, 0);
    let set = &s0.truth_profiles.as_ref().unwrap().set;
    assert_eq!(set.profiles.len(), profiles.len());
    for (p, g) in set.profiles.iter().zip(&profiles) {
        for (&h, &rho) in g.altitude_m.iter().zip(&g.density).step_by(10) {
            assert!((p.table.density(h) / rho - 1.0).abs() < 1e-5, "{h}");
        }
    }
    let kinds = [FilterKind::UkfAc, FilterKind::UskfNn];
    for (k, p) in profiles.iter().enumerate() {
        let extreme =
            [0.1, 3.0].contains(&p.case.factor_above) && [0.7, 1.3].contains(&p.case.factor_below);
        // Measured on the whole set (10 runs per case, docs/density.md): at most 0.22 % (0.35 %
        // before the local correction).
        if !extreme {
            continue;
        }
        let s = synthetic_scenario(&text, k);
        let t = run_trade(&s, &kinds, &McOptions::new(6, 1), &|_| {}).unwrap();
        let (ac, nn) = (&t.filters[0], &t.filters[1]);
        let nn_pct = nn.density_rmspe_pct.unwrap();
        let case = (p.case.factor_above, p.case.factor_below);
        eprintln!(
            "{case:?}: USKF-NN {nn_pct:.3} %, UKF-AC {:.2} %",
            ac.density_rmspe_pct.unwrap()
        );
        assert!(nn_pct < 0.75, "{case:?}: {nn_pct}");
        assert!(ac.density_rmspe_pct.unwrap() > 10.0 * nn_pct, "{case:?}");
        assert_eq!((nn.failed, nn.diverged), (0, 0), "{case:?}");
    }
}

/// Issue 30: the high-latitude cases (scale heights × 0.75 below 60 km, twice the perturbation, an
/// upper atmosphere 0.3× or 3× the mean over a 1.3× lower one). USKF-NN holds its density RMSPE
/// below 1 % with no failed or diverged run (docs/density.md measures all 30 cases of the
/// extended set at 10 runs: at most 0.36 %).
#[test]
fn uskf_nn_holds_one_percent_on_the_steepest_high_latitude_cases() {
    let spec = SyntheticSetSpec::extended();
    let profiles = generate_synthetic_set(&mars_mean_profile(), &spec).unwrap();
    let text = synthetic_set_gram_text(&profiles, &spec, 3_396_200.0);
    let mut flown = 0;
    for (k, p) in profiles.iter().enumerate() {
        let c = p.case;
        if c.scale_height_factor != 0.75 || c.factor_below != 1.3 {
            continue;
        }
        let s = synthetic_scenario(&text, k);
        let t = run_trade(&s, &[FilterKind::UskfNn], &McOptions::new(6, 1), &|_| {}).unwrap();
        let nn = &t.filters[0];
        let pct = nn.density_rmspe_pct.unwrap();
        eprintln!("{}: USKF-NN {pct:.3} %", c.describe());
        assert!(pct < 1.0, "{c:?}: {pct}");
        assert_eq!((nn.failed, nn.diverged), (0, 0), "{c:?}");
        flown += 1;
    }
    assert_eq!(flown, 3);
}
