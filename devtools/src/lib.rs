//! `entrynav-dev`: entrynav's developer tools, an xtask-style binary of the workspace that is
//! built with it (`cargo build --release --workspace` → `target/release/entrynav-dev`) and never
//! shipped.
//!
//! * `entrynav-dev fmu check FILE` — our FMI host against the in-process library, every output
//!   bit for bit (`--bench`: doStep through the host against the engine);
//! * `entrynav-dev fmu fuzz FILE --calls N` — random FMI 2.0 or 3.0 call sequences through our
//!   host against a model of what the FMU must answer;
//! * `entrynav-dev fmu run …` — the in-process reference run of a model, as CSV;
//! * `entrynav-dev fmu cross-check …` — the FMI Cross-Check files of packed FMUs.
//!
//! **Why these are not `entrynav fmu` subcommands.** They need our own FMI host
//! (`entrynav-fmi-host`), which loads an FMU's shared library with libloading; a library loader
//! must not ship in the user's `entrynav` binary, whose `fmu` command only packs FMUs. Users
//! check an FMU with the real FMI tools (fmpy, the Reference-FMUs' fmusim, the FMU Compliance
//! Checker), which `tests/python` runs on every packed FMU; `run` and `cross-check` produce the
//! references those tests compare with. The commands print and write exactly what `entrynav fmu
//! check/run/fuzz/cross-check` did before they moved here.
//!
//! Exit codes: 0 success, 1 an output file that could not be written, 2 anything else (a usage
//! error, an FMU that does not check, a fuzzer finding).

pub mod fmu;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

/// entrynav's developer tools (not shipped with entrynav).
#[derive(Parser)]
#[command(name = "entrynav-dev", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Test tools of the FMUs (FMI 2.0 and 3.0) through our own FMI host: check, fuzz, run,
    /// cross-check.
    Fmu(fmu::FmuArgs),
}

/// The `entrynav-dev` command tree as the binary parses it: every option that takes a value
/// accepts a negative number after a space (`--step -1` reaches the step's range message).
pub fn command() -> clap::Command {
    negative_numbers_everywhere(Cli::command())
}

fn negative_numbers_everywhere(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    })
    .mut_subcommands(negative_numbers_everywhere)
}

/// Parse the process's arguments, run, print an error and exit with its code.
pub fn main_entry() {
    let matches = command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    let result = match &cli.command {
        Command::Fmu(args) => fmu::run(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        let written = e
            .chain()
            .any(|c| c.is::<entrynav_studies::output::OutputError>());
        std::process::exit(if written { 1 } else { 2 });
    }
}
