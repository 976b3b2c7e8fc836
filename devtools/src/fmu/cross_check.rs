//! `entrynav-dev fmu cross-check`: the FMI Cross-Check files of packed FMUs, as the cross-check rules
//! (version 4.1) lay them out: `fmus/2.0/cs/linux64/entrynav/<version>/<Model>/` (FMI 3.0 FMUs:
//! `fmus/3.0/cs/x86_64-linux/…`) with
//! `<Model>.fmu`, `<Model>_ref.csv` (at most 10 important outputs, from StartTime to StopTime),
//! `<Model>_ref.opt`, `<Model>_in.csv` (every input) and `README.md`. CSV files have a quoted
//! header, a `time` first column, numbers only (Booleans as 0/1) and stay under 1 MB.
//!
//! The reference is the model run in process with the FMU's own table and resources, its default
//! parameters and the input table; `tests/python` simulates each FMU with fmpy on the same files
//! and compares (and runs fmpy's own cross-check validator on the folder).

use super::check::inputs::{check_available, check_bank, check_inputs, load_scenario};
use super::guided::guided_rows;
use super::run::run_in_process;
use super::table::{Table, csv, fmt_value};
use anyhow::{Context, Result, ensure};
use clap::Args;
use entrynav::sim::engine::TruthSensors;
use entrynav_fmi_host::unpack;
use entrynav_fmu::ModelSpec;
use entrynav_fmu::vars::{
    Causality, DEFAULT_SCENARIO, DEFAULT_SEED, GUIDED_SCENARIO_FILE, Model, Value, Var,
};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Arguments of `entrynav-dev fmu cross-check`.
#[derive(Args)]
pub(super) struct CrossCheckArgs {
    /// Packed .fmu files.
    #[arg(required = true)]
    fmus: Vec<PathBuf>,
    /// The vendor folder to write (`fmus/...` below it).
    #[arg(long, default_value = "target/cross-check")]
    out: PathBuf,
}

/// The cross-check rules' size limit of a CSV file.
const MAX_CSV_BYTES: usize = 1_000_000;

/// The (at most 10) outputs of a model's reference result.
fn reference_outputs(spec: &ModelSpec) -> Vec<String> {
    let names: Vec<String> = match (spec.model(), spec.specific()) {
        (_, Some(s)) => {
            let st = |k: usize| s.states[k].name;
            vec![
                "truth_altitude".into(),
                "truth_v".into(),
                format!("est.{}", st(0)),
                format!("est.{}", st(1)),
                format!("est.{}", st(3)),
                format!("est_sigma.{}", st(0)),
                format!("err.{}", st(0)),
                format!("err.{}", st(3)),
                "nav_time".into(),
                "nav_status".into(),
            ]
        }
        (Model::Combined, None) => [
            "truth_altitude",
            "truth_v",
            "truth_fpa",
            "est_r",
            "est_v",
            "est_fpa",
            "nav_time",
            "n_meas",
            "nav_status",
            "weight_1",
        ]
        .map(String::from)
        .to_vec(),
        (Model::Filter, None) => [
            "est_r",
            "est_lon",
            "est_lat",
            "est_v",
            "est_fpa",
            "est_heading",
            "est_sigma_1",
            "nav_time",
            "n_meas",
            "nav_status",
        ]
        .map(String::from)
        .to_vec(),
        (Model::Guidance, None) => [
            "bank_command",
            "bank_rate",
            "guidance_command",
            "guidance_time",
            "guidance_cycles",
            "sensed_drag",
            "range_to_go",
            "crossrange",
            "deploy_trigger",
            "deployed",
            "guidance_status",
            "guidance_status_code",
        ]
        .map(String::from)
        .to_vec(),
        (Model::Guided, None) => [
            "truth_altitude",
            "truth_v",
            "truth_bank_angle",
            "est_r",
            "est_v",
            "guidance_command",
            "guided_status",
            "deployed",
            "miss_distance",
            "nav_status",
        ]
        .map(String::from)
        .to_vec(),
        (Model::Truth, None) => [
            "truth_r",
            "truth_lon",
            "truth_lat",
            "truth_v",
            "truth_fpa",
            "truth_heading",
            "truth_altitude",
            "truth_density",
            "meas_epoch",
            "truth_stop",
        ]
        .map(String::from)
        .to_vec(),
    };
    names
}

/// The input table of a cross-check run: the `fmu check` inputs at every communication point.
/// For the guidance FMU, row t holds what the in-process guided loop (EKF, run 0 of the default
/// seed) gave its guidance at t (`super::guided`). For the filter FMU, row t holds the measurements of a truth run with the FMU's default seed
/// that flew the combined FMU's inputs (bank, beacon availability) over the step ending at t, and
/// the bank of that step: the filter fed from it reproduces the combined FMU one step late.
fn input_table(spec: &ModelSpec, resources: &Path, stop: f64, step: f64) -> Result<Table> {
    let vars = spec.vars();
    let inputs: Vec<Var> = vars
        .iter()
        .filter(|v| v.causality == Causality::Input)
        .cloned()
        .collect();
    let mut feeder = match spec.model() {
        Model::Filter => Some(TruthSensors::new(
            load_scenario(DEFAULT_SCENARIO, resources)?,
            DEFAULT_SEED as u64,
            false,
        )),
        _ => None,
    };
    let n = (stop / step).round() as usize;
    let guided = match spec.model() {
        Model::Guidance => guided_rows(
            &load_scenario(GUIDED_SCENARIO_FILE, resources)?,
            DEFAULT_SEED as u64,
            step,
            n,
        )?,
        _ => Vec::new(),
    };
    let mut rows = Vec::with_capacity(n + 1);
    for k in 0..=n {
        let t = k as f64 * step;
        let vals = check_inputs(spec.model(), vars, t, step, feeder.as_ref(), guided.get(k));
        rows.push((t, vals.into_iter().map(|(_, v)| v).collect()));
        if let Some(ts) = feeder.as_mut() {
            // What the combined FMU's truth flies on this step (bank, beacon availability): the
            // filter gets these measurements and this bank in the next row, one step late.
            ts.do_step(t, step, check_bank(t), &check_available(t))?;
        }
    }
    Ok(Table {
        columns: inputs,
        rows,
    })
}

fn write_limited(path: &Path, text: &str) -> Result<()> {
    ensure!(
        text.len() < MAX_CSV_BYTES,
        "{} would be {} bytes; the cross-check rules allow 1 MB",
        path.display(),
        text.len()
    );
    Ok(entrynav_studies::output::atomic_file::write(path, text)?)
}

pub(super) fn cross_check(a: &CrossCheckArgs) -> Result<()> {
    for fmu in &a.fmus {
        super::bounds::input(fmu, "FMUS")?;
    }
    entrynav_studies::output::check_output_dir(&a.out, "--out")?;
    for fmu in &a.fmus {
        let u = unpack(fmu)?;
        let spec = Arc::clone(&u.spec);
        let id = spec.identifier();
        let (version, platform) = match u.fmi_version {
            3 => ("3.0", "x86_64-linux"),
            _ => ("2.0", "linux64"),
        };
        let dir = a
            .out
            .join(format!("fmus/{version}/cs/{platform}/entrynav"))
            .join(env!("CARGO_PKG_VERSION"))
            .join(id);
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        let res = u.dir.join("resources");
        let (start, stop, step) = spec.default_experiment();
        let table = input_table(&spec, &res, stop, step)?;
        let names = reference_outputs(&spec);
        let record: Vec<Var> = names
            .iter()
            .map(|n| {
                spec.vars()
                    .iter()
                    .find(|v| &v.name == n)
                    .cloned()
                    .with_context(|| format!("{id} has no output {n}"))
            })
            .collect::<Result<_>>()?;
        let rows = run_in_process(&spec, Some(&res), &[], &table, stop, step, &record)?;
        for (t, vals) in &rows {
            for (v, x) in record.iter().zip(vals) {
                ensure!(
                    !matches!(x, Value::Real(r) if !r.is_finite()),
                    "{id}: reference output {} is {} at t = {t}",
                    v.name,
                    fmt_value(x)
                );
            }
        }
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        write_limited(
            &dir.join(format!("{id}_ref.csv")),
            &csv(&refs, &rows, true)?,
        )?;
        let in_names: Vec<&str> = table.columns.iter().map(|v| v.name.as_str()).collect();
        write_limited(
            &dir.join(format!("{id}_in.csv")),
            &csv(&in_names, &table.rows, true)?,
        )?;
        entrynav_studies::output::atomic_file::write(
            &dir.join(format!("{id}_ref.opt")),
            format!(
                "StartTime, {start:?}\nStopTime, {stop:?}\nStepSize, {step:?}\nRelTol, 1e-06\n"
            ),
        )?;
        let bytes = std::fs::read(fmu).with_context(|| format!("cannot read {}", fmu.display()))?;
        entrynav_studies::output::atomic_file::write(&dir.join(format!("{id}.fmu")), bytes)?;
        entrynav_studies::output::atomic_file::write(
            &dir.join("README.md"),
            format!(
                "# {id}\n\n{}\n\nExported by entrynav {} (`entrynav fmu pack`), FMI {version} co-simulation, {platform}.\n\n\
                 The reference result `{id}_ref.csv` is the model run with its default parameters from {start} s to {stop} s \
                 in communication steps of {step} s, with the inputs of `{id}_in.csv` held over each step (the row at each \
                 communication point applies). The model is deterministic: an importer that applies the same inputs at the \
                 same communication points reproduces the reference exactly.\n",
                spec.description(),
                env!("CARGO_PKG_VERSION"),
            ),
        )?;
        println!(
            "{}: {} reference rows x {} outputs, {} input columns",
            dir.display(),
            rows.len(),
            record.len(),
            table.columns.len()
        );
    }
    Ok(())
}
