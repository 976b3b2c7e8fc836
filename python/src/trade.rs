//! Trades from Python: the study layer's trade (`run_trade_study`), its shards, the native result
//! that keeps the report (per-epoch series as numpy views, the JSON summary and the HTML report
//! written through the study layer's outputs).

use crate::errors::{json_err, study_err};
use crate::options::options;
use crate::scenario::input;
use crate::watch::run_watched;
use entrynav::sim::{NoCheckpoint, Shard};
use entrynav_render::chart::labels::WeightNames;
use entrynav_studies::output::{check_output_file, write};
use entrynav_studies::provenance::Provenance;
use entrynav_studies::trade::{
    TradeOptions, TradeOutcome, TradeScenario, TradeSetup, run_trade_shard, run_trade_study,
};
use entrynav_studies::{StudyError, StudyResult};
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;

/// A finished trade kept on the Rust side.
#[pyclass(frozen, module = "entrynav._entrynav")]
pub struct NativeTrade {
    pub(crate) outcome: TradeOutcome,
    pub(crate) setup: TradeSetup,
    pub(crate) options: TradeOptions,
}

impl NativeTrade {
    /// The provenance of a trade run from Python: what reproduces it.
    fn provenance(&self) -> Provenance {
        let o = &self.options;
        let call = format!(
            "entrynav.trade({:?}, filters={:?}, runs={}, seed={}, pcrlb={})",
            self.setup.scenario.config.name,
            o.filters,
            self.setup.runs,
            o.seed,
            if o.pcrlb { "True" } else { "False" }
        );
        self.setup
            .provenance(vec!["entrynav (Python package)".into(), call])
    }
}

/// The setup of a trade of `options` on the scenario `toml`.
fn setup(toml: &str, dir: &str, options: &TradeOptions) -> PyResult<TradeSetup> {
    let built = TradeScenario::build(&input(toml, dir)?).map_err(study_err)?;
    TradeSetup::new(built, options).map_err(study_err)
}

/// The summary (the CLI's `--json` without `provenance` and `timing`) and each filter's series
/// and final errors.
fn documents(native: &NativeTrade) -> PyResult<(String, String)> {
    let text = native
        .outcome
        .to_json(&native.provenance())
        .map_err(study_err)?;
    let mut summary: serde_json::Value = serde_json::from_str(&text).map_err(json_err)?;
    if let Some(map) = summary.as_object_mut() {
        map.remove("provenance");
        map.remove("timing");
    }
    let filters: serde_json::Map<String, serde_json::Value> = native
        .outcome
        .report
        .filters
        .iter()
        .map(|f| {
            let v = serde_json::json!({ "series": f.series, "final_errors": f.final_errors });
            (f.name.clone(), v)
        })
        .collect();
    let details = serde_json::json!({ "filters": filters });
    Ok((summary.to_string(), details.to_string()))
}

/// What a trade hands back: the summary JSON, the series JSON, whether Ctrl-C stopped it, and
/// the native result.
type TradeOut = (String, String, bool, NativeTrade);

/// Run a Monte Carlo trade of the scenario `toml` (relative file names against `dir`) with the
/// trade's options as keyword arguments (`filters`, `runs`, `seed`, `threads`, `pcrlb`, `method`);
/// `progress(done, total)` is called about every 50 ms while runs finish.
#[pyfunction]
#[pyo3(signature = (toml, dir, kwargs=None, progress=None))]
pub fn trade(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    kwargs: Option<Bound<'_, PyDict>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<TradeOut> {
    let options: TradeOptions = options("trade", kwargs.as_ref(), TradeOptions::validate)?;
    let setup = setup(toml, dir, &options)?;
    let total = setup.runs as u64;
    let (outcome, stopped) = run_watched(py, progress.as_ref(), total, |watch| {
        run_trade_study(
            &setup,
            &options,
            None,
            &mut NoCheckpoint,
            Some(watch.cancel),
            &|step| watch.record(step),
        )
        .map_err(study_err)
    })?;
    let native = NativeTrade {
        outcome: outcome?,
        setup,
        options,
    };
    let (summary, details) = documents(&native)?;
    match stopped {
        // Ctrl-C: the finished runs go back with the flag; the Python side raises
        // KeyboardInterrupt carrying them. Another error from the callback propagates as is.
        Some(e) if e.is_instance_of::<PyKeyboardInterrupt>(py) => {
            Ok((summary, details, true, native))
        }
        Some(e) => Err(e),
        None => Ok((summary, details, false, native)),
    }
}

/// Shard `index` of `count` of the study (the CLI's `trade --shard I/N`): the shard file's JSON,
/// as `entrynav trade --shard I/N --json FILE` writes it (so `entrynav trade merge` combines
/// shards from either). `overrides` are the `--set` strings already applied to `toml`, recorded
/// in the shard's provenance. The GIL is released while it runs.
#[pyfunction]
#[pyo3(signature = (toml, dir, index, count, overrides, kwargs=None))]
pub fn trade_shard(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    index: usize,
    count: usize,
    overrides: Vec<String>,
    kwargs: Option<Bound<'_, PyDict>>,
) -> PyResult<String> {
    let options: TradeOptions = options("trade_shard", kwargs.as_ref(), TradeOptions::validate)?;
    let mut input = input(toml, dir)?;
    // The overrides are already applied to `toml`: they are recorded, not applied again.
    input.overrides = overrides;
    let built = TradeScenario::build(&input).map_err(study_err)?;
    let setup = TradeSetup::new(built, &options).map_err(study_err)?;
    let shard = Shard::parse(&format!("{index}/{count}")).map_err(|e| study_err(e.into()))?;
    let file = py.detach(|| run_trade_shard(&setup, &options, shard, None).map_err(study_err))?;
    // A delivery that cannot be flown is an error here (the CLI warns and writes the sums).
    if let Some(w) = file.warnings.first() {
        return Err(PyRuntimeError::new_err(w.clone()));
    }
    file.to_json().map_err(study_err)
}

/// Refuse a path a file cannot be written to (`-` included: Python has no standard output file).
fn check_path(path: &Path, what: &str) -> StudyResult<()> {
    if path.as_os_str() == "-" {
        return Err(StudyError::Refused(format!("{what} -: give a file path")));
    }
    check_output_file(path, what)
}

#[pymethods]
impl NativeTrade {
    /// One time series of `filter` as little-endian f64 bytes with its shape `(rows, columns)`
    /// (NaN where a value is undefined). `numpy.frombuffer` views the bytes without a copy.
    fn series<'py>(
        &self,
        py: Python<'py>,
        filter: &str,
        key: &str,
    ) -> PyResult<(Bound<'py, pyo3::types::PyBytes>, usize, usize)> {
        let f = self
            .outcome
            .report
            .filters
            .iter()
            .find(|f| f.name == filter)
            .ok_or_else(|| {
                PyValueError::new_err(format!("filter '{filter}' is not in this trade"))
            })?;
        let (values, rows, cols) = crate::series::series(&f.series, key)?;
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        Ok((pyo3::types::PyBytes::new(py, &bytes), rows, cols))
    }

    /// Write the summary as `entrynav trade --json PATH` writes it (with its `provenance` and
    /// `timing`), whole or not at all.
    fn write_json(&self, py: Python<'_>, path: &str) -> PyResult<()> {
        let path = Path::new(path);
        check_path(path, "path").map_err(study_err)?;
        let text = self
            .outcome
            .to_json(&self.provenance())
            .map_err(study_err)?;
        py.detach(|| write(path, text))
            .map_err(|e| study_err(e.into()))
    }

    /// Write the HTML report (as `entrynav trade --report PATH`): the seconds it took.
    fn write_report(&self, py: Python<'_>, path: &str) -> PyResult<f64> {
        let path = Path::new(path);
        check_path(path, "path").map_err(study_err)?;
        py.detach(|| {
            let clock = std::time::Instant::now();
            let o = &self.outcome;
            let names = WeightNames::of_scenario(&self.setup.scenario);
            let page = entrynav_render::report::trade_report(
                &o.report,
                &names,
                &self.provenance(),
                0.0,
                o.lincov.as_ref(),
                o.delivery.as_ref(),
            )
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            write(path, page).map_err(|e| study_err(e.into()))?;
            Ok(clock.elapsed().as_secs_f64())
        })
    }
}
