//! Issue 49: the recommended filter of `msl-airdata` (USKF-NN) with its own load-scaled process
//! noise and no constant Q (scenario file, `[filter.tuned.uskf-nn]`) and the re-sized consider
//! parameter (`filter.density.consider_*`). With Table 2's constant Q and Table 4's consider
//! settings it was conservative everywhere: ANEES/dof 0.46, no epoch in the NEES band, position
//! RMSE 48 / 62 m (200 runs, seeds 1 and 2). This holds what the change bought, on seeds it was not
//! chosen on, so that it cannot silently regress.
//!
//! Not yet the goal (≥ 80 % of epochs in band at 200 runs): at 200 runs it is 24–73 % on
//! seeds 1–4 (docs/process-noise.md, "msl-airdata's USKF-NN"). The floor below is for 60 runs, whose
//! band is √(200/60) ≈ 1.8× wider than at 200 runs.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::{McOptions, run_trade};

/// Measured at 60 runs: seed 11 76 %, seed 12 74 % (with Table 2's Q on C_D S/m and L/D, which
/// this built-in had before: 83 % and 48 %; 60-run sets scatter that much).
const IN_BAND_FLOOR: f64 = 0.5;

#[test]
fn msl_airdata_uskf_nn_is_near_its_nees_band_and_twice_as_accurate() {
    let s = Scenario::build(
        ScenarioConfig::builtin("msl-airdata").unwrap(),
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
    let anees = c.anees.unwrap() / c.nees_dof as f64;
    let in_band = c.nees_in_bounds_frac.unwrap();
    let pos = f.rmse_time_avg.get("pos_m").copied().flatten().unwrap();
    assert_eq!(f.failed + f.diverged, 0, "no failed or diverged run");
    assert!(
        (0.8..=1.25).contains(&anees),
        "ANEES/dof {anees:.3} (was 0.46 with Table 2's Q)"
    );
    assert!(
        in_band >= IN_BAND_FLOOR,
        "{:.0} % of epochs in the 60-run NEES band, floor {:.0} %",
        100.0 * in_band,
        100.0 * IN_BAND_FLOOR
    );
    assert!(
        pos < 35.0,
        "time-averaged position RMSE {pos:.1} m (was 48 m)"
    );
}
