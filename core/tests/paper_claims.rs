//! Claims docs/results.md makes about the papers' scenarios, checked as stated there.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::monte_carlo::filter_run;
use entrynav::sim::{McOptions, record_run, run_trade};

fn scenario(name: &str) -> Scenario {
    Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

/// docs/results.md, seed 000: the fast ∞-norm weights of eq. 21 move in the first 42 s (up to
/// 0.18 from 1/4 at t = 1 s) and are 0.25 ± 1e-9 from t = 43 s to the end, with or without the
/// fault — in every run, at every epoch, for every beacon; always a convex combination.
#[test]
fn dcifaif_fusion_weights_settle_at_a_quarter() {
    for name in ["four-beacon-fusion", "four-beacon-fusion-fault"] {
        let s = scenario(name);
        let (mut settled, mut early_max) = (0, 0.0_f64);
        for run in 0..12 {
            let rec = record_run(&s, 1, run).unwrap();
            let r = filter_run(&s, &s.onboard, &rec, FilterKind::Dcifaif);
            assert!(r.failure.is_none(), "{name} run {run}: {:?}", r.failure);
            for (t, e) in r.times.iter().zip(&r.epochs) {
                let w = e
                    .weights
                    .as_ref()
                    .expect("a fusion filter reports its weights");
                assert_eq!(w.len(), 4, "{name} run {run} t = {t}");
                assert!(
                    w.iter().all(|v| *v >= 0.0) && (w.iter().sum::<f64>() - 1.0).abs() < 1e-12,
                    "{name} run {run} t = {t}: {w:?}"
                );
                let off = w.iter().map(|v| (v - 0.25).abs()).fold(0.0, f64::max);
                if *t >= 43.0 {
                    assert!(off <= 1e-9, "{name} run {run} t = {t} s: weights {w:?}");
                    settled += 1;
                } else {
                    early_max = early_max.max(off);
                }
            }
        }
        assert!(
            settled >= 12 * 250,
            "{name}: only {settled} settled epochs checked"
        );
        // The early transient the page describes is there (a claim of "throughout" would fail).
        assert!(
            (0.1..0.25).contains(&early_max),
            "{name}: early deviation {early_max}"
        );
    }
}

/// docs/results.md, seed 003 scenario 1 (msl-pressure: IMU and dynamic pressure, Δ a consider
/// parameter): the paper's "position RMSE within 600 m, velocity RMSE within 0.3 m/s" at
/// deployment is met by both model banks (1000 runs: mmae 452 m / 0.23 m/s, mmae-moe
/// 488 m / 0.25 m/s) and missed by the EKF, which does not learn Δ (605 m / 0.71 m/s).
#[test]
fn seed_003_scenario_1_banks_deliver_within_600_m_and_0_3_mps() {
    let s = scenario("msl-pressure");
    let kinds = [FilterKind::Mmae, FilterKind::MmaeMoe, FilterKind::Ekf];
    let opts = McOptions {
        pcrlb: false,
        ..McOptions::new(300, 1)
    };
    let r = run_trade(&s, &kinds, &opts, &|_| {}).unwrap();
    for f in &r.filters {
        let pos = f.rmse_final["pos_m"].unwrap();
        let vel = f.rmse_final["vel_mps"].unwrap();
        assert_eq!((f.failed, f.diverged), (0, 0), "{}", f.name);
        if f.name == "ekf" {
            assert!(vel > 0.5, "the EKF cannot learn Δ: {vel} m/s");
        } else {
            assert!(pos < 600.0 && vel < 0.3, "{}: {pos} m, {vel} m/s", f.name);
            // ... and not by a wide margin that would hide a regression (docs: 452–488 m).
            assert!(
                pos > 380.0,
                "{}: {pos} m is below the PCRLB's ~380 m",
                f.name
            );
        }
    }
}
