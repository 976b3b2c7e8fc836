//! `entrynav-dev fmu run`: the in-process reference run of a model (no FFI), writing its outputs as
//! CSV ([`super::table`]). The cross-check artifacts are made with the same runner.

use super::table::{Table, csv, parse_value};
use anyhow::{Context, Result, ensure};
use clap::Args;
use entrynav_fmi_host::{file_uri, unpack};
use entrynav_fmu::ModelSpec;
use entrynav_fmu::instance::{Instance, Status};
use entrynav_fmu::vars::{Causality, Model, Value, Var};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Arguments of `entrynav-dev fmu run`.
#[derive(Args)]
pub(super) struct RunArgs {
    /// Model identifier: MarsEntryNav, MarsEntryNavFilter or MarsEntryTruth.
    #[arg(long, default_value = "MarsEntryNav")]
    model: String,
    /// Run the model of this packed .fmu instead (its table, embedded scenario and resources;
    /// in process, its library is not called).
    #[arg(long, conflicts_with = "resources")]
    fmu: Option<PathBuf>,
    /// Parameter or input start value NAME=VALUE (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
    /// Input table (CSV with a `time` column and one column per input; the row at or before each
    /// communication point applies, as fmpy applies discrete inputs).
    #[arg(long)]
    input: Option<PathBuf>,
    #[arg(long, help = "Stop time [s]")]
    stop: f64,
    #[arg(long, help = "Communication step [s]")]
    step: f64,
    /// Folder scenario files are read from (the FMU's resources).
    #[arg(long)]
    resources: Option<PathBuf>,
    /// Output CSV.
    #[arg(long)]
    out: PathBuf,
}

/// Run `spec` in process from 0 to `stop` in steps of `step` with the parameter and start values
/// `sets` and the input `table`; returns the time and the values of `record` at every
/// communication point, the start included.
pub(super) fn run_in_process(
    spec: &Arc<ModelSpec>,
    resources: Option<&Path>,
    sets: &[(Var, Value)],
    table: &Table,
    stop: f64,
    step: f64,
    record: &[Var],
) -> Result<Vec<(f64, Vec<Value>)>> {
    let uri = resources.map(file_uri);
    let mut inst = Instance::new(
        Arc::clone(spec),
        "reference",
        spec.guid(),
        uri.as_deref(),
        false,
        Box::new(|_, _, msg| eprintln!("{msg}")),
    )
    .map_err(|(_, e)| anyhow::anyhow!(e))?;
    for (v, val) in sets {
        ensure!(
            inst.set(v.ty, &[v.vr], vec![val.clone()]) == Status::Ok,
            "cannot set {}",
            v.name
        );
    }
    let apply = |inst: &mut Instance, t: f64| -> Result<()> {
        if let Some(vals) = table.at(t) {
            for (v, val) in table.columns.iter().zip(vals) {
                ensure!(
                    inst.set(v.ty, &[v.vr], vec![val.clone()]) == Status::Ok,
                    "cannot set {}",
                    v.name
                );
            }
        }
        Ok(())
    };
    let read = |inst: &mut Instance, t: f64| -> Result<(f64, Vec<Value>)> {
        let mut vals = Vec::with_capacity(record.len());
        for v in record {
            let got = inst
                .get(v.ty, &[v.vr])
                .map_err(|s| anyhow::anyhow!("get {}: {s:?}", v.name))?;
            vals.extend(got);
        }
        Ok((t, vals))
    };
    ensure!(inst.setup_experiment(0.0, Some(stop)) == Status::Ok);
    ensure!(inst.enter_initialization_mode() == Status::Ok);
    apply(&mut inst, 0.0)?;
    ensure!(
        inst.exit_initialization_mode() == Status::Ok,
        "initialisation failed"
    );
    let mut rows = vec![read(&mut inst, 0.0)?];
    let n = (stop / step).round() as usize;
    for k in 0..n {
        let t = k as f64 * step;
        apply(&mut inst, t)?;
        ensure!(
            inst.do_step(t, step) <= Status::Warning,
            "doStep at {t} failed"
        );
        rows.push(read(&mut inst, (k + 1) as f64 * step)?);
    }
    Ok(rows)
}

pub(super) fn run_reference(a: &RunArgs) -> Result<()> {
    let stop = super::bounds::stop(a.stop)?;
    super::bounds::step(a.step, stop)?;
    if let Some(p) = &a.fmu {
        super::bounds::input(p, "--fmu")?;
    }
    entrynav_studies::output::check_output_file(&a.out, "--out")?;
    let unpacked = a.fmu.as_deref().map(unpack).transpose()?;
    let (spec, resources) = match &unpacked {
        Some(u) => (Arc::clone(&u.spec), Some(u.dir.join("resources"))),
        None => {
            let m = Model::from_identifier(&a.model)
                .with_context(|| format!("unknown model '{}'", a.model))?;
            (Arc::new(ModelSpec::generic(m)), a.resources.clone())
        }
    };
    let vars = spec.vars();
    let find = |name: &str| {
        vars.iter()
            .find(|v| v.name == name)
            .with_context(|| format!("{} has no variable '{name}'", spec.identifier()))
    };
    let mut sets = Vec::new();
    for s in &a.sets {
        let (name, value) = s
            .split_once('=')
            .with_context(|| format!("--set '{s}': expected NAME=VALUE"))?;
        let v = find(name.trim())?;
        sets.push((v.clone(), parse_value(v, value)?));
    }
    let table = match &a.input {
        Some(p) => Table::parse(&entrynav_studies::input::read_text(p, "--input")?, vars)?,
        None => Table::default(),
    };
    let outputs: Vec<Var> = vars
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .cloned()
        .collect();
    let rows = run_in_process(
        &spec,
        resources.as_deref(),
        &sets,
        &table,
        a.stop,
        a.step,
        &outputs,
    )?;
    let names: Vec<&str> = outputs.iter().map(|v| v.name.as_str()).collect();
    entrynav_studies::output::atomic_file::write(&a.out, csv(&names, &rows, false)?)?;
    Ok(())
}
