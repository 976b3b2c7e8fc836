//! A density table as the truth mean atmosphere (`--atmosphere-file`, `--no-perturbation`):
//! good profiles become the truth, bad ones are refused naming the file, the line and the problem.

use entrynav::atmosphere::{Atmosphere, AtmosphereConfig, mars_mean_profile};
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav_studies::StudyError;
use entrynav_studies::scenario::TruthAtmosphere;
use entrynav_studies::scenario::truth_atmosphere::check_profile_covers;
use std::path::PathBuf;

fn write(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "entrynav-truth-atmosphere-tests-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn table(lo_km: usize, hi_km: usize, csv: bool) -> String {
    let m = mars_mean_profile();
    let mut s = if csv {
        "height_km,density\n".to_string()
    } else {
        "# Mars-GRAM style\n Height(km)   Lat  DENSTOT\n".to_string()
    };
    for h in lo_km..=hi_km {
        let rho = 1.1 * m.density(h as f64 * 1e3);
        if csv {
            s += &format!("{h},{rho:e}\n");
        } else {
            s += &format!("  {h:.3}  -3.9  {rho:.6E}\n");
        }
    }
    s
}

fn truth_atmosphere(
    cfg: ScenarioConfig,
    file: Option<&PathBuf>,
    no_perturbation: bool,
) -> Result<ScenarioConfig, StudyError> {
    let args = file.map(TruthAtmosphere::file).unwrap_or_default();
    args.apply(cfg, no_perturbation)
}

fn build(cfg: ScenarioConfig) -> Result<Scenario, StudyError> {
    Ok(entrynav_loader::build(cfg, std::path::Path::new("."))?)
}

fn msl() -> ScenarioConfig {
    ScenarioConfig::builtin("msl-airdata").unwrap()
}

#[test]
fn a_good_profile_becomes_the_truth_mean_with_or_without_perturbation() {
    for csv in [true, false] {
        let p = write(
            if csv { "good.csv" } else { "good.txt" },
            &table(0, 150, csv),
        );
        let cfg = truth_atmosphere(msl(), Some(&p), false).unwrap();
        assert!(matches!(
            cfg.truth.atmosphere,
            AtmosphereConfig::Table { .. }
        ));
        assert!(cfg.truth.perturbation.is_some());
        let s = build(cfg).unwrap();
        check_profile_covers(&s, &p).unwrap();
        let h = 50e3_f64;
        let want = 1.1 * mars_mean_profile().density(h);
        assert!((s.truth_model.atmosphere.density(h) / want - 1.0).abs() < 1e-5);
    }
    let cfg = truth_atmosphere(msl(), None, true).unwrap();
    assert!(cfg.truth.perturbation.is_none());
}

#[test]
fn bad_profiles_are_refused_naming_file_line_and_problem() {
    let good = table(0, 150, true);
    let cases = [
        (
            "nonmono.csv",
            good.replace("\n40,", "\n38.5,"),
            "lines",
            "order",
        ),
        (
            "repeat.csv",
            good.replace("\n40,", "\n39,"),
            "lines",
            "repeats",
        ),
        (
            "negative.csv",
            good.replace(&good.lines().nth(21).unwrap().to_string(), "20,-1e-3"),
            "line 22",
            "not positive",
        ),
        (
            "malformed.csv",
            good.replace("\n30,", "\n3O,"),
            "line 32",
            "not a number",
        ),
    ];
    for (name, text, line, problem) in cases {
        let p = write(name, &text);
        let err = truth_atmosphere(msl(), Some(&p), false)
            .and_then(build)
            .err()
            .unwrap_or_else(|| panic!("{name} accepted"));
        let msg = err.to_string();
        assert!(
            msg.contains(name) && msg.contains(line) && msg.contains(problem),
            "{name}: {msg}"
        );
    }
    // A profile that stops at 100 km does not cover the 126 km entry interface.
    let p = write("short.csv", &table(0, 100, true));
    let s = build(truth_atmosphere(msl(), Some(&p), false).unwrap()).unwrap();
    let msg = check_profile_covers(&s, &p).unwrap_err().to_string();
    assert!(
        msg.contains("short.csv") && msg.contains("lines 2-102") && msg.contains("100.000 km"),
        "{msg}"
    );
}
