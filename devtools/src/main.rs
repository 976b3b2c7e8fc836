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

mod fmu;

use clap::{Parser, Subcommand};

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

fn main() {
    let cli = Cli::parse();
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
