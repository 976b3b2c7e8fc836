//! Innovation gating and beacon exclusion (issue 30) on the built-ins, as a user judges them:
//! with faults the gated filters stay consistent and near their fault-free accuracy and exclude
//! the biased beacon within seconds; without the gate the same runs are ruined; without faults
//! the gate changes nothing that matters and excludes nobody.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::monte_carlo::report::FilterReport;
use entrynav::sim::{McOptions, run_trade};

const RUNS: usize = 100;

fn build(cfg: ScenarioConfig) -> Scenario {
    Scenario::build(cfg, &entrynav::files::no_files).unwrap()
}

fn trade(s: &Scenario) -> Vec<FilterReport> {
    let opts = McOptions {
        runs: RUNS,
        seed: 1,
        chunk: 64,
        pcrlb: false,
        cancel: None,
    };
    run_trade(s, &[FilterKind::Ekf, FilterKind::Dcifaif], &opts, &|_| {})
        .unwrap()
        .filters
}

fn pos(f: &FilterReport, final_: bool) -> f64 {
    let m = if final_ {
        &f.rmse_final
    } else {
        &f.rmse_time_avg
    };
    m["pos_m"].unwrap()
}

fn anees_per_dof(f: &FilterReport) -> f64 {
    f.consistency.anees.unwrap() / f.consistency.nees_dof as f64
}

#[test]
fn faults_are_survived_with_the_gate_and_ruin_the_filters_without_it() {
    let faulty = ScenarioConfig::builtin("four-beacon-fusion-faults").unwrap();
    let mut clean = faulty.clone();
    clean.faults.clear();
    let mut ungated = faulty.clone();
    ungated.filter.gating.as_mut().unwrap().enabled = false;
    let (faulty, clean, ungated) = (
        trade(&build(faulty)),
        trade(&build(clean)),
        trade(&build(ungated)),
    );
    for ((f, c), u) in faulty.iter().zip(&clean).zip(&ungated) {
        let name = &f.name;
        let a = anees_per_dof(f);
        assert!(
            (0.7..=1.5).contains(&a),
            "{name}: ANEES/dof {a} with faults and gate"
        );
        assert!(
            pos(f, true) <= 1.5 * pos(c, true),
            "{name}: final position RMSE {} with faults vs {} without",
            pos(f, true),
            pos(c, true)
        );
        let g = f
            .gating
            .as_ref()
            .expect("the faulty built-in runs behind a gate");
        let o2 = &g.per_beacon["orbiter-2"];
        let within = o2.detected_within_10s_frac.unwrap();
        assert!(
            within >= 0.99,
            "{name}: orbiter-2 excluded within 10 s in {within} of runs"
        );
        assert_eq!(g.false_exclusion_run_frac, 0.0, "{name}: false exclusions");
        // The 1 % outliers are rejected: 0.5 % of all ranges (from 30 s on) plus the biased ones
        // before exclusion.
        assert!(
            g.rejected_frac > 0.003 && g.rejected_frac < 0.02,
            "{name}: {}",
            g.rejected_frac
        );
        assert!(u.gating.is_none());
        assert!(
            pos(u, true) > 50.0 * pos(f, true),
            "{name}: without the gate the faults should ruin the estimate ({} m vs {} m)",
            pos(u, true),
            pos(f, true)
        );
    }
}

#[test]
fn without_faults_the_gate_changes_accuracy_by_under_two_percent_and_excludes_nobody() {
    let mut gated = ScenarioConfig::builtin("four-beacon-fusion-faults").unwrap();
    gated.faults.clear();
    let plain = build(ScenarioConfig::builtin("four-beacon-fusion").unwrap());
    let (gated, plain) = (trade(&build(gated)), trade(&plain));
    for (g, p) in gated.iter().zip(&plain) {
        let change = pos(g, false) / pos(p, false) - 1.0;
        assert!(
            change.abs() < 0.02,
            "{}: gate changes the RMSE by {change}",
            g.name
        );
        let s = g.gating.as_ref().unwrap();
        assert_eq!(s.false_exclusion_run_frac, 0.0, "{}", g.name);
        assert!(s.per_beacon.is_empty(), "{}: {:?}", g.name, s.per_beacon);
        // A consistent filter loses 1 − p = 1e-4 of its measurements to the gate.
        assert!(
            s.rejected_frac < 1e-3,
            "{}: rejected {}",
            g.name,
            s.rejected_frac
        );
        let before = s.anis_before_gating_per_dof.unwrap();
        assert!(
            (0.8..1.2).contains(&before),
            "{}: ANIS before gating {before}",
            g.name
        );
    }
}

#[test]
fn a_stuck_range_is_excluded_and_survived() {
    let text = ScenarioConfig::builtin("four-beacon-fusion-faults")
        .unwrap()
        .to_toml_string();
    // Replace the faults with one: orbiter-1's range frozen from 100 s.
    let head = text.split("[[faults]]").next().unwrap().to_string();
    let text =
        head + "[[faults]]\nkind = \"range-stuck\"\nbeacon = \"orbiter-1\"\nstart_s = 100.0\n";
    let stuck = build(ScenarioConfig::from_toml_str(&text, "stuck.toml").unwrap());
    for f in trade(&stuck) {
        let g = f.gating.as_ref().unwrap();
        let o1 = &g.per_beacon["orbiter-1"];
        assert_eq!(o1.detected_runs, RUNS as u64, "{}: {o1:?}", f.name);
        assert!(o1.detection_max_s.unwrap() <= 10.0, "{}: {o1:?}", f.name);
        assert_eq!(g.false_exclusion_run_frac, 0.0, "{}", f.name);
        let a = anees_per_dof(&f);
        assert!((0.7..=1.5).contains(&a), "{}: ANEES/dof {a}", f.name);
    }
}

#[test]
fn a_fault_on_an_unknown_beacon_is_refused_by_name() {
    let text = ScenarioConfig::builtin("four-beacon-fusion-faults")
        .unwrap()
        .to_toml_string()
        .replace("beacon = \"orbiter-2\"", "beacon = \"orbiter-9\"");
    let err = ScenarioConfig::from_toml_str(&text, "t.toml")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("faults[0].beacon") && err.contains("orbiter-9"),
        "{err}"
    );
    let text = ScenarioConfig::builtin("four-beacon-fusion-faults")
        .unwrap()
        .to_toml_string()
        .replace("probability = 0.9999", "probability = 0.5");
    let err = ScenarioConfig::from_toml_str(&text, "t.toml")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("filter.gating.probability") && err.contains("0.5"),
        "{err}"
    );
}
