//! LinCov of the EKF along a scenario's nominal trajectory (issue 25): against Monte Carlos of
//! the same filter on the same scenario, in the matched case against the filter's own P, and its
//! refusals.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::lincov::{EntryLinCov, EntryLinCovError, entry_lincov};
use entrynav::sim::{McOptions, TradeReport, run_trade};

fn build(cfg: ScenarioConfig) -> Scenario {
    Scenario::build(cfg, &entrynav::files::no_files).unwrap()
}

fn builtin(name: &str) -> ScenarioConfig {
    ScenarioConfig::builtin(name).unwrap()
}

fn monte_carlo(s: &Scenario, runs: usize, kind: FilterKind) -> TradeReport {
    let mut opts = McOptions::new(runs, 7);
    opts.pcrlb = false;
    run_trade(s, &[kind], &opts, &|_| {}).unwrap()
}

/// |a/b − 1| ≤ tol, with a message naming what is compared.
fn close(what: &str, lincov: f64, mc: f64, tol: f64) {
    let rel = lincov / mc - 1.0;
    assert!(
        rel.abs() <= tol,
        "{what}: LinCov {lincov} vs Monte Carlo {mc} ({:+.1} %, allowed ±{:.0} %)",
        rel * 100.0,
        tol * 100.0
    );
}

/// Position and velocity RMSE (time average and final) and ANEES/dof within `tol` of the Monte
/// Carlo's.
fn agree(s: &Scenario, l: &EntryLinCov, runs: usize, tol: f64) {
    let mc = monte_carlo(s, runs, FilterKind::parse(&l.filter).unwrap());
    let f = &mc.filters[0];
    let get = |m: &std::collections::BTreeMap<String, Option<f64>>, k: &str| m[k].unwrap();
    close(
        "pos time-avg",
        l.time_avg(|e| e.pos_m),
        get(&f.rmse_time_avg, "pos_m"),
        tol,
    );
    close(
        "vel time-avg",
        l.time_avg(|e| e.vel_mps),
        get(&f.rmse_time_avg, "vel_mps"),
        tol,
    );
    close(
        "pos final",
        l.final_value(|e| e.pos_m),
        get(&f.rmse_final, "pos_m"),
        tol,
    );
    close(
        "vel final",
        l.final_value(|e| e.vel_mps),
        get(&f.rmse_final, "vel_mps"),
        tol,
    );
    let c = &f.consistency;
    let mc_ratio = c.anees.unwrap() / c.nees_dof as f64;
    close("ANEES/dof", l.nees_ratio_time_avg(), mc_ratio, tol);
}

/// Filter model = truth model, start drawn from P0 around the truth, Q = 0: the Kalman filter is
/// exact, so the true error covariance LinCov propagates (truth sensitivities by finite
/// differences of whole truth runs) must equal the filter's own P. It does to 1e-6 while the
/// vehicle is above the atmosphere; once drag acts the filter's 1 s RK4 transition and the
/// truth's 0.1 s integration part by a few per cent in the least observable directions.
#[test]
fn matched_filter_true_covariance_is_its_own_p() {
    let mut cfg = builtin("orbiters-3");
    cfg.filter.q_diag = vec![0.0; 6];
    let s = build(cfg);
    let l = entry_lincov(&s, FilterKind::Ekf).unwrap();
    assert_eq!(l.parameters.len(), 6, "{:?}", l.parameters);
    for e in l.epochs.iter().filter(|e| e.t <= 30.0) {
        let ratio = e.nees / e.nees_dof as f64;
        assert!((ratio - 1.0).abs() < 1e-6, "t = {}: NEES/dof {ratio}", e.t);
        assert!((e.pos_m / e.pos_sigma_m - 1.0).abs() < 1e-6, "t = {}", e.t);
    }
    assert!((l.nees_ratio_time_avg() - 1.0).abs() < 0.05);
}

/// Small dispersions and start errors (msl-pressure with the initial-state and density-bias
/// dispersions scaled by 0.1 and P0 by 0.01): first-order theory holds, and LinCov matches a
/// 400-run Monte Carlo (a 400-run RMSE has a sampling error of about 3.5 %). The density bias is
/// a truth-only parameter here (the filter only considers it) and the start is drawn around the
/// truth. (Scaling the kinematic P0 alone is not enough: the start of the consider Δ̂, drawn with
/// σ 0.033, then makes each run's gains differ from the nominal's and the Monte Carlo RMSE grows
/// 13 % above LinCov's; docs/results.md.)
#[test]
fn small_dispersions_match_a_monte_carlo() {
    let mut cfg = builtin("msl-pressure");
    let d = &mut cfg.dispersions;
    d.density_bias *= 0.1;
    if let Some(init) = d.initial.as_mut() {
        for v in [&mut init.radius_km, &mut init.lon_deg, &mut init.lat_deg] {
            *v = v.map(|x| x * 0.1);
        }
        for v in [
            &mut init.speed_mps,
            &mut init.fpa_deg,
            &mut init.heading_deg,
        ] {
            *v = v.map(|x| x * 0.1);
        }
        init.position_km = init.position_km.map(|p| p.map(|x| x * 0.1));
        init.velocity_mps = init.velocity_mps.map(|p| p.map(|x| x * 0.1));
    }
    for p in cfg.filter.p0_diag.iter_mut() {
        *p *= 0.01;
    }
    let s = build(cfg);
    let l = entry_lincov(&s, FilterKind::Ekf).unwrap();
    assert!(l.parameters.iter().any(|p| p == "density_bias"));
    agree(&s, &l, 400, 0.06);
}

/// The iterated EKF from a fixed (wrong) start with a wrong vehicle model (four-beacon-fusion):
/// the error is a deterministic mean plus noise, and LinCov carries the mean.
#[test]
fn iterated_ekf_with_model_mismatch_matches_a_monte_carlo() {
    let s = build(builtin("four-beacon-fusion"));
    assert!(s.onboard.tuning.update_iterations > 1);
    let l = entry_lincov(&s, FilterKind::Ekf).unwrap();
    assert!(l.parameters.is_empty());
    let first = &l.epochs[0];
    assert!(first.mean_error.iter().take(6).any(|m| m.abs() > 0.0));
    agree(&s, &l, 300, 0.05);
}

/// The UKF is analysed as its EKF equivalent: the same prediction as the EKF's with the same
/// tuning (a note says so), and within 10 % of a Monte Carlo of the UKF itself on an entry
/// where the EKF's start transient makes the EKF's own Monte Carlo depart from LinCov.
#[test]
fn ukf_is_analysed_as_its_ekf_equivalent() {
    let s = build(builtin("ground-beacons-3"));
    let ekf = entry_lincov(&s, FilterKind::Ekf).unwrap();
    let ukf = entry_lincov(&s, FilterKind::Ukf).unwrap();
    assert_eq!(ukf.filter, "ukf");
    assert!(
        ukf.notes.iter().any(|n| n.contains("EKF equivalent")),
        "{:?}",
        ukf.notes
    );
    assert_eq!(ekf.epochs, ukf.epochs);
    agree(&s, &ukf, 300, 0.10);
}

#[test]
fn filters_it_cannot_analyse_are_refused_with_the_reason() {
    let s = build(builtin("four-beacon-fusion"));
    for kind in [FilterKind::Mmae, FilterKind::MmaeMoe, FilterKind::UkfCm] {
        let e = entry_lincov(&s, kind).unwrap_err();
        assert!(
            matches!(&e, EntryLinCovError::UnsupportedFilter { filter, .. } if filter == kind.name()),
            "{e}"
        );
        assert!(
            e.to_string()
                .contains("supported filters: ekf, ukf, ci, dcifaif"),
            "{e}"
        );
    }
    // The gate's exclusions and the faults are refused for the fusion filters too.
    let gated = build(builtin("four-beacon-fusion-faults"));
    for kind in [FilterKind::Ekf, FilterKind::Ci, FilterKind::Dcifaif] {
        let e = entry_lincov(&gated, kind).unwrap_err();
        assert!(e.to_string().contains("filter.gating.enabled"), "{e}");
    }
    let mut cfg = builtin("four-beacon-fusion-faults");
    cfg.filter.gating = None;
    let e = entry_lincov(&build(cfg), FilterKind::Dcifaif).unwrap_err();
    assert!(e.to_string().contains("faults"), "{e}");
}

/// The truth's density perturbation is carried as the grid normals below the trajectory's top
/// (msl-airdata: entry at 125 km, grid every 1 km from 0), and the notes say that its nominal is
/// the median profile; a scenario without perturbation, clip or profile set has no notes.
#[test]
fn density_perturbation_is_carried_and_noted() {
    let s = build(builtin("msl-airdata"));
    let l = entry_lincov(&s, FilterKind::Ekf).unwrap();
    let grid = l
        .parameters
        .iter()
        .filter(|p| p.starts_with("density_perturbation_"))
        .count();
    assert!(
        (100..=140).contains(&grid),
        "{grid} grid normals: {:?}",
        l.parameters
    );
    assert!(
        !l.parameters
            .iter()
            .any(|p| p == "density_perturbation_150000m")
    );
    assert!(
        l.notes.iter().any(|n| n.contains("median")),
        "{:?}",
        l.notes
    );
    let e = entry_lincov(&build(builtin("orbiters-3")), FilterKind::Ekf).unwrap();
    assert!(e.notes.is_empty(), "{:?}", e.notes);
}
