//! The design studies from Python — tune, observe, guided delivery, one truth run, and the three
//! optimizers — each the study layer's function with its options as keyword arguments, run with
//! the GIL released. Results come back as the JSON the command line writes (and a written
//! scenario's TOML), so the Python API equals the CLI's output.

use crate::errors::{json_err, study_err};
use crate::options::options;
use crate::scenario::input;
use entrynav_studies::design::{
    GroundOptions, OrbiterOptions, SelectOptions, run_ground_design, run_orbiter_design,
    run_site_selection,
};
use entrynav_studies::fmu_pack::{PackOptions, pack_fmus};
use entrynav_studies::guidance::{DeliverOptions, run_deliver};
use entrynav_studies::observe::{ObserveOptions, run_observe};
use entrynav_studies::progress::silent;
use entrynav_studies::simulate::{SimulateOptions, run_simulate};
use entrynav_studies::tune::{TuneStudyOptions, run_tune};
use entrynav_studies::{ScenarioInput, StudyResult};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;

/// `entrynav tune`: the tuned scenario's TOML text. A tuning worse than the input on the fresh
/// runs (and no `force`) is a `RuntimeError` naming the filter and the figure.
#[pyfunction]
#[pyo3(signature = (toml, dir, kwargs=None))]
pub fn tune(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<(String, Option<String>)> {
    let opts: TuneStudyOptions = options("tune", kwargs.as_ref(), TuneStudyOptions::validate)?;
    let input = input(toml, dir)?;
    let study = py.detach(|| run_tune(&input, &opts, &silent).map_err(study_err))?;
    let out = Path::new("the tuned scenario");
    if let Some(e) = study.refusal(out) {
        return Err(study_err(e));
    }
    // A tuning still inconsistent: the text and why, for a RuntimeError carrying the scenario.
    let inconsistent = study.inconsistency(out).map(|e| e.to_string());
    Ok((study.text.unwrap_or_default(), inconsistent))
}

/// `entrynav observe --json`: δ(t) along the trajectory (and with `fim` the beacons' Fisher
/// information, with `pcrlb` the bound), as JSON text.
#[pyfunction]
#[pyo3(signature = (toml, dir, kwargs=None))]
pub fn observe(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<String> {
    let opts: ObserveOptions = options("observe", kwargs.as_ref(), ObserveOptions::validate)?;
    let scenario = input(toml, dir)?.build().map_err(study_err)?;
    let study = py.detach(|| run_observe(&scenario, &opts).map_err(study_err))?;
    serde_json::to_string(&study.to_json(&scenario)).map_err(json_err)
}

/// `entrynav guidance deliver --json`: delivery at deployment with each filter in the guidance
/// loop, perfect navigation and the unguided bank, as JSON text.
#[pyfunction]
#[pyo3(signature = (toml, dir, kwargs=None))]
pub fn deliver(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<String> {
    let opts: DeliverOptions = options("deliver", kwargs.as_ref(), DeliverOptions::validate)?;
    let scenario = input(toml, dir)?.build().map_err(study_err)?;
    let study = py.detach(|| run_deliver(&scenario, &opts, &silent).map_err(study_err))?;
    serde_json::to_string(&study.document()).map_err(json_err)
}

/// One truth run with its measurement record (`entrynav simulate --out FILE`): JSON
/// `{"columns", "rows", "stop", "peaks"}` (a missing measurement is null).
#[pyfunction]
#[pyo3(signature = (toml, dir, kwargs=None))]
pub fn simulate(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<String> {
    let opts: SimulateOptions = options("simulate", kwargs.as_ref(), SimulateOptions::validate)?;
    let scenario = input(toml, dir)?.build().map_err(study_err)?;
    let sim = py.detach(|| run_simulate(&scenario, &opts).map_err(study_err))?;
    let (columns, rows) = sim.truth_table(&scenario);
    let stop = match sim.run.stop {
        entrynav::sim::StopReason::Duration => "duration",
        entrynav::sim::StopReason::StopSpeed => "stop_speed",
        entrynav::sim::StopReason::Ground => "ground",
    };
    let peak = |p: &entrynav::sim::Peak| serde_json::json!({ "value": p.value, "t_s": p.t });
    let doc = serde_json::json!({
        "columns": columns,
        "rows": rows,
        "stop": stop,
        "peaks": {
            "aero_accel_mps2": peak(&sim.peaks.aero_accel),
            "dynamic_pressure_pa": peak(&sim.peaks.dynamic_pressure),
            "heating_wm2": peak(&sim.peaks.heating),
        },
    });
    Ok(doc.to_string())
}

/// What a design study gives back: its `--json` text, the written scenario's TOML, and the
/// check's refusal (a design worse than the input) as a message, if any.
type DesignOut = (String, String, Option<String>);

/// Run a design study and take its JSON, scenario and verdict.
fn design<R: Send>(
    py: Python<'_>,
    input: &ScenarioInput,
    run: impl FnOnce(&ScenarioInput) -> PyResult<R> + Send,
    parts: impl FnOnce(&R) -> (serde_json::Value, String, StudyResult<()>),
) -> PyResult<DesignOut> {
    let result = py.detach(|| run(input))?;
    let (json, toml, verdict) = parts(&result);
    let text = serde_json::to_string(&json).map_err(json_err)?;
    Ok((text, toml, verdict.err().map(|e| e.to_string())))
}

/// `entrynav optimize ground`.
#[pyfunction]
#[pyo3(signature = (toml, dir, kwargs=None))]
pub fn optimize_ground(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<DesignOut> {
    let opts: GroundOptions = options("optimize_ground", kwargs.as_ref(), GroundOptions::validate)?;
    design(
        py,
        &input(toml, dir)?,
        |i| run_ground_design(i, &opts, &silent).map_err(study_err),
        |d| (d.to_json(), d.design_toml.clone(), d.verdict()),
    )
}

/// `entrynav optimize select`.
#[pyfunction]
#[pyo3(signature = (toml, dir, kwargs=None))]
pub fn optimize_select(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<DesignOut> {
    let opts: SelectOptions = options("optimize_select", kwargs.as_ref(), SelectOptions::validate)?;
    design(
        py,
        &input(toml, dir)?,
        |i| run_site_selection(i, &opts, &silent).map_err(study_err),
        |d| (d.to_json(), d.design_toml.clone(), d.verdict()),
    )
}

/// `entrynav optimize orbiters`.
#[pyfunction]
#[pyo3(signature = (toml, dir, kwargs=None))]
pub fn optimize_orbiters(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<DesignOut> {
    let opts: OrbiterOptions = options(
        "optimize_orbiters",
        kwargs.as_ref(),
        OrbiterOptions::validate,
    )?;
    design(
        py,
        &input(toml, dir)?,
        |i| run_orbiter_design(i, &opts, &silent).map_err(study_err),
        |d| (d.to_json(), d.design_toml.clone(), d.verdict()),
    )
}

/// `entrynav fmu pack`: the FMUs into `out` with the library `library`; with a scenario (a
/// built-in's name, or TOML text and its folder) the combined model specific to it. The paths of
/// the `.fmu` (and `.ssp`) files written.
#[pyfunction]
#[pyo3(signature = (out, library, builtin=None, toml=None, dir=None, kwargs=None))]
pub fn fmu_pack(
    py: Python<'_>,
    out: &str,
    library: &str,
    builtin: Option<&str>,
    toml: Option<&str>,
    dir: Option<&str>,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<Vec<String>> {
    let opts: PackOptions = options("fmu_pack", kwargs.as_ref(), PackOptions::validate)?;
    let scenario = match (builtin, toml) {
        (Some(name), _) => Some(ScenarioInput::resolve(name, &[]).map_err(study_err)?),
        (None, Some(text)) => Some(input(text, dir.unwrap_or("."))?),
        (None, None) => None,
    };
    let packed = py.detach(|| {
        pack_fmus(Path::new(library), Path::new(out), scenario.as_ref(), &opts).map_err(study_err)
    })?;
    let fmus = packed.fmus.iter().map(|f| f.path.display().to_string());
    Ok(fmus
        .chain(packed.ssps.iter().map(|p| p.display().to_string()))
        .collect())
}
