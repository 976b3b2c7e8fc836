//! `entrynav-dev fmu`: the FMU test tools, through our own FMI host (`entrynav-fmi-host`, which
//! loads `binaries/<platform>/<modelIdentifier>.so` with libloading): `check` (with `--bench`),
//! `fuzz`, `run` and `cross-check`. The FMUs themselves are packed by `entrynav fmu pack`.

mod bounds;
mod check;
mod cross_check;
mod defaults;
mod fuzz;
mod guided;
mod run;
mod table;

use clap::{Args, Subcommand};

/// Arguments of `entrynav-dev fmu`.
#[derive(Args)]
pub struct FmuArgs {
    #[command(subcommand)]
    action: FmuAction,
}

#[derive(Subcommand)]
enum FmuAction {
    /// Unzip a .fmu, run a scenario through its fmi2 API with our host and compare every output
    /// with the in-process library, bit for bit.
    Check(check::CheckArgs),
    /// Run a model in process (no FFI) with an input table and write every output as CSV: the
    /// reference the Python tests compare external FMI tools with.
    Run(run::RunArgs),
    /// Random fmi2 call sequences and values through our host (fmi3 for an FMI 3.0 FMU), huge and
    /// tiny intervals and every size-like argument included: no crash, every illegal call answered
    /// with fmi2Error (fmi3Error), every refused request leaves the instance as it was.
    Fuzz(fuzz::FuzzArgs),
    #[command(
        about = "Write the FMI Cross-Check files (<Model>_ref.csv, _ref.opt, _in.csv, README.md and the .fmu) of packed FMUs, laid out as fmus/2.0/cs/linux64/entrynav/<version>/<Model>/"
    )]
    CrossCheck(cross_check::CrossCheckArgs),
}

/// Run the command.
pub fn run(args: &FmuArgs) -> anyhow::Result<()> {
    match &args.action {
        FmuAction::Check(a) => check::check(a),
        FmuAction::Run(a) => run::run_reference(a),
        FmuAction::Fuzz(a) => fuzz::fuzz(a),
        FmuAction::CrossCheck(a) => cross_check::cross_check(a),
    }
}
