//! `entrynav fmu`: build the FMI 2.0 co-simulation FMUs (`pack`, also scenario-specific ones),
//! check a `.fmu` through our own FMI host against the in-process library (`check`, with
//! `--bench`), drive random call sequences through the host (`fuzz`), run a model in process
//! (`run`) and write the FMI Cross-Check files of packed FMUs (`cross-check`).
//!
//! The host (the `entrynav-fmi-host` crate, kept out of the FMU library) loads
//! `binaries/linux64/<modelIdentifier>.so` with libloading and calls the 34 fmi2 functions.

#![allow(non_snake_case)]

mod check;
mod cross_check;
mod fuzz;
mod fuzz3;
mod guided;
mod library;
mod pack;
mod run;
mod ssp;
mod table;

use check::check;
use cross_check::{CrossCheckArgs, cross_check};
use fuzz::{FuzzArgs, fuzz};
use pack::{PackArgs, pack};
use run::run_reference;

use anyhow::{Context, Result, bail, ensure};
use clap::{Args, Subcommand};
use entrynav::scenario::{BUILTIN_NAMES, builtin_toml};
use entrynav::sim::engine::TruthSensors;
use entrynav_fmu::instance::{Instance, Status};
use entrynav_fmu::vars::{Causality, Key, MAX_BEACONS, Model, Slot, Type, Value, Var};
use std::ffi::CStr;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Arguments of `entrynav fmu`.
#[derive(Args)]
pub struct FmuArgs {
    #[command(subcommand)]
    action: FmuAction,
}

#[derive(Subcommand)]
enum FmuAction {
    /// Build MarsEntryNav.fmu, MarsEntryNavFilter.fmu, MarsEntryTruth.fmu, MarsEntryGuidance.fmu
    /// and MarsEntryNavGuided.fmu (or, with --scenario, the combined model specific to one
    /// scenario), each with a stripped library bound to its model.
    Pack(PackArgs),
    /// Unzip a .fmu, run a scenario through its fmi2 API with our host and compare every output
    /// with the in-process library, bit for bit.
    Check(CheckArgs),
    /// Run a model in process (no FFI) with an input table and write every output as CSV: the
    /// reference the Python tests compare external FMI tools with.
    Run(RunArgs),
    /// Random fmi2 call sequences and values through our host (fmi3 for an FMI 3.0 FMU), huge and
    /// tiny intervals and every size-like argument included: no crash, every illegal call answered
    /// with fmi2Error (fmi3Error), every refused request leaves the instance as it was.
    Fuzz(FuzzArgs),
    /// Write the FMI Cross-Check files (<Model>_ref.csv, _ref.opt, _in.csv, README.md and the
    /// .fmu) of packed FMUs, laid out as fmus/2.0/cs/linux64/entrynav/<version>/<Model>/.
    CrossCheck(CrossCheckArgs),
}

#[derive(Args)]
struct RunArgs {
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
    /// Stop time [s].
    #[arg(long)]
    stop: f64,
    /// Communication step [s].
    #[arg(long)]
    step: f64,
    /// Folder scenario files are read from (the FMU's resources).
    #[arg(long)]
    resources: Option<PathBuf>,
    /// Output CSV.
    #[arg(long)]
    out: PathBuf,
}

#[derive(Args)]
struct CheckArgs {
    /// The .fmu file.
    file: PathBuf,
    /// Scenario parameter (built-in name or a file in the FMU's resources). Default:
    /// four-beacon-fusion, or msl-guided.toml for MarsEntryGuidance (whose inputs come from the
    /// in-process guided loop on it, the EKF in the loop, run 0 of --seed) and for
    /// MarsEntryNavGuided.
    #[arg(long)]
    scenario: Option<String>,
    /// Filter parameter (default: the FMU's: dcifaif for the generic FMUs, ekf for
    /// MarsEntryNavGuided).
    #[arg(long)]
    filter: Option<String>,
    /// Seed parameter.
    #[arg(long, default_value_t = 1)]
    seed: i32,
    /// Nominal truth instead of a dispersed one.
    #[arg(long)]
    nominal: bool,
    /// Communication step [s] (default: the fastest sensor period of the scenario).
    #[arg(long)]
    step: Option<f64>,
    /// Also time doStep through the host against the in-process engine.
    #[arg(long)]
    bench: bool,
    /// Repetitions of the benchmark.
    #[arg(long, default_value_t = 15)]
    reps: usize,
}

/// Run the command.
pub fn run(args: &FmuArgs) -> Result<()> {
    match &args.action {
        FmuAction::Pack(a) => pack(a),
        FmuAction::Check(a) => check(a),
        FmuAction::Run(a) => run_reference(a),
        FmuAction::Fuzz(a) => fuzz(a),
        FmuAction::CrossCheck(a) => cross_check(a),
    }
}
