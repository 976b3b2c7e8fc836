//! The guidance and simulate studies as Python will call them: options built from keyword
//! arguments, refused out of range with the option's name before any work, and results that hold
//! what the command line prints and writes.

use entrynav_studies::ScenarioInput;
use entrynav_studies::guidance::{DeliverOptions, run_deliver, run_reference};
use entrynav_studies::progress::silent;
use entrynav_studies::simulate::{SimulateOptions, run_simulate};

#[test]
fn deliver_options_are_bounded_and_named_before_any_run() {
    let scenario = ScenarioInput::resolve("msl-guided", &[])
        .unwrap()
        .build()
        .unwrap();
    for (options, message) in [
        (
            DeliverOptions {
                runs: Some(0),
                ..DeliverOptions::default()
            },
            "runs = 0 is out of range: must be from 1 to 10000000",
        ),
        (
            DeliverOptions {
                threads: Some(2000),
                ..DeliverOptions::default()
            },
            "threads = 2000 is out of range: must be from 1 to 1024",
        ),
    ] {
        let e = run_deliver(&scenario, &options, &silent).unwrap_err();
        assert_eq!(e.to_string(), message);
        assert_eq!(e.kind(), entrynav_studies::ErrorKind::Refused);
    }
    let o: DeliverOptions =
        serde_json::from_str(r#"{"filters": "ekf,ukf", "runs": 4, "seed": 7}"#).unwrap();
    assert_eq!(
        (o.filters.as_str(), o.runs, o.seed),
        ("ekf,ukf", Some(4), 7)
    );
    assert!(serde_json::from_str::<DeliverOptions>(r#"{"filter": "ekf"}"#).is_err());
}

#[test]
fn a_reference_needs_guidance_and_tabulates_its_gains() {
    let plain = ScenarioInput::resolve("orbiters-3", &[])
        .unwrap()
        .build()
        .unwrap();
    let e = run_reference(&plain).unwrap_err();
    assert!(e.to_string().contains("has no [guidance] section"), "{e}");
    let guided = ScenarioInput::resolve("msl-guided", &[])
        .unwrap()
        .build()
        .unwrap();
    let r = run_reference(&guided).unwrap();
    let (first, last) = r.ends().unwrap();
    assert!(first[1] > last[1], "speed decreases along the reference");
    let v = r.to_json();
    assert_eq!(v["points"].as_array().unwrap().len(), r.rows.len());
    let mut w = csv::Writer::from_writer(Vec::new());
    r.write_csv(&mut w).unwrap();
    let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
    assert_eq!(text.lines().count(), r.rows.len() + 1);
}

#[test]
fn a_simulation_is_a_table_of_the_documented_columns() {
    let scenario = ScenarioInput::resolve("four-beacon-fusion", &[])
        .unwrap()
        .build()
        .unwrap();
    let o: SimulateOptions = serde_json::from_str(r#"{"seed": 5}"#).unwrap();
    assert!(!o.dispersed);
    let sim = run_simulate(&scenario, &o).unwrap();
    let (columns, rows) = sim.truth_table(&scenario);
    assert_eq!(columns[0], "t_s");
    assert_eq!(rows.len(), sim.run.samples.len());
    assert!(rows.iter().all(|r| r.len() == columns.len()));
    assert!(sim.peaks.aero_accel.value > 0.0);
    // The same seed flies the same run.
    let again = run_simulate(&scenario, &o).unwrap();
    assert_eq!(again.truth_table(&scenario), (columns, rows));
}
