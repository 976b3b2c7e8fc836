//! `entrynav simulate`: the command over the simulation study (`entrynav_studies::simulate`):
//! one truth run with its measurement record, printed as a summary and written as CSV.

use crate::args::ScenarioArgs;
use anyhow::{Context, Result};
use clap::Args;
use entrynav::scenario::Scenario;
use entrynav::sim::{Peaks, TruthRun};
use entrynav_studies::ScenarioInput;
use entrynav_studies::simulate::{SimulateOptions, run_simulate};
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `entrynav simulate`.
#[derive(Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    scenario: ScenarioArgs,
    /// Seed of the measurement noise (and of the dispersions with --dispersed).
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = crate::args::seed)]
    seed: u64,
    /// Draw the truth from the scenario's dispersions (initial state, vehicle, density bias,
    /// atmosphere perturbation) instead of using the nominal truth.
    #[arg(long)]
    dispersed: bool,
    /// Write the trajectory and measurements as CSV to this file (`-`: to standard output,
    /// without the summary).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Run the command.
pub fn run(args: &SimulateArgs) -> Result<()> {
    crate::preflight::check_output_files(&[(args.out.as_deref(), "--out")])?;
    let input = ScenarioInput::resolve(&args.scenario.scenario, &args.scenario.overrides.sets)?;
    crate::preflight::warn_implausible(&input.config);
    let scenario = input.build()?;
    let options = SimulateOptions {
        seed: args.seed,
        dispersed: args.dispersed,
    };
    let sim = run_simulate(&scenario, &options)?;
    let run = &sim.run;
    if let Some(path) = args
        .out
        .as_deref()
        .filter(|p| crate::preflight::is_stdout(p))
    {
        let mut w = crate::csv_file::writer(std::io::stdout().lock());
        write_csv(&mut w, &scenario, run)
            .and_then(|()| Ok(w.flush()?))
            .with_context(|| format!("writing {}", path.display()))?;
        return Ok(());
    }
    if let Some(path) = &args.out {
        crate::csv_file::write(path, |w| Ok(write_csv(w, &scenario, run)?))?;
    }
    print_summary(&scenario, run, &sim.peaks, args);
    Ok(())
}

/// The truth run as a table (`entrynav_studies::simulate::truth_table`), for the Python package
/// until it calls the study itself.
pub fn truth_table(scenario: &Scenario, run: &TruthRun) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    entrynav_studies::simulate::truth_table(scenario, run)
}

/// CSV of [`truth_table`].
fn write_csv<W: Write>(
    w: &mut csv::Writer<W>,
    scenario: &Scenario,
    run: &TruthRun,
) -> csv::Result<()> {
    let (header, rows) = truth_table(scenario, run);
    w.write_record(&header)?;
    for row in rows {
        w.write_record(row.into_iter().map(crate::csv_file::opt))?;
    }
    Ok(())
}

/// The summary; the peak loads are over every truth integration step (`timing.truth_step_s`),
/// not only the sampled rows of the CSV.
fn print_summary(scenario: &Scenario, run: &TruthRun, peaks: &Peaks, args: &SimulateArgs) {
    let last = run
        .samples
        .last()
        .expect("a run has at least its initial sample");
    let (acc, t_acc) = (peaks.aero_accel.value, peaks.aero_accel.t);
    let (q, t_q) = (peaks.dynamic_pressure.value, peaks.dynamic_pressure.t);
    let (h, t_h) = (peaks.heating.value, peaks.heating.t);
    println!(
        "scenario        {} ({})",
        scenario.config.name,
        if args.dispersed {
            "dispersed truth"
        } else {
            "nominal truth"
        }
    );
    println!("seed            {}", args.seed);
    let why = match run.stop {
        entrynav::sim::StopReason::Duration => "timing.duration_s reached",
        entrynav::sim::StopReason::StopSpeed => "below timing.stop_speed_mps: parachute deployment",
        entrynav::sim::StopReason::Ground => "ground reached",
    };
    println!("stopped         at t = {:.2} s ({why})", last.t);
    println!("final altitude  {:.3} km", last.altitude / 1e3);
    println!("final speed     {:.2} m/s", last.spherical[3]);
    println!(
        "peak decel      {:.2} m/s^2 ({:.2} Earth g) at t = {:.1} s",
        acc,
        acc / entrynav::planet::G_EARTH,
        t_acc
    );
    println!("peak dyn. press {:.1} Pa at t = {:.1} s", q, t_q);
    println!(
        "peak heating    {:.1} kW/m^2 at t = {:.1} s (R_n = {} m)",
        h / 1e3,
        t_h,
        scenario.measurement.heating.nose_radius
    );
    println!(
        "measurements    {} epochs, {} channels",
        run.epochs.len(),
        scenario.channels.len()
    );
    for (c, spec) in scenario.channels.iter().enumerate() {
        let n = run.epochs.iter().filter(|e| e.values[c].is_some()).count();
        println!("  {:<28} {n} samples", spec.name);
    }
    if let Some(out) = &args.out {
        println!("wrote           {}", out.display());
    }
}
