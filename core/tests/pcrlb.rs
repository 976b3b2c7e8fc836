//! The posterior Cramér–Rao lower bound as users read it in trade summaries: a matched,
//! consistent EKF sits just above it; a filter-free study gives the same bound as a trade.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::{McOptions, TradeReport, pcrlb_study, run_trade};

fn scenario(name: &str) -> Scenario {
    Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

fn trade(s: &Scenario, filters: &[FilterKind], runs: usize, seed: u64) -> TradeReport {
    let opts = McOptions::new(runs, seed);
    assert!(opts.pcrlb, "the bound is on by default");
    run_trade(s, filters, &opts, &|_| {}).unwrap()
}

fn get(m: &std::collections::BTreeMap<String, Option<f64>>, k: &str) -> f64 {
    m.get(k).copied().flatten().unwrap_or(f64::NAN)
}

#[test]
fn matched_ekf_on_ground_beacons_sits_just_above_the_bound() {
    // ground-beacons-3: the EKF's model is the truth's, its Q is tuned and it is consistent, so
    // its final position RMSE should be close to (and never far below) the PCRLB.
    let s = scenario("ground-beacons-3");
    let r = trade(&s, &[FilterKind::Ekf], 100, 1);
    let b = r.pcrlb.as_ref().expect("trade has a pcrlb block");
    assert!(b.available, "bound unavailable: {:?}", b.reason);
    let bound = get(&b.final_, "pos_m");
    let rmse = get(&r.filters[0].rmse_final, "pos_m");
    let eff = get(&r.filters[0].efficiency_final, "pos_m");
    assert!(
        (eff - rmse / bound).abs() < 1e-12 * eff,
        "efficiency = RMSE / PCRLB"
    );
    assert!(
        (0.9..=1.5).contains(&eff),
        "EKF final pos RMSE {rmse} m vs PCRLB {bound} m: efficiency {eff} outside [0.9, 1.5]"
    );
    // Every state's bound is positive and finite, and tightens from the start to deployment
    // as range information accumulates.
    for (name, v) in &b.final_ {
        let v = v.unwrap_or(f64::NAN);
        assert!(v.is_finite() && v > 0.0, "final bound of {name} is {v}");
    }
    let pos = &b.series["pos_m"];
    assert!(
        pos[pos.len() - 1] < 0.5 * pos[0],
        "position bound must shrink: {pos:?}"
    );
}

#[test]
fn observe_bound_without_filters_equals_the_trade_bound() {
    let s = scenario("orbiters-3");
    let r = trade(&s, &[FilterKind::Ekf], 24, 7);
    let t = r.pcrlb.unwrap();
    let o = pcrlb_study(&s, 7, 24).unwrap();
    assert!(o.available && t.available);
    for (k, v) in &t.final_ {
        let (a, b) = (v.unwrap(), o.final_[k].unwrap());
        assert!(
            (a - b).abs() <= 1e-9 * a.abs(),
            "{k}: trade {a} vs study {b}"
        );
    }
    let other = pcrlb_study(&s, 8, 24).unwrap();
    assert_ne!(
        other.final_["pos_m"], o.final_["pos_m"],
        "a different seed flies different truths"
    );
}
