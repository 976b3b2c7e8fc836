//! `[filter.tuned.<name>]`: one filter's own Q and assumed noise in place of the shared ones. The
//! onboard view a filter is built from carries them; every other filter keeps the shared tuning;
//! bad tables are refused naming the field.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{FilterRetuneConfig, NoiseInflation, Scenario, ScenarioConfig};
use entrynav::sensors::Noise;
use std::sync::Arc;

fn ground() -> ScenarioConfig {
    ScenarioConfig::builtin("ground-beacons-3").unwrap()
}

fn sigma(n: Noise) -> f64 {
    match n {
        Noise::Absolute(s) | Noise::Relative(s) => s,
    }
}

#[test]
fn a_filter_flies_its_own_tuning_and_the_others_the_shared_one() {
    let mut cfg = ground();
    let own_q: Vec<f64> = cfg.filter.q_diag.iter().map(|q| q * 1e3).collect();
    cfg.filter.noise_inflation = Some(NoiseInflation {
        range: 2.0,
        ..Default::default()
    });
    cfg.filter.tuned.insert(
        "ukf".into(),
        FilterRetuneConfig {
            q_diag: Some(own_q.clone()),
            process_noise: None,
            noise_inflation: Some(NoiseInflation {
                range: 3.0,
                ..Default::default()
            }),
        },
    );
    let sc = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    let shared = &sc.onboard;
    let ekf = shared.for_filter(FilterKind::Ekf);
    assert!(Arc::ptr_eq(&ekf, shared), "the EKF has no own tuning");
    let ukf = shared.for_filter(FilterKind::Ukf);
    assert_eq!(ukf.tuning.q_diag, own_q);
    for (own, sh) in ukf.channels.iter().zip(&shared.channels) {
        // Its own factor 3 in place of the shared 2 (not on top of it).
        let ratio = sigma(own.noise) / sigma(sh.noise);
        assert!((ratio - 1.5).abs() < 1e-12, "{}: {ratio}", own.name);
    }
    // The re-tuned view serves that filter only: it carries no further per-filter tunings.
    assert!(ukf.per_filter.is_empty());
}

fn refused(edit: impl FnOnce(&mut ScenarioConfig)) -> String {
    let mut cfg = ground();
    edit(&mut cfg);
    let text = cfg.to_toml_string();
    ScenarioConfig::from_toml_str(&text, "test")
        .map(|_| ())
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_per_filter_tables_are_refused_naming_the_field() {
    let err = refused(|c| {
        c.filter
            .tuned
            .insert("kalman".into(), FilterRetuneConfig::default());
    });
    assert!(
        err.contains("filter.tuned.kalman") && err.contains("unknown filter 'kalman'"),
        "{err}"
    );
    let err = refused(|c| {
        c.filter.tuned.insert(
            "ekf".into(),
            FilterRetuneConfig {
                q_diag: Some(vec![1.0; 5]),
                process_noise: None,
                noise_inflation: None,
            },
        );
    });
    assert!(
        err.contains("filter.tuned.ekf.q_diag") && err.contains("has 5 entries"),
        "{err}"
    );
    let err = refused(|c| {
        let mut q = c.filter.q_diag.clone();
        q[3] = -1.0;
        c.filter.tuned.insert(
            "ekf".into(),
            FilterRetuneConfig {
                q_diag: Some(q),
                process_noise: None,
                noise_inflation: None,
            },
        );
    });
    assert!(err.contains("filter.tuned.ekf.q_diag[3] = -1"), "{err}");
}
