//! `MarsEntryGuidance` with its start values (issue 52): an importer that simulates it alone
//! (fmpy, fmusim, the FMU Compliance Checker) sets no input, so the start values must be a state
//! guidance can fly. They are the default scenario's nominal entry (`msl-guided`'s filter start)
//! at `nav_time` = 0; held for the whole default experiment every step answers fmi2OK with finite
//! outputs, and an estimate that is truly invalid (radius 0) is still refused by name.

mod common;

use common::Inst;
use entrynav_fmu::vars::{
    GUIDED_SCENARIO_FILE, Key, MAX_STATES, Model, Value, entry_estimate, guided_scenario,
    guided_scenario_toml, variables,
};

fn guidance(tag: &str, logging_on: bool) -> Inst {
    let dir = std::env::temp_dir().join(format!(
        "entrynav-guidance-start-{tag}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(GUIDED_SCENARIO_FILE), guided_scenario_toml()).unwrap();
    Inst::with(Model::Guidance, Some(dir.to_str().unwrap()), logging_on)
}

fn start(key: Key) -> Option<Value> {
    variables(Model::Guidance)
        .into_iter()
        .find(|v| v.key == key)
        .and_then(|v| v.start)
}

#[test]
fn the_estimate_starts_at_the_default_scenarios_nominal_entry_at_nav_time_0() {
    let s = guided_scenario().unwrap();
    let entry = &s.onboard.initial_estimate;
    // Every slot: the kinematic states, msl-guided's augmented C_D S/m and L/D, then 0.
    assert_eq!(entry.len(), 8);
    assert_eq!(&entry_estimate()[..8], &entry[..]);
    for k in 0..MAX_STATES {
        let x = entry.get(k).copied().unwrap_or(0.0);
        assert_eq!(start(Key::EstX(k)), Some(Value::Real(x)), "est_x_{}", k + 1);
    }
    assert_eq!(start(Key::NavTime), Some(Value::Real(0.0)));
    assert_eq!(start(Key::NavStatusCode), Some(Value::Integer(0)));
    // A spherical filter model on msl-guided: the radius is the entry interface's, above the
    // planet and within the bounds guidance accepts.
    let radius = s.guidance_model().unwrap().planet.radius;
    assert!(!s.onboard.model.kind.is_cartesian());
    assert!(
        entry[0] > radius && entry[0] < 1.1 * radius,
        "r = {}",
        entry[0]
    );
    assert!(entry[3] > 5000.0, "v = {}", entry[3]);
}

#[test]
fn with_its_start_values_held_it_flies_the_default_experiment_without_a_warning() {
    let i = guidance("held", true);
    assert_eq!(i.init(), [0, 0, 0], "{:?}", i.messages());
    assert_eq!(i.int(Key::GuidanceStatus), 0);
    let reals = [
        Key::GuidanceBank,
        Key::GuidanceBankRate,
        Key::GuidanceCommand,
        Key::GuidanceTime,
        Key::SensedDrag,
        Key::RangeToGo,
        Key::Crossrange,
        Key::DeployTrigger,
    ];
    let limit = 20f64.to_radians() + 1e-12; // msl-guided: bank_rate_limit_deg_s = 20
    for k in 0..300 {
        assert_eq!(i.step(k as f64, 1.0), 0, "step {k}: {:?}", i.messages());
        for key in reals {
            let x = i.real(key);
            assert!(x.is_finite(), "{key:?} = {x} after step {k}");
        }
        assert!(i.real(Key::GuidanceBankRate).abs() <= limit);
        // Held at the entry speed the estimate never reaches the 450 m/s trigger.
        assert!(i.real(Key::DeployTrigger) > 0.0);
        assert!(!i.boolean(Key::Deployed));
        assert_eq!(i.int(Key::GuidanceStatus), 1);
        assert_eq!(i.int(Key::GuidanceStatusCode), 1);
    }
    assert_eq!(i.int(Key::GuidanceCycles), 300);
    // No warning or error was logged (importers treat an fmi2Warning from a step as a failure).
    let bad: Vec<_> = i.messages().into_iter().filter(|m| m.0 != 0).collect();
    assert!(bad.is_empty(), "{bad:?}");
}

#[test]
fn a_radius_of_0_is_still_refused_with_the_field_value_and_bounds() {
    let i = guidance("radius0", false);
    assert_eq!(i.init(), [0, 0, 0]);
    assert_eq!(i.set_real(Key::EstX(0), 0.0), 0);
    assert_eq!(i.step(0.0, 1.0), 3);
    let radius = guided_scenario()
        .unwrap()
        .guidance_model()
        .unwrap()
        .planet
        .radius;
    let want = format!(
        "the navigation estimate at nav_time = 0 s is not a state guidance can fly: radius 0 m is not between half and twice the planet radius ({radius} m)"
    );
    assert!(i.last().contains(&want), "{}", i.last());
    // Refused with the instance unchanged: the start values fly again.
    assert_eq!(i.int(Key::GuidanceCycles), 0);
    assert_eq!(i.set_real(Key::EstX(0), entry_estimate()[0]), 0);
    assert_eq!(i.step(0.0, 1.0), 0, "{}", i.last());
    assert_eq!(i.int(Key::GuidanceCycles), 1);
}
