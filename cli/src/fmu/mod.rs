//! `entrynav fmu`: build the FMI 2.0 co-simulation FMUs (`pack`), check a `.fmu` through our own
//! FMI host against the in-process library (`check`, with `--bench`), and drive random call
//! sequences through the host (`fuzz`).
//!
//! The host (`mars_entry_nav::host`, in the `fmu` crate) loads
//! `binaries/linux64/<modelIdentifier>.so` with libloading and calls the 34 fmi2 functions.

#![allow(non_snake_case)]

mod check;
mod fuzz;
mod pack;
mod run;

use check::check;
use fuzz::fuzz;
use pack::pack;
use run::run_reference;

use anyhow::{Context, Result, bail, ensure};
use clap::{Args, Subcommand};
use entrynav::scenario::{BUILTIN_NAMES, builtin_toml};
use entrynav::sim::engine::TruthSensors;
use mars_entry_nav::instance::{Instance, Status};
use mars_entry_nav::vars::{Causality, Key, MAX_BEACONS, Model, Slot, Type, Value, Var, variables};
use mars_entry_nav::xml::model_description;
use mars_entry_nav::{guid_of, xml};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::ffi::{CStr, c_int, c_void};
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
    /// Build MarsEntryNav.fmu, MarsEntryNavFilter.fmu and MarsEntryTruth.fmu.
    Pack {
        /// Output folder.
        #[arg(long, default_value = "target/fmu")]
        out: PathBuf,
        /// The FMU shared library (default: libmars_entry_nav.so next to this executable; build
        /// it with `cargo build --release -p entrynav-fmu`).
        #[arg(long)]
        lib: Option<PathBuf>,
    },
    /// Unzip a .fmu, run a scenario through its fmi2 API with our host and compare every output
    /// with the in-process library, bit for bit.
    Check(CheckArgs),
    /// Run a model in process (no FFI) with an input table and write every output as CSV: the
    /// reference the Python tests compare external FMI tools with.
    Run(RunArgs),
    /// Random fmi2 call sequences and values through our host: no crash, and every illegal call
    /// answered with fmi2Error.
    Fuzz {
        /// The .fmu file.
        file: PathBuf,
        /// Number of random call sequences.
        #[arg(long, default_value_t = 200)]
        cases: usize,
        /// Calls per sequence.
        #[arg(long, default_value_t = 60)]
        calls: usize,
        /// Seed of the random sequences.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
}

#[derive(Args)]
struct RunArgs {
    /// Model identifier: MarsEntryNav, MarsEntryNavFilter or MarsEntryTruth.
    #[arg(long, default_value = "MarsEntryNav")]
    model: String,
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
    /// Scenario parameter (built-in name or a file in the FMU's resources).
    #[arg(long, default_value = "four-beacon-fusion")]
    scenario: String,
    /// Filter parameter.
    #[arg(long, default_value = "dcifaif")]
    filter: String,
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
        FmuAction::Pack { out, lib } => pack(out, lib.as_deref()),
        FmuAction::Check(a) => check(a),
        FmuAction::Run(a) => run_reference(a),
        FmuAction::Fuzz {
            file,
            cases,
            calls,
            seed,
        } => fuzz(file, *cases, *calls, *seed),
    }
}
