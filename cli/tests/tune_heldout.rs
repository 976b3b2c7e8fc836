//! `entrynav tune` on an entry nobody tuned by hand (issue "Navigation that holds where nobody
//! tuned it", case 1): a Pathfinder-like ballistic entry with three ground beacons and one
//! orbiter, a truth atmosphere (mars-mean, 8 km-correlated perturbations) that the onboard
//! exponential model with an estimated ρ0 does not follow, and a default-looking constant Q.
//! As given, both filters diverge in every run. The tuned file is better on every primary figure,
//! so tune writes it; the test then checks it on 200 runs of a seed the tuning never saw.
//!
//! Measured (seed 7, 200 runs): EKF ANEES/dof 37229 -> 0.88, ANIS/dof 4.54 -> 1.02, position
//! RMSE 669 -> 146 m, divergences 200 -> 0, epochs in the NEES band 0 -> 34 %; UKF 37035 -> 0.80,
//! 4.67 -> 0.99, 667 -> 201 m, 200 -> 0, 14 -> 13 %. The target of half the epochs in the
//! band is not reached yet (tune says so and exits 1); the test holds what is.
//!
//! Case 2 is a lifting entry at 60°S flown through real Mars-GRAM Monte Carlo profiles, with L/D
//! and β dispersed but estimated by no filter: as it is today no Q makes it consistent, and tune
//! must say so by channel and cause, write the file and exit 1.

mod common;

use common::{num, scratch_dir, trade_filters, tune_defaults};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn input() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/heldout-ballistic-beacons.toml")
}

/// Case 2 in `dir`, beside the decompressed Mars-GRAM set it flies (../shared/data/gram).
fn polar_input(dir: &Path) -> PathBuf {
    use std::io::Read;
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let gz = manifest.join("../../shared/data/gram/LAT60S.txt.gz");
    let file = std::fs::File::open(&gz).unwrap_or_else(|e| panic!("{}: {e}", gz.display()));
    let mut text = String::new();
    flate2::read::GzDecoder::new(file)
        .read_to_string(&mut text)
        .unwrap();
    std::fs::write(dir.join("LAT60S.txt"), text).unwrap();
    let scenario = dir.join("heldout-lifting-polar.toml");
    std::fs::copy(
        manifest.join("tests/data/heldout-lifting-polar.toml"),
        &scenario,
    )
    .unwrap();
    scenario
}

/// The filters' blocks of a 200-run trade on seed 7 (not the tuning's seed).
fn trade(scenario: &Path, json: &Path, filters: &str) -> Vec<Value> {
    trade_filters(scenario, filters, 200, 7, json)
}

#[test]
fn tune_writes_a_tuning_better_on_every_primary_figure_and_it_holds_on_fresh_runs() {
    let dir = scratch_dir("tune", "heldout");
    let out = dir.join("tuned.toml");
    let (code, stdout, err) = tune_defaults(&input(), "ekf,ukf", &out);
    // Never refused: written, with a warning and exit code 1 while a target is still missed.
    assert!(!err.contains("not written"), "{err}");
    assert!(code == 0 || code == 1, "{stdout}\n{err}");
    if code == 1 {
        assert!(err.contains("written, but not consistent yet"), "{err}");
    }
    let before = trade(&input(), &dir.join("before.json"), "ekf,ukf");
    let after = trade(&out, &dir.join("after.json"), "ekf,ukf");
    for (b, a) in before.iter().zip(&after) {
        let name = a["name"].as_str().unwrap();
        let per_dof = |f: &Value| num(f, "anees") / num(f, "nees_dof");
        let anis = |f: &Value| num(f, "anis_per_dof");
        let rmse = |f: &Value| num(&f["rmse_time_avg"], "pos_m");
        assert_eq!(
            num(b, "diverged"),
            200.0,
            "{name}: the input no longer diverges"
        );
        assert_eq!(num(a, "diverged") + num(a, "failed"), 0.0, "{name}");
        for (label, v) in [("ANEES/dof", per_dof(a)), ("ANIS/dof", anis(a))] {
            assert!((0.7..=1.5).contains(&v), "{name}: {label} {v}");
        }
        assert!(
            rmse(a) < 0.5 * rmse(b),
            "{name}: position RMSE {} -> {}",
            rmse(b),
            rmse(a)
        );
        let band = |f: &Value| num(f, "nees_in_bounds_frac");
        assert!(
            band(a) >= band(b) - 0.05,
            "{name}: epochs in the NEES band {} -> {}",
            band(b),
            band(a)
        );
    }
}

/// Case 1 with the density error modelled where it lives: the estimated ρ0 driven as a
/// Gauss–Markov process over 8 km of altitude (`density_sigma` 0.1) and a 1 % lift-plane
/// load-scaled noise, tuned by the same command. Measured on seed 7 (200 runs): UKF 56 % of
/// epochs in the NEES band (constant Q tuned: 13 %), ANEES/dof 1.04, position RMSE 141 m
/// (constant Q tuned: 201 m); EKF 27 % (34 %), 0.96, 156 m (146 m).
#[test]
fn a_density_error_in_altitude_brings_the_ukf_into_its_band() {
    let dir = scratch_dir("tune", "heldout-density");
    let text = std::fs::read_to_string(input()).unwrap().replacen(
        "[filter.vehicle]",
        "[filter.process_noise]\nmodel = \"aero-scaled\"\nfraction = [0.0, 0.01, 0.01]\n\
         correlation_length_m = 8000.0\ndensity_sigma = 0.1\n\n[filter.vehicle]",
        1,
    );
    let density = dir.join("density.toml");
    std::fs::write(&density, text).unwrap();
    let mut ukf_band = Vec::new();
    let mut ukf_rmse = Vec::new();
    for (name, scenario) in [("constant", input()), ("density", density)] {
        let out = dir.join(format!("{name}-tuned.toml"));
        let (code, stdout, err) = tune_defaults(&scenario, "ukf", &out);
        assert!(code == 0 || code == 1, "{name}: {stdout}\n{err}");
        let f = trade(&out, &dir.join(format!("{name}.json")), "ukf").remove(0);
        assert_eq!(num(&f, "diverged") + num(&f, "failed"), 0.0, "{name}");
        ukf_band.push(num(&f, "nees_in_bounds_frac"));
        ukf_rmse.push(num(&f["rmse_time_avg"], "pos_m"));
        if name == "density" {
            let per_dof = num(&f, "anees") / num(&f, "nees_dof");
            assert!((0.7..=1.5).contains(&per_dof), "ANEES/dof {per_dof}");
        }
    }
    assert!(
        ukf_band[1] >= 0.45 && ukf_band[1] > ukf_band[0] + 0.2,
        "UKF epochs in the NEES band: constant Q {} -> density in altitude {}",
        ukf_band[0],
        ukf_band[1]
    );
    assert!(
        ukf_rmse[1] < ukf_rmse[0],
        "UKF position RMSE: constant Q {} m -> density in altitude {} m",
        ukf_rmse[0],
        ukf_rmse[1]
    );
}

/// Measured: on the fresh runs the EKF ends at ANEES/dof 6.4 with accelerometer y and z
/// innovations 25x and 23x their predicted variance, the UKF at ANEES/dof 2.0 and ANIS/dof 0.44;
/// both diverged in 96-98 of 100 runs as given and in none after.
#[test]
fn a_tuning_still_inconsistent_is_written_with_the_channel_and_cause_and_exit_1() {
    let dir = scratch_dir("tune", "heldout-polar");
    let input = polar_input(&dir);
    let out = dir.join("tuned.toml");
    let (code, stdout, err) = tune_defaults(&input, "ekf,ukf", &out);
    assert_eq!(code, 1, "{stdout}\n{err}");
    assert!(
        err.contains("written, but not consistent yet: ekf is still inconsistent"),
        "{err}"
    );
    // The EKF's lift-plane accelerometer channels are named with the likely cause.
    let ekf = err
        .split("ukf is still inconsistent")
        .next()
        .unwrap_or_default();
    assert!(
        ["accel_y_mps2", "accel_z_mps2"]
            .iter()
            .any(|ch| ekf.contains(&format!("{ch} innovations"))),
        "{ekf}"
    );
    assert!(ekf.contains("an unmodelled lift or density error"), "{ekf}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("# WARNING: ekf is still inconsistent"),
        "{text}"
    );
}
