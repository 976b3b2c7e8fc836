//! USKF-NN on the three real Mars-GRAM 2010 Monte Carlo sets of `../shared/data/gram/` (20°S,
//! 60°S, 80°S; 200 dispersed profiles each, `DENSTOT` as the truth, placed by their `Radius`
//! column): the run of `entrynav trade --scenario msl-airdata --filters uskf-nn --runs 40
//! --seed 5 --atmosphere-file LATxxS.txt` (issue 49, item 4; docs/density.md, "Polar Mars-GRAM
//! sets"). The sets are gzip-compressed; `gzip -dc` decompresses them into memory.

use entrynav::atmosphere::AtmosphereConfig;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::{FilterReport, McOptions, run_trade};
use std::path::PathBuf;
use std::process::Command;

fn gram_text(lat: &str) -> String {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "..",
        "..",
        "shared",
        "data",
        "gram",
    ]
    .iter()
    .collect::<PathBuf>()
    .join(format!("LAT{lat}S.txt.gz"));
    let out = Command::new("gzip")
        .arg("-dc")
        .arg(&path)
        .output()
        .unwrap_or_else(|e| panic!("gzip -dc {}: {e}", path.display()));
    assert!(
        out.status.success(),
        "gzip -dc {}: {} (the Mars-GRAM sets live in ../shared/data/gram/)",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("the Mars-GRAM set is text")
}

/// `msl-airdata` with the set's profiles as the truth (run k flies profile k mod 200, no
/// synthetic perturbation, as `trade --atmosphere-file` does) and `slope_window` as given.
fn trade(lat: &str, slope_window: Option<usize>, runs: usize) -> FilterReport {
    trade_with(lat, slope_window, None, runs)
}

/// As [`trade`], with `filter.density.consider_match_epochs` as given.
fn trade_with(
    lat: &str,
    slope_window: Option<usize>,
    match_epochs: Option<usize>,
    runs: usize,
) -> FilterReport {
    let mut cfg = ScenarioConfig::builtin("msl-airdata").unwrap();
    cfg.truth.atmosphere = toml::from_str::<AtmosphereConfig>(&format!(
        "model = 'table'\nfile = 'LAT{lat}S.txt'\nformat = 'mars-gram'"
    ))
    .unwrap();
    cfg.truth.perturbation = None;
    let density = cfg.filter.density.as_mut().unwrap();
    density.slope_window = slope_window;
    density.consider_match_epochs = match_epochs;
    let text = gram_text(lat);
    let load = |_: &str| Ok(text.clone());
    let s = Scenario::build(cfg, &load).unwrap();
    assert_eq!(s.truth_profiles.as_ref().unwrap().count(), 200);
    let mut opts = McOptions::new(runs, 5);
    opts.pcrlb = false;
    let t = run_trade(&s, &[FilterKind::UskfNn], &opts, &|_| {}).unwrap();
    t.filters.into_iter().next().unwrap()
}

/// The default `msl-airdata` (local level-and-slope correction over 2 epochs) keeps the density
/// profile error below 1 % on all three sets with the trade's 40 runs (measured 0.219 %, 0.238 %,
/// 0.251 %; before the correction 0.408 %, 2.407 %, 2.976 %), with no failed or diverged run.
/// Without the correction (no `slope_window`, seed 001's adaptation) the 80°S set is above 1 %
/// on 10 runs, so the set still exercises what the correction fixes.
#[test]
fn uskf_nn_holds_one_percent_on_the_polar_mars_gram_sets() {
    let mut line = String::new();
    for lat in ["20", "60", "80"] {
        let f = trade(lat, Some(2), 40);
        let pct = f.density_rmspe_pct.unwrap();
        let r = f.rmse_time_avg["r_m"].unwrap();
        line += &format!(" {lat}°S {pct:.3} % (r {r:.1} m);");
        assert!(pct < 1.0, "LAT{lat}S: density RMSPE {pct} %");
        assert_eq!((f.failed, f.diverged), (0, 0), "LAT{lat}S");
    }
    let before = trade("80", None, 10).density_rmspe_pct.unwrap();
    eprintln!(
        "USKF-NN density RMSPE, 40 runs, seed 5:{line} 80°S without the correction, 10 runs: {before:.3} %"
    );
    assert!(before > 1.0, "LAT80S without the correction: {before} %");
}

/// Issue 49: with the consider parameter's variance matched to the correction's one-step
/// prediction error (`consider_match_epochs = 10`), USKF-NN is in its per-epoch NEES band on the
/// polar sets, where `msl-airdata` as shipped is optimistic: 40 runs, seed 5, measured ANEES/dof
/// 1.22 → 0.89 and 30 % → 60 % of epochs in band at 60°S, 1.44 → 1.06 and 3 % → 90 % at 80°S
/// (20°S: 1.19 → 0.93, 48 % → 66 %), density RMSPE and position RMSE equal or lower.
#[test]
fn matched_consider_variance_puts_uskf_nn_in_its_band_on_the_polar_sets() {
    let mut line = String::new();
    for lat in ["60", "80"] {
        let (before, after) = (
            trade(lat, Some(2), 40),
            trade_with(lat, Some(2), Some(10), 40),
        );
        let dof = after.consistency.nees_dof as f64;
        let (a0, a1) = (
            before.consistency.anees.unwrap() / dof,
            after.consistency.anees.unwrap() / dof,
        );
        let (b0, b1) = (
            before.consistency.nees_in_bounds_frac.unwrap(),
            after.consistency.nees_in_bounds_frac.unwrap(),
        );
        let (p0, p1) = (
            before.rmse_time_avg["pos_m"].unwrap(),
            after.rmse_time_avg["pos_m"].unwrap(),
        );
        line += &format!(
            " {lat}°S ANEES/dof {a0:.3} -> {a1:.3}, in band {b0:.2} -> {b1:.2}, pos {p0:.1} -> {p1:.1} m;"
        );
        assert!((0.8..=1.25).contains(&a1), "LAT{lat}S: ANEES/dof {a1}");
        assert!(
            b1 >= 0.5 && b1 > b0 + 0.2,
            "LAT{lat}S: in band {b0} -> {b1}"
        );
        assert!(p1 <= 1.02 * p0, "LAT{lat}S: position RMSE {p0} -> {p1} m");
        assert!(after.density_rmspe_pct.unwrap() < 1.0, "LAT{lat}S");
        assert_eq!((after.failed, after.diverged), (0, 0), "LAT{lat}S");
    }
    eprintln!("USKF-NN, 40 runs, seed 5, consider_match_epochs = 10:{line}");
}
