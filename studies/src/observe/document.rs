//! The JSON document of an observability study (`entrynav observe --json`): the δ series of the
//! centralised system and its subsystems, the scaling, the Fisher information per epoch (the
//! PCRLB is added by [`Observation::to_json`](crate::observe::study::Observation::to_json)), and
//! the two notes that say what raw and scaled δ are.

use entrynav::observability::{DegreeSeries, FimEpoch, Scaling};
use entrynav::scenario::Scenario;
use serde_json::{Value, json};

/// What the raw δ is.
pub const RAW_NOTE: &str = "raw SI: delta = sigma_min/sigma_max of O with states in m, rad, m/s, kg/m^3 and outputs in their SI units (the papers' convention)";

/// What the scaled δ is: the characteristic sizes of `scaling`.
pub fn scaling_note(scaling: &Scaling) -> String {
    let sizes: Vec<String> = scaling
        .state_names
        .iter()
        .zip(&scaling.state)
        .map(|(n, s)| format!("{n} {s:e}"))
        .collect();
    format!(
        "delta of W*O*D: states divided by characteristic sizes [{}], each row divided by its \
         channel's noise 1-sigma, Lie order k rows times ({} s)^k (dimensionless)",
        sizes.join(", "),
        scaling.time_s
    )
}

fn series_json(s: &DegreeSeries, elapsed_s: f64) -> Value {
    let stat = |scaled: bool| s.summary(scaled);
    let (raw, sc) = (stat(false), stat(true));
    json!({
        "name": s.name,
        "method": s.method.name(),
        "times_s": s.times(),
        "delta": s.deltas(false),
        "delta_min": raw.map(|m| m.min),
        "delta_max": raw.map(|m| m.max),
        "t_delta_min_s": raw.map(|m| m.t_min_s),
        "t_delta_max_s": raw.map(|m| m.t_max_s),
        "rank": s.samples.iter().map(|x| x.raw.rank).collect::<Vec<_>>(),
        "delta_scaled": s.deltas(true),
        "delta_scaled_min": sc.map(|m| m.min),
        "delta_scaled_max": sc.map(|m| m.max),
        "t_delta_scaled_min_s": sc.map(|m| m.t_min_s),
        "t_delta_scaled_max_s": sc.map(|m| m.t_max_s),
        "rank_scaled": s.samples.iter().map(|x| x.scaled.rank).collect::<Vec<_>>(),
        "outputs": s.samples.iter().map(|x| x.outputs).collect::<Vec<_>>(),
        "elapsed_s": elapsed_s,
    })
}

/// The document without the PCRLB: the centralised series at the top level, `elapsed_s` its
/// seconds; each subsystem with its own.
pub fn to_json(
    scenario: &Scenario,
    scaling: &Scaling,
    central: &DegreeSeries,
    elapsed_s: f64,
    subsystems: &[(DegreeSeries, f64)],
    fim: Option<&[FimEpoch]>,
) -> Value {
    let mut v = series_json(central, elapsed_s);
    let o = v.as_object_mut().expect("series_json builds an object");
    o.insert("scenario".into(), json!(scenario.config.name));
    o.insert("delta_units".into(), json!(RAW_NOTE));
    o.insert(
        "scaling".into(),
        json!({
            "description": scaling_note(scaling),
            "state_names": scaling.state_names,
            "state_scale": scaling.state,
            "time_s": scaling.time_s,
            "rows": "divided by the channel's noise 1-sigma (relative noise: at the analysis point)",
        }),
    );
    o.insert(
        "subsystems".into(),
        Value::Array(subsystems.iter().map(|(s, e)| series_json(s, *e)).collect()),
    );
    if let Some(f) = fim {
        let col = |g: &dyn Fn(&FimEpoch) -> Value| Value::Array(f.iter().map(g).collect());
        o.insert("fim_times_s".into(), col(&|e| json!(e.t)));
        o.insert(
            "fim_beacons".into(),
            col(&|e| {
                json!(
                    e.beacons
                        .iter()
                        .map(|&b| scenario.beacon_names[b].clone())
                        .collect::<Vec<_>>()
                )
            }),
        );
        o.insert("fim_det".into(), col(&|e| json!(e.summary.det)));
        o.insert("fim_trace".into(), col(&|e| json!(e.summary.trace)));
        o.insert(
            "fim_eigenvalues".into(),
            col(&|e| json!(e.summary.eigenvalues)),
        );
        o.insert(
            "fim_trace_inverse".into(),
            col(&|e| json!(e.summary.trace_inverse)),
        );
        o.insert(
            "fim_trace_lower_bound".into(),
            col(&|e| {
                json!(
                    e.summary
                        .trace_lower_bound
                        .is_finite()
                        .then_some(e.summary.trace_lower_bound)
                )
            }),
        );
        o.insert(
            "fim_det_upper_bound".into(),
            col(&|e| json!(e.summary.det_upper_bound)),
        );
        o.insert("fim_det_max".into(), col(&|e| json!(e.summary.det_max)));
        o.insert("geometry_index".into(), col(&|e| json!(e.geometry_index)));
    }
    v
}
