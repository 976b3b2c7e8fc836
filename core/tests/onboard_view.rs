//! The rule ARCHITECTURE.md puts first: a filter sees only what the vehicle knows onboard. A
//! scenario whose truth differs (atmosphere, density bias, perturbation, vehicle, a Mars-GRAM
//! profile set) gives the same onboard view, and so the same filter start; the climatology
//! UKF-AC forms its initial correction factor from is a filter-side setting
//! (`filter.density.climatology`).

use entrynav::atmosphere::Atmosphere;
use entrynav::estimation::nav::FilterStart;
use entrynav::estimation::nav::ukf_ac::UkfAcNav;
use entrynav::files::FileError;
use entrynav::scenario::{Scenario, ScenarioConfig};

/// Three stacked Mars-GRAM-like profiles (the height restarts at each) whose densities differ
/// by a factor per profile, in Mars-GRAM's column layout.
fn profile_set(path: &str) -> Result<String, FileError> {
    if path != "set.txt" {
        return Err(FileError::new(path, "no such file (test loader)"));
    }
    let mut text = String::from("#   Var_X    DENSTOT    Radius\n");
    for factor in [3.0, 1.0, 0.3] {
        for i in -5..=140 {
            let h = i as f64;
            let rho = factor * 0.0166 * (-h / 10.5).exp();
            text.push_str(&format!("{h:9.4} {rho:10.3E} {:9.3}\n", 3395.419 + h));
        }
    }
    Ok(text)
}

fn build(text: &str) -> Scenario {
    let cfg = ScenarioConfig::from_toml_str(text, "test.toml").unwrap_or_else(|e| panic!("{e}"));
    Scenario::build(cfg, &profile_set).unwrap_or_else(|e| panic!("{e}"))
}

fn builtin() -> String {
    entrynav::scenario::builtin_toml("msl-airdata")
        .unwrap()
        .to_string()
}

/// UKF-AC's initial correction factor 𝒦₀ on the scenario's onboard view.
fn initial_k(s: &Scenario) -> f64 {
    let start = FilterStart::<8>::with_estimate(&s.onboard, &s.onboard.initial_estimate);
    UkfAcNav::<8, 9>::new(&s.onboard, &start)
        .expect("UKF-AC builds")
        .correction_factor()
        .0
}

/// Replace the `[truth.atmosphere]` table and the truth vehicle of the built-in.
fn other_truth(atmosphere: &str) -> String {
    let text = builtin();
    let text = text.replace(
        "[truth.atmosphere]\nmodel = \"mars-mean\"",
        &format!("[truth.atmosphere]\n{atmosphere}"),
    );
    assert_ne!(text, builtin(), "the truth atmosphere was replaced");
    let text = text.replace(
        "[truth.vehicle]\ncd_s_over_m_m2kg = 7.1e-3",
        "[truth.vehicle]\ncd_s_over_m_m2kg = 7.6e-3",
    );
    text.replace("\nscale = 1.0", "\nscale = 2.0")
        .replace("[truth]\n", "[truth]\ndensity_bias = 0.2\n")
}

#[test]
fn a_different_truth_leaves_the_onboard_view_unchanged() {
    let base = build(&builtin());
    let exponential = build(&other_truth(
        "model = \"exponential\"\nrho_ref_kgm3 = 2e-4\nref_radius_km = 3437.2\nscale_height_km = 7.5",
    ));
    let gram = build(&other_truth(
        "model = \"table\"\nfile = \"set.txt\"\nformat = \"mars-gram\"",
    ));
    // The truths do differ.
    let h = 60e3;
    let rho = |s: &Scenario| -> f64 { s.truth_model.atmosphere.density(h) };
    assert!((rho(&base) / rho(&exponential) - 1.0).abs() > 0.05);
    assert!((rho(&base) / rho(&gram) - 1.0).abs() > 0.05);
    // The onboard views do not.
    let view = |s: &Scenario| format!("{:?}", s.onboard);
    assert_eq!(view(&base), view(&exponential));
    assert_eq!(view(&base), view(&gram));
    assert_eq!(initial_k(&base), initial_k(&exponential));
    assert_eq!(initial_k(&base), initial_k(&gram));
}

#[test]
fn the_climatology_is_the_filter_side_setting() {
    let base = build(&builtin());
    // msl-airdata carries the mars-mean climatology: 𝒦₀ is its ratio to the exponential
    // onboard model at the initial altitude (the onboard model is fitted to that profile).
    let k = initial_k(&base);
    assert!(
        k.is_finite() && (k - 1.0).abs() > 0.01 && (k - 1.0).abs() < 0.5,
        "{k}"
    );
    // Without a climatology the filter's own atmosphere is it: 𝒦₀ = 1 exactly.
    let none = builtin().replace("climatology = { model = \"mars-mean\" }", "");
    assert_ne!(none, builtin());
    assert_eq!(initial_k(&build(&none)), 1.0);
    // An explicit climatology changes 𝒦₀ and nothing in the truth.
    let explicit = builtin().replace(
        "climatology = { model = \"mars-mean\" }",
        "climatology = { model = \"table\", file = \"set.txt\", format = \"mars-gram\", profile = 2 }",
    );
    let s = build(&explicit);
    assert_ne!(initial_k(&s), k);
    assert_eq!(
        s.truth_model.atmosphere.density(60e3),
        base.truth_model.atmosphere.density(60e3)
    );
}

#[test]
fn a_climatology_of_several_profiles_is_refused_naming_the_field() {
    let text = builtin().replace(
        "climatology = { model = \"mars-mean\" }",
        "climatology = { model = \"table\", file = \"set.txt\", format = \"mars-gram\" }",
    );
    let cfg = ScenarioConfig::from_toml_str(&text, "t.toml").unwrap();
    let err = Scenario::build(cfg, &profile_set).unwrap_err().to_string();
    assert!(
        err.contains("filter.density.climatology") && err.contains("3 profiles"),
        "{err}"
    );
}

#[test]
fn a_climatology_out_of_range_is_refused_at_load_naming_the_field() {
    let text = builtin().replace(
        "climatology = { model = \"mars-mean\" }",
        "climatology = { model = \"exponential\", rho_ref_kgm3 = 0.02, ref_radius_km = 3396.2, scale_height_km = -3.0 }",
    );
    let err = ScenarioConfig::from_toml_str(&text, "t.toml")
        .expect_err("a negative scale height must be refused")
        .to_string();
    assert!(
        err.contains("filter.density.climatology.scale_height_km") && err.contains("-3"),
        "{err}"
    );
}
