//! LinCov of the CI and DCIFAIF fusion filters (issue 25): against Monte Carlos of the same
//! filters with small dispersions, tight enough that the fusion modelled as one EKF fails.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::lincov::{EntryLinCov, entry_lincov};
use entrynav::sim::{McOptions, run_trade};

/// The figures compared: position and velocity RMSE (time average and final) and NEES/dof.
const FIGURES: [&str; 5] = [
    "pos time-avg",
    "vel time-avg",
    "pos final",
    "vel final",
    "NEES/dof",
];

/// LinCov's figures in the order of [`FIGURES`].
fn predicted(l: &EntryLinCov) -> [f64; 5] {
    [
        l.time_avg(|e| e.pos_m),
        l.time_avg(|e| e.vel_mps),
        l.final_value(|e| e.pos_m),
        l.final_value(|e| e.vel_mps),
        l.nees_ratio_time_avg(),
    ]
}

/// The Monte Carlo's figures and their 95 % sampling half-widths, relative: the trade's RMSE
/// interval ± 1.96/√(2N) (per epoch, so conservative for the time averages), and twice its ANEES
/// interval 1.96·√(2/(dof·N)): that one assumes a χ² NEES with `dof` equal directions, while
/// CI's conservative P_CI leaves a few directions dominating it (2000-run Monte Carlos of the
/// case below with seeds 1 and 7 give NEES/dof 0.850 and 0.874, 3 % apart).
fn monte_carlo(s: &Scenario, kind: FilterKind, runs: usize) -> ([f64; 5], [f64; 5]) {
    let mut opts = McOptions::new(runs, 7);
    opts.pcrlb = false;
    let mc = run_trade(s, &[kind], &opts, &|_| {}).unwrap();
    let f = &mc.filters[0];
    let get = |m: &std::collections::BTreeMap<String, Option<f64>>, k: &str| m[k].unwrap();
    let c = &f.consistency;
    let rmse = 1.96 / (2.0 * runs as f64).sqrt();
    let nees = 2.0 * 1.96 * (2.0 / (c.nees_dof * runs) as f64).sqrt();
    (
        [
            get(&f.rmse_time_avg, "pos_m"),
            get(&f.rmse_time_avg, "vel_mps"),
            get(&f.rmse_final, "pos_m"),
            get(&f.rmse_final, "vel_mps"),
            c.anees.unwrap() / c.nees_dof as f64,
        ],
        [rmse, rmse, rmse, rmse, nees],
    )
}

/// The figures of `l` outside the Monte Carlo's intervals, with their relative errors.
fn outside(l: &EntryLinCov, mc: &[f64; 5], tol: &[f64; 5]) -> Vec<String> {
    let p = predicted(l);
    (0..5)
        .filter(|&i| (p[i] / mc[i] - 1.0).abs() > tol[i])
        .map(|i| {
            format!(
                "{}: LinCov {} vs MC {} ({:+.1} %, allowed ±{:.1} %)",
                FIGURES[i],
                p[i],
                mc[i],
                (p[i] / mc[i] - 1.0) * 100.0,
                tol[i] * 100.0
            )
        })
        .collect()
}

/// orbiters-3 (three orbiters, every channel a range, so each local filter has one range) with
/// its initial-state dispersions and P0 scaled to a hundredth in σ, so first-order theory holds
/// for the weakly observable locals too. LinCov of `ci` (three locals fused by determinant-optimal
/// CI) and `dcifaif` (feedback, exact covariance) lies within the sampling interval of a
/// 1000-run Monte Carlo of the same filter for both RMSEs (time average and final) and NEES/dof;
/// the EKF's LinCov, i.e. the fusion modelled as one centralised EKF, does not (measured: CI's
/// NEES/dof 0.85 against the EKF's 1.00 and position 13 % above it, DCIFAIF's position 19 %
/// above). At a tenth in σ CI's NEES/dof is already 9–12 % below the Monte Carlo's (second
/// order: docs/results.md).
#[test]
fn small_dispersions_match_a_monte_carlo_of_the_fusion() {
    let mut cfg = ScenarioConfig::builtin("orbiters-3").unwrap();
    let init = cfg.dispersions.initial.as_mut().unwrap();
    init.position_km = init.position_km.map(|p| p.map(|x| x * 0.01));
    init.velocity_mps = init.velocity_mps.map(|p| p.map(|x| x * 0.01));
    for p in cfg.filter.p0_diag.iter_mut() {
        *p *= 1e-4;
    }
    let s = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    let ekf = entry_lincov(&s, FilterKind::Ekf).unwrap();
    for kind in [FilterKind::Ci, FilterKind::Dcifaif] {
        let l = entry_lincov(&s, kind).unwrap();
        assert_eq!(l.parameters.len(), 6, "{:?}", l.parameters);
        let (mc, tol) = monte_carlo(&s, kind, 1000);
        let off = outside(&l, &mc, &tol);
        assert!(off.is_empty(), "{}: {off:#?}", kind.name());
        let as_ekf = outside(&ekf, &mc, &tol);
        assert!(
            !as_ekf.is_empty(),
            "{}: the EKF's LinCov also agrees, the test cannot tell the fusion from an EKF",
            kind.name()
        );
    }
}
