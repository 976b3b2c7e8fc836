//! `entrynav._entrynav`: the native half of the Python package (the typed API is the pure
//! Python `entrynav/__init__.py` over it).
//!
//! Scenarios cross the boundary as their TOML text and the folder their relative file names
//! resolve against, so a Python `Scenario` is a value that `to_toml()` prints exactly; every
//! change goes through the loader's `--set` path and validation. A trade runs on a Rust thread
//! with the GIL released; the calling thread waits in slices of 50 ms, runs Python's signal
//! handlers between them (Ctrl-C raises `KeyboardInterrupt` there: the trade is cancelled like
//! the CLI's SIGINT, the runs finished so far are folded and handed back) and calls the progress
//! callback. Errors become Python exceptions: `FileNotFoundError` for a scenario file that does
//! not exist, `ValueError` for a bad field (the loader's message names field, value and range),
//! `RuntimeError` for a numerical failure; a panic is caught and becomes `RuntimeError`.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use entrynav::sim::guided::delivery_shard::deliver_runs;
use entrynav::sim::monte_carlo::shard::ACCUMULATION_BLOCK;
use entrynav::sim::{
    McOptions, Shard, TradeError, TradeReport, run_shard, run_trade, simulate_truth_with_peaks,
};
use entrynav_loader as load;
use pyo3::exceptions::{PyFileNotFoundError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

fn load_err(e: load::LoadError) -> PyErr {
    match e {
        load::LoadError::NotFound { .. } => PyFileNotFoundError::new_err(e.to_string()),
        e => PyValueError::new_err(e.to_string()),
    }
}

fn config_of(toml: &str, origin: &str) -> PyResult<ScenarioConfig> {
    ScenarioConfig::from_toml_str(toml, origin).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// `[(name, one-line summary)]` of every built-in scenario.
#[pyfunction]
fn builtin_scenarios() -> PyResult<Vec<(String, String)>> {
    BUILTIN_NAMES
        .iter()
        .map(|name| {
            let cfg =
                ScenarioConfig::builtin(name).map_err(|e| PyValueError::new_err(e.to_string()))?;
            let sc = Scenario::build(cfg, &entrynav::files::no_files)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            Ok((name.to_string(), load::summary::summary(&sc)))
        })
        .collect()
}

/// A built-in name or a TOML file (relative to the working directory): `(toml, folder)`.
#[pyfunction]
fn resolve_scenario(name_or_file: &str) -> PyResult<(String, String)> {
    let (cfg, dir) = load::resolve(name_or_file, load::Base::CurrentDir)
        .map_err(load_err)?
        .into_parts();
    Ok((cfg.to_toml_string(), dir.display().to_string()))
}

/// The scenario `toml` with `PATH=VALUE` overrides applied and validated: its new TOML text.
#[pyfunction]
fn apply_sets(toml: &str, sets: Vec<String>) -> PyResult<String> {
    let cfg = config_of(toml, "scenario")?;
    let cfg = load::apply_overrides(cfg, &sets).map_err(load_err)?;
    Ok(cfg.to_toml_string())
}

/// The scenario as JSON (every field, defaults filled in).
#[pyfunction]
fn scenario_json(toml: &str) -> PyResult<String> {
    let cfg = config_of(toml, "scenario")?;
    serde_json::to_string(&cfg).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// Build the scenario as the CLI's `trade` does, and its filters.
fn setup(toml: &str, dir: &str, filters: &str) -> PyResult<(Scenario, Vec<FilterKind>)> {
    let cfg = config_of(toml, "scenario")?;
    let scenario = load::build(cfg, Path::new(dir)).map_err(load_err)?;
    let kinds = FilterKind::parse_list(filters, &scenario.onboard)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((scenario, kinds))
}

fn trade_err(e: TradeError) -> PyErr {
    match e {
        TradeError::Options(m) => PyValueError::new_err(m),
        e => PyRuntimeError::new_err(e.to_string()),
    }
}

/// A finished trade kept on the Rust side, for what needs more than its JSON (the HTML report).
#[pyclass(frozen, module = "entrynav._entrynav")]
struct NativeTrade {
    report: TradeReport,
    scenario: Scenario,
}

/// The names [`NativeTrade::series`] knows: one value per epoch, or a row per epoch.
const SERIES_KEYS: &str = "times_s, rmse, sigma_mean, bias, pos_rmse_m, local_rmse_m, vel_rmse_mps, \
     nees_mean, nees_kinematic_mean, nis_mean, density_rms_pct, density_mean_pct, \
     density_at_estimate_rms_pct";

/// Rows of possibly missing values as one row-major block, NaN for a missing value or a short
/// row: `(values, rows, columns)`.
fn block(rows: &[Vec<Option<f64>>]) -> (Vec<f64>, usize, usize) {
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0);
    let values = rows
        .iter()
        .flat_map(|r| (0..cols).map(|j| r.get(j).copied().flatten().unwrap_or(f64::NAN)))
        .collect();
    (values, rows.len(), cols)
}

fn column(v: &[Option<f64>]) -> (Vec<f64>, usize, usize) {
    (
        v.iter().map(|x| x.unwrap_or(f64::NAN)).collect(),
        v.len(),
        1,
    )
}

#[pymethods]
impl NativeTrade {
    /// One time series of `filter` as little-endian f64 bytes with its shape `(rows, columns)`
    /// (NaN where a value is undefined). `numpy.frombuffer` views the bytes without a copy; this
    /// replaces a JSON text, its parse into Python lists and their conversion.
    fn series<'py>(
        &self,
        py: Python<'py>,
        filter: &str,
        key: &str,
    ) -> PyResult<(Bound<'py, pyo3::types::PyBytes>, usize, usize)> {
        let f = self
            .report
            .filters
            .iter()
            .find(|f| f.name == filter)
            .ok_or_else(|| {
                PyValueError::new_err(format!("filter '{filter}' is not in this trade"))
            })?;
        let s = &f.series;
        let (values, rows, cols) = match key {
            "times_s" => (s.times_s.clone(), s.times_s.len(), 1),
            "rmse" => block(&s.rmse),
            "sigma_mean" => block(&s.sigma_mean),
            "bias" => block(&s.bias),
            "local_rmse_m" => block(&s.local_rmse_m),
            "pos_rmse_m" => column(&s.pos_rmse_m),
            "vel_rmse_mps" => column(&s.vel_rmse_mps),
            "nees_mean" => column(&s.nees_mean),
            "nees_kinematic_mean" => column(&s.nees_kinematic_mean),
            "nis_mean" => column(&s.nis_mean),
            "density_rms_pct" => column(&s.density_rms_pct),
            "density_mean_pct" => column(&s.density_mean_pct),
            "density_at_estimate_rms_pct" => column(&s.density_at_estimate_rms_pct),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "series '{key}' does not exist: one of {SERIES_KEYS}"
                )));
            }
        };
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        Ok((pyo3::types::PyBytes::new(py, &bytes), rows, cols))
    }
}

/// Write the HTML report of `trade` to `path` (as `entrynav trade --report PATH`): seconds taken.
#[pyfunction]
fn write_report(py: Python<'_>, trade: &NativeTrade, path: &str) -> PyResult<f64> {
    py.detach(|| {
        entrynav_cli::write_trade_report(Path::new(path), &trade.report, &trade.scenario, &[])
    })
    .map_err(|e| PyValueError::new_err(format!("{e:#}")))
}

/// What a trade hands back to Python: the summary JSON (the CLI's `--json` without `provenance`
/// and `timing`), the per-filter series and final errors as JSON, whether it completed, and
/// whether Ctrl-C (or the progress callback) stopped it.
type TradeOut = (String, String, bool, bool, NativeTrade);

fn details(report: &TradeReport) -> serde_json::Value {
    let filters: serde_json::Map<String, serde_json::Value> = report
        .filters
        .iter()
        .map(|f| {
            (
                f.name.clone(),
                serde_json::json!({ "series": f.series, "final_errors": f.final_errors }),
            )
        })
        .collect();
    serde_json::json!({ "filters": filters })
}

/// Run a Monte Carlo trade of `filters` (comma-separated names, as `--filters`) on the scenario
/// `toml` (relative file names against `dir`): `runs` (default the scenario's), `seed`, on
/// `threads` workers (default all cores), with the PCRLB unless `pcrlb` is false.
/// `progress(done, total)` is called from the calling thread about every 50 ms while runs finish.
#[pyfunction]
#[pyo3(signature = (toml, dir, filters, runs=None, seed=1, threads=None, pcrlb=true, progress=None))]
#[allow(clippy::too_many_arguments)]
fn trade(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    filters: &str,
    runs: Option<usize>,
    seed: u64,
    threads: Option<usize>,
    pcrlb: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<TradeOut> {
    let (scenario, kinds) = setup(toml, dir, filters)?;
    let runs = runs.unwrap_or(scenario.config.monte_carlo.runs);
    if !(1..=10_000_000).contains(&runs) {
        return Err(PyValueError::new_err(format!(
            "runs = {runs} is out of range: must be >= 1 and <= 10000000"
        )));
    }
    if threads == Some(0) {
        return Err(PyValueError::new_err(
            "threads = 0: must be at least 1 (or None for all cores)",
        ));
    }
    // The core reads the cancellation flag through a 'static reference: one byte per trade is
    // leaked so that a trade never shares its flag with another.
    let cancel: &'static AtomicBool = Box::leak(Box::new(AtomicBool::new(false)));
    let opts = McOptions {
        pcrlb,
        cancel: Some(cancel),
        ..McOptions::new(runs, seed)
    };
    let done = AtomicUsize::new(0);
    let mut stopped: Option<PyErr> = None;
    let result = std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let job = || {
                run_trade(&scenario, &kinds, &opts, &|d| {
                    done.store(d, Ordering::Relaxed)
                })
            };
            match threads {
                Some(n) => rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| TradeError::Options(format!("threads = {n}: {e}")))
                    .and_then(|pool| pool.install(job)),
                None => job(),
            }
        });
        let mut shown = usize::MAX;
        while !worker.is_finished() {
            py.detach(|| {
                let until = std::time::Instant::now() + Duration::from_millis(50);
                while !worker.is_finished() && std::time::Instant::now() < until {
                    std::thread::sleep(Duration::from_millis(2));
                }
            });
            if stopped.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    stopped = Some(e);
                    continue;
                }
                let d = done.load(Ordering::Relaxed);
                if let Some(cb) = &progress
                    && d != shown
                {
                    shown = d;
                    if let Err(e) = cb.call1(py, (d, runs)) {
                        cancel.store(true, Ordering::Relaxed);
                        stopped = Some(e);
                    }
                }
            }
        }
        worker.join()
    });
    let report = match result {
        Ok(r) => r.map_err(trade_err)?,
        Err(_) => {
            return Err(PyRuntimeError::new_err(
                "the trade panicked (internal error)",
            ));
        }
    };
    if let (Some(cb), None) = (&progress, &stopped) {
        cb.call1(py, (report.runs_completed, runs))?;
    }
    let summary =
        serde_json::to_string(&report).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let details = details(&report).to_string();
    let complete = report.complete;
    let native = NativeTrade { report, scenario };
    match stopped {
        // Ctrl-C: the finished runs go back with the flag; the Python side raises
        // KeyboardInterrupt carrying them. Another error from the callback propagates as is.
        Some(e) if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) => {
            Ok((summary, details, complete, true, native))
        }
        Some(e) => Err(e),
        None => Ok((summary, details, complete, false, native)),
    }
}

/// Run shard `index` of `count` of the study (the CLI's `trade --shard I/N`) and return the
/// shard file's JSON, as `entrynav trade --shard I/N --json FILE` writes it (so `entrynav trade
/// merge` combines shards from either): the block sums, the study's `provenance` (`overrides`
/// as given, the truth atmosphere source) and `wall_s`. The GIL is released while it runs.
#[pyfunction]
#[pyo3(signature = (toml, dir, filters, runs, seed, index, count, overrides, threads=None))]
#[allow(clippy::too_many_arguments)]
fn trade_shard(
    py: Python<'_>,
    toml: &str,
    dir: &str,
    filters: &str,
    runs: usize,
    seed: u64,
    index: usize,
    count: usize,
    overrides: Vec<String>,
    threads: Option<usize>,
) -> PyResult<String> {
    let (scenario, kinds) = setup(toml, dir, filters)?;
    if !(1..=10_000_000).contains(&runs) {
        return Err(PyValueError::new_err(format!(
            "runs = {runs} is out of range: must be >= 1 and <= 10000000"
        )));
    }
    let shard = Shard::parse(&format!("{index}/{count}")).map_err(trade_err)?;
    let opts = McOptions {
        pcrlb: true,
        ..McOptions::new(runs, seed)
    };
    let clock = std::time::Instant::now();
    let result = py.detach(|| {
        // A scenario with `[guidance]`: the delivery runs of this shard's blocks, as the CLI's
        // shard file carries them (merged by run index in `trade merge`).
        let job = || {
            let sums = run_shard(&scenario, &kinds, &opts, shard, &|_| {})?;
            let delivery = match scenario.config.guidance {
                Some(_) => {
                    let (blocks, block) = (shard.blocks(runs), ACCUMULATION_BLOCK);
                    let span = (blocks.start * block).min(runs)..(blocks.end * block).min(runs);
                    Some(deliver_runs(&scenario, &kinds, runs, seed, span))
                }
                None => None,
            };
            Ok::<_, TradeError>((sums, delivery))
        };
        match threads {
            Some(n) => rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| TradeError::Options(format!("threads = {n}: {e}")))
                .and_then(|pool| pool.install(job)),
            None => job(),
        }
    });
    let (result, delivery) = result.map_err(trade_err)?;
    let delivery = delivery
        .transpose()
        .map_err(|e| PyRuntimeError::new_err(format!("delivery at deployment: {e}")))?;
    let truth = &scenario.config.truth;
    let mut doc =
        serde_json::to_value(&result).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    if let Some(map) = doc.as_object_mut() {
        map.insert(
            "provenance".into(),
            serde_json::json!({
                "overrides": overrides,
                "atmosphere": {
                    "file": null,
                    "truth": serde_json::to_value(&truth.atmosphere).unwrap_or(serde_json::Value::Null),
                    "perturbation": truth.perturbation.is_some(),
                },
            }),
        );
        map.insert("wall_s".into(), clock.elapsed().as_secs_f64().into());
        if let Some(d) = &delivery {
            map.insert(
                "delivery".into(),
                serde_json::to_value(d).map_err(|e| PyRuntimeError::new_err(e.to_string()))?,
            );
        }
    }
    Ok(doc.to_string())
}

/// One truth run with its measurement record, as `entrynav simulate --out FILE` writes it: JSON
/// `{"columns": [...], "rows": [[...]], "stop": "...", "peaks": {...}}` (a missing measurement
/// is null). `dispersed` draws the truth from the scenario's dispersions.
#[pyfunction]
#[pyo3(signature = (toml, dir, seed=1, dispersed=false))]
fn simulate(py: Python<'_>, toml: &str, dir: &str, seed: u64, dispersed: bool) -> PyResult<String> {
    let cfg = config_of(toml, "scenario")?;
    let scenario = load::build(cfg, Path::new(dir)).map_err(load_err)?;
    let (run, peaks) = py
        .detach(|| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let draw = if dispersed {
                scenario.draw_truth(&mut rng)
            } else {
                entrynav::scenario::TruthDraw {
                    initial: scenario.truth_initial,
                    model: scenario.truth_model.clone(),
                }
            };
            simulate_truth_with_peaks(&scenario, &draw, &mut rng)
        })
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let (columns, rows) = entrynav_cli::simulate::truth_table(&scenario, &run);
    let stop = match run.stop {
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
            "aero_accel_mps2": peak(&peaks.aero_accel),
            "dynamic_pressure_pa": peak(&peaks.dynamic_pressure),
            "heating_wm2": peak(&peaks.heating),
        },
    });
    Ok(doc.to_string())
}

/// Run one `entrynav` command line in this process (the design commands: `tune`, `observe`,
/// `optimize …`, `fmu pack`), with the GIL released: `(exit code, error message)`. Their tables
/// print on the process's standard output, as the CLI's do; their files are what the Python API
/// reads back.
#[pyfunction]
fn run_cli(py: Python<'_>, args: Vec<String>) -> PyResult<(i32, String)> {
    let mut argv = vec!["entrynav".to_string()];
    argv.extend(args);
    let out = py.detach(|| std::panic::catch_unwind(|| entrynav_cli::run_args(argv)));
    out.map_err(|_| PyRuntimeError::new_err("the command panicked (internal error)"))
}

/// The version of the library.
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

/// The native module.
#[pymodule]
fn _entrynav(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(builtin_scenarios, m)?)?;
    m.add_function(wrap_pyfunction!(resolve_scenario, m)?)?;
    m.add_function(wrap_pyfunction!(apply_sets, m)?)?;
    m.add_function(wrap_pyfunction!(scenario_json, m)?)?;
    m.add_function(wrap_pyfunction!(trade, m)?)?;
    m.add_function(wrap_pyfunction!(trade_shard, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(run_cli, m)?)?;
    m.add_function(wrap_pyfunction!(write_report, m)?)?;
    m.add_class::<NativeTrade>()?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    Ok(())
}
