//! Issue 49: the recommended filter of `msl-airdata` and `msl-guided` (USKF-NN) with its own
//! load-scaled process noise and no constant Q (scenario file, `[filter.tuned.uskf-nn]`) and the
//! re-sized consider parameter (`filter.density.consider_*`). With Table 2's constant Q and Table
//! 4's consider settings it was conservative everywhere: ANEES/dof 0.46, no epoch in the NEES band,
//! position RMSE 45–48 m (200 runs, seeds 1 and 2). This holds what the change bought, on a seed it
//! was not chosen on, so that it cannot silently regress.
//!
//! Not yet the goal (≥ 80 % of epochs in band at 200 runs): at 200 runs it is 24–73 % on
//! seeds 1–4 for msl-airdata, 22 % on seed 1 for msl-guided since issue 50 (docs/process-noise.md). The
//! floors below are for 60 runs, whose band is √(200/60) ≈ 1.8× wider than at 200 runs.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::{McOptions, run_trade};

/// Measured at 60 runs: seed 11 76 %, seed 12 74 % (with Table 2's Q on C_D S/m and L/D, which
/// this built-in had before: 83 % and 48 %; 60-run sets scatter that much).
const IN_BAND_FLOOR: f64 = 0.5;

/// msl-guided (no level-and-slope correction, c at 3 % over 60 s), measured at 60 runs: seed 11
/// 50 %, seed 12 71 %; before issue 49's noise 0 %. Since issue 50's defaults (MSL-class
/// dispersions, 45° reference bank; the longer entry adds late epochs where the flight-path
/// angle is optimistic, docs/process-noise.md): seed 11 just under 35 % (the old floor).
const GUIDED_IN_BAND_FLOOR: f64 = 0.25;

/// USKF-NN on built-in `name`, 60 runs of seed 11: (ANEES/dof, share of epochs in the NEES band,
/// time-averaged position RMSE [m], failed + diverged runs).
fn uskf_nn_on(name: &str) -> (f64, f64, f64, u64) {
    let s = Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap();
    let opts = McOptions {
        runs: 60,
        seed: 11,
        chunk: 64,
        pcrlb: false,
        cancel: None,
    };
    let r = run_trade(&s, &[FilterKind::UskfNn], &opts, &|_| {}).unwrap();
    let f = &r.filters[0];
    let c = &f.consistency;
    let pos = f.rmse_time_avg.get("pos_m").copied().flatten().unwrap();
    (
        c.anees.unwrap() / c.nees_dof as f64,
        c.nees_in_bounds_frac.unwrap(),
        pos,
        f.failed + f.diverged,
    )
}

/// The checks both built-ins share; `was` names the figures before issue 49.
fn assert_near_band(name: &str, floor: f64, was: &str) {
    let (anees, in_band, pos, bad) = uskf_nn_on(name);
    assert_eq!(bad, 0, "{name}: no failed or diverged run");
    assert!(
        (0.8..=1.25).contains(&anees),
        "{name}: ANEES/dof {anees:.3} ({was})"
    );
    assert!(
        in_band >= floor,
        "{name}: {:.0} % of epochs in the 60-run NEES band, floor {:.0} % ({was})",
        100.0 * in_band,
        100.0 * floor
    );
    assert!(
        pos < 35.0,
        "{name}: time-averaged position RMSE {pos:.1} m ({was})"
    );
}

#[test]
fn msl_airdata_uskf_nn_is_near_its_nees_band_and_twice_as_accurate() {
    assert_near_band(
        "msl-airdata",
        IN_BAND_FLOOR,
        "was ANEES/dof 0.46, 0 % in band, 48 m with Table 2's Q",
    );
}

#[test]
fn msl_guided_uskf_nn_is_near_its_nees_band_and_twice_as_accurate() {
    assert_near_band(
        "msl-guided",
        GUIDED_IN_BAND_FLOOR,
        "was ANEES/dof 0.46, 0 % in band, 45 m with Table 2's Q",
    );
}
