//! `entrynav simulate`: one truth run with its measurement record.

use anyhow::{Context, Result};
use clap::Args;
use entrynav::scenario::Scenario;
use entrynav::sim::{Peaks, TruthRun, simulate_truth_with_peaks};
use entrynav_loader as load;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `entrynav simulate`.
#[derive(Args)]
pub struct SimulateArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    scenario: String,
    /// Override a scenario field: PATH=VALUE in TOML syntax (repeatable), e.g.
    /// `--set truth.density_bias=0.095`.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    sets: Vec<String>,
    /// Seed of the measurement noise (and of the dispersions with --dispersed).
    #[arg(long, default_value_t = 1)]
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
    let (cfg, dir) = load::resolve(&args.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &args.sets)?;
    crate::exit::warn_implausible(&cfg);
    let scenario = load::build(cfg, &dir)?;
    let mut rng = ChaCha8Rng::seed_from_u64(args.seed);
    let draw = if args.dispersed {
        scenario.draw_truth(&mut rng)
    } else {
        entrynav::scenario::TruthDraw {
            initial: scenario.truth_initial,
            model: scenario.truth_model.clone(),
        }
    };
    let (run, peaks) = simulate_truth_with_peaks(&scenario, &draw, &mut rng)?;
    if let Some(path) = args.out.as_deref().filter(|p| crate::exit::is_stdout(p)) {
        let mut w = crate::csv_file::writer(std::io::stdout().lock());
        write_csv(&mut w, &scenario, &run)
            .and_then(|()| Ok(w.flush()?))
            .with_context(|| format!("writing {}", path.display()))?;
        return Ok(());
    }
    if let Some(path) = &args.out {
        crate::csv_file::write(path, |w| Ok(write_csv(w, &scenario, &run)?))?;
    }
    print_summary(&scenario, &run, &peaks, args);
    Ok(())
}

/// The truth run as a table: the column names and one row per truth sample (t = 0, every
/// measurement epoch, the final time); a measurement is `None` where the channel was not sampled
/// or not available, a visibility 0 or 1. What `--out FILE` writes and the Python package's
/// `simulate` returns.
pub fn truth_table(scenario: &Scenario, run: &TruthRun) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    let cartesian = scenario.truth_model.kind.is_cartesian();
    let mut header: Vec<String> = [
        "t_s",
        "r_m",
        "lon_rad",
        "lat_rad",
        "v_mps",
        "fpa_rad",
        "heading_rad",
        "altitude_m",
        "density_kgm3",
        "dynamic_pressure_pa",
        "heating_wm2",
        "aero_accel_mps2",
    ]
    .map(String::from)
    .to_vec();
    if cartesian {
        header.extend(["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"].map(String::from));
    }
    header.extend(scenario.beacon_names.iter().map(|b| format!("visible_{b}")));
    header.extend(scenario.channels.iter().map(|c| c.name.clone()));
    let mut epochs = run.epochs.iter().peekable();
    let mut rows = Vec::with_capacity(run.samples.len());
    for s in &run.samples {
        let mut row: Vec<Option<f64>> = vec![Some(s.t)];
        row.extend(s.spherical.iter().map(|v| Some(*v)));
        row.extend(
            [
                s.altitude,
                s.density,
                s.dynamic_pressure,
                s.heating,
                s.aero_accel,
            ]
            .map(Some),
        );
        if cartesian {
            row.extend(s.state.iter().map(|v| Some(*v)));
        }
        row.extend(s.visible.iter().map(|v| Some(f64::from(u8::from(*v)))));
        match epochs.peek() {
            Some(e) if (e.t - s.t).abs() < 1e-9 => {
                row.extend(e.values.iter().copied());
                epochs.next();
            }
            _ => row.extend(std::iter::repeat_n(None, scenario.channels.len())),
        }
        rows.push(row);
    }
    (header, rows)
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
