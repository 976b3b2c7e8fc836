//! `entrynav`: Mars entry navigation from the command line: argument parsing, printing and the
//! files of each command over the study layer (`entrynav-studies`). `src/main.rs` is the binary;
//! [`command`] is its clap command tree, which `tests/option_walk.rs` walks.

mod args;
mod atmosphere_file;
mod atmosphere_generate;
mod atmosphere_inspect;
mod compare;
mod compare_table;
mod csv_file;
mod exit_code;
mod figures;
mod fmu;
mod grid;
mod guidance;
mod guidance_reference;
mod interrupt;
mod lincov;
mod observe;
mod optimize;
mod preflight;
mod progress;
mod replay;
mod report;
mod scenarios;
pub mod simulate;
mod threads;
mod trade;
mod trade_args;
mod trade_checkpoint;
mod trade_lincov;
mod trade_merge;
mod trade_outputs;
mod trade_tables;
mod train;
mod tune;

use anyhow::{Context, Result};
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use entrynav_loader as load;

/// Mars atmospheric-entry navigation: scenarios, truth simulation, navigation filters and
/// Monte Carlo trade studies, observability and Fisher information.
#[derive(Parser)]
#[command(name = "entrynav", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// Parsed once per process; boxing the larger argument structs would only add noise.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// List the built-in scenarios.
    Scenarios,
    /// Inspect a scenario.
    Scenario {
        #[command(subcommand)]
        action: ScenarioAction,
    },
    /// Density tables (CSV, Mars-GRAM output, Mars-GRAM Monte Carlo sets): inspect.
    Atmosphere {
        #[command(subcommand)]
        action: atmosphere_inspect::AtmosphereAction,
    },
    /// Simulate the truth trajectory and the sensor measurements of a scenario.
    Simulate(simulate::SimulateArgs),
    /// Monte Carlo trade study of navigation filters on a scenario.
    ///
    /// Per filter: RMSE per state, consistency (NEES over all states with truth-equivalent
    /// augmented parameters and over the six kinematic states; NIS overall and per channel; χ²
    /// 95 % bounds), and two kinds of bad runs: FAILED = the filter stopped on a numerical
    /// failure (a covariance lost positive definiteness, a value became non-finite); DIVERGED =
    /// the run completed but its final NEES exceeds 100 × its degrees of freedom (confidently
    /// wrong). `failures` lists run index, time and reason; `--replay-run K --csv-dir DIR`
    /// writes run K's full series.
    ///
    /// Progress is a bar on a terminal; with the environment variable `ENTRYNAV_PROGRESS=lines`
    /// (and no `--quiet`) it is one `progress: DONE/TOTAL runs` line on standard error per chunk
    /// of finished runs, for a script that reads it through a pipe (e.g. to know that runs have
    /// finished before it sends Ctrl-C).
    Trade(trade::TradeArgs),
    /// Tune a scenario's process noise (and optionally the assumed measurement noise) until its
    /// filters are consistent (ANEES/dof and ANIS/dof near 1, no divergence), validate on fresh
    /// runs and write the tuned scenario.
    Tune(tune::TuneArgs),
    /// Degree of observability δ(t) and beacon Fisher information along a scenario's trajectory.
    Observe(observe::ObserveArgs),
    /// Linear covariance analysis (LinCov) of a filter along the scenario's nominal trajectory:
    /// the true RMSE a Monte Carlo of the same filter would measure (model mismatch included),
    /// the filter's own σ and the predicted NEES, in one pass (Maybeck vol. 1 ch. 6; Geller
    /// 2006). Analyses the EKF (its iterated update linearised at the nominal, consider states
    /// included), the UKF as its EKF equivalent, and the fusion filters CI and DCIFAIF; other
    /// filters get an error saying why. `--compare-mc RUNS` runs the Monte Carlo beside it and
    /// prints both wall times.
    Lincov(lincov::LinCovArgs),
    /// Train the USKF-NN density network offline (seed 001 Algorithm 1) and write its file.
    TrainDensity(train::TrainArgs),
    /// Pack the FMI 2.0 and FMI 3.0 co-simulation FMUs (and SSP systems of them).
    Fmu(fmu::FmuArgs),
    /// Optimize beacon and orbiter geometry (seed 002 Sec. 4): orbiters, ground sites, certified
    /// site selection.
    Optimize(optimize::OptimizeArgs),
    /// Entry guidance: `deliver`, the Monte Carlo of delivery at deployment with navigation
    /// filters in the loop; `reference`, the reference trajectory and gains (docs/guidance.md).
    Guidance(guidance::GuidanceArgs),
}

#[derive(Subcommand)]
enum ScenarioAction {
    /// Print a scenario (built-in name or TOML file) as written, comments included, after
    /// validating it; the output is a file to copy and edit.
    Show {
        /// Built-in name or path to a scenario TOML file.
        scenario: String,
        /// Print the validated configuration in canonical TOML instead (every field, defaults
        /// filled in, no comments).
        #[arg(long)]
        resolved: bool,
    },
    /// Print the reference of every scenario field (type, default, allowed range, meaning) as
    /// Markdown, generated from the configuration types: docs/scenario-reference.md.
    Schema,
}

/// The `entrynav` command tree as the binary parses it: every option that takes a value accepts
/// a negative number after a space (`--region -34 -18 -84 -74`; `--seed -1` reaches the seed's
/// range message instead of "unexpected argument").
pub fn command() -> clap::Command {
    args::negative_numbers_everywhere(Cli::command())
}

/// The `entrynav` command: parse the process's arguments, run, print an error and exit with its
/// code. What the binary's `main` is.
pub fn cli_main() {
    interrupt::die_on_broken_pipe();
    let matches = command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Err(e) = run(cli) {
        let code = exit_code::code(&e);
        if code == interrupt::EXIT_INTERRUPTED {
            eprintln!("{e}");
        } else {
            eprintln!("error: {e:#}");
        }
        std::process::exit(code);
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Scenarios => scenarios::list(),
        Command::Scenario {
            action: ScenarioAction::Schema,
        } => {
            print!("{}", entrynav::scenario::reference::markdown());
            Ok(())
        }
        Command::Scenario {
            action:
                ScenarioAction::Show {
                    scenario: name,
                    resolved,
                },
        } => {
            let (cfg, _) = load::resolve(&name, load::Base::CurrentDir)?.into_parts();
            if resolved {
                print!("{}", cfg.to_toml_string());
            } else if let Some(text) = entrynav::scenario::builtin_toml(name.trim()) {
                print!("{text}");
            } else {
                let path = name.trim();
                let text = entrynav_loader::read_text(path)
                    .with_context(|| format!("cannot read scenario file {path}"))?;
                print!("{text}");
            }
            Ok(())
        }
        Command::Atmosphere { action } => atmosphere_inspect::run(&action),
        Command::Simulate(args) => simulate::run(&args),
        Command::Trade(args) => trade::run(&args),
        Command::Tune(args) => tune::run(&args),
        Command::Observe(args) => observe::run(&args),
        Command::Lincov(args) => lincov::run(&args),
        Command::TrainDensity(args) => train::run(&args),
        Command::Fmu(args) => fmu::run(&args),
        Command::Optimize(args) => optimize::run(&args),
        Command::Guidance(args) => guidance::run(&args),
    }
}
