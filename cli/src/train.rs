//! `entrynav train-density`: offline training of the USKF-NN density network (seed 001
//! Algorithm 1), writing a network file such as `core/scenarios/msl-airdata-density-nn.toml`, and
//! (`--evaluate RUNS`) the Monte Carlo density-error evaluation of the density-adaptation filters
//! (seed 001 Table 6 in both readings of eq. 70, Fig. 10 plots).

use anyhow::{Context, Result, bail};
use clap::Args;
use entrynav::atmosphere::Exponential;
use entrynav::estimation::adaptive::{NetworkFile, fit_onboard_exponential};
use entrynav::sim::density::training::train_density_networks;
use entrynav_loader as load;
use std::path::PathBuf;

/// Arguments of `entrynav train-density`.
#[derive(Args)]
pub struct TrainArgs {
    /// Built-in scenario name or scenario TOML file; its `[filter.density.training]` section
    /// (or the seed-001 defaults) sets the training.
    #[arg(long, default_value = "msl-airdata")]
    pub scenario: String,
    /// The `--set` overrides.
    #[command(flatten)]
    pub overrides: crate::args::SetArgs,
    /// Network file to write (TOML), e.g. core/scenarios/msl-airdata-density-nn.toml. Without it
    /// nothing is trained and `--evaluate` uses the scenario's built-in network.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Seed (overrides filter.density.training.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Simulated trajectories (overrides filter.density.training.trajectories).
    #[arg(long)]
    pub trajectories: Option<usize>,
    /// Epochs (overrides filter.density.training.epochs).
    #[arg(long)]
    pub epochs: Option<usize>,
    /// Mini-batch size (overrides filter.density.training.batch_size).
    #[arg(long)]
    pub batch_size: Option<usize>,
    /// Band edges in km for one network per band, e.g. `0,40,70,130` (overrides
    /// filter.density.training.bands_km; `none` for a single network).
    #[arg(long)]
    pub bands_km: Option<String>,
    /// The worker pool.
    #[command(flatten)]
    pub workers: crate::args::ThreadsArg,
    #[arg(long, help = crate::args::QUIET_HELP)]
    pub quiet: bool,
    /// Evaluate the density estimates of `--filters` over this many Monte Carlo runs (the runs of
    /// `entrynav trade --seed MC_SEED`): eq. 70 RMSPE with the filter's density model at the true
    /// altitude (our reading of seed 001 Table 6) and at its own estimate (`trade` reports both as density_rmspe_pct and density_at_estimate_rmspe_pct).
    #[arg(long, value_name = "RUNS", value_parser = crate::args::evaluate)]
    pub evaluate: Option<usize>,
    /// Filters evaluated by `--evaluate`.
    #[arg(
        long,
        visible_alias = "filter",
        default_value = "ukf-cm,ukf-ac,uskf-nn"
    )]
    pub filters: String,
    /// Master seed of the `--evaluate` Monte Carlo runs.
    #[arg(long, default_value_t = 1)]
    pub mc_seed: u64,
    /// Write seed 001 Fig. 10-style SVG plots (density error vs time per filter: 50 runs and the
    /// RMS) into this directory (with `--evaluate`).
    #[arg(long)]
    pub plots: Option<PathBuf>,
    /// As `trade --atmosphere-file` and its companions (for `--evaluate`).
    #[command(flatten)]
    pub atmosphere: crate::atmosphere_file::AtmosphereFileArgs,
    /// As `trade --no-perturbation` (for `--evaluate`).
    #[arg(long)]
    pub no_perturbation: bool,
}

fn print_fit(e: &Exponential, radius_m: f64, lo: f64, hi: f64) {
    println!(
        "least-squares exponential fit to the truth mean profile over {lo}-{hi} km (seed 001 eq. 16):"
    );
    println!(
        "  rho_ref_kgm3 = {:.6e}   ref_radius_km = {:.4}   scale_height_km = {:.6}",
        e.rho_ref,
        (e.h_ref + radius_m) / 1e3,
        e.scale_height / 1e3
    );
}

/// Run the command.
pub fn run(args: &TrainArgs) -> Result<()> {
    if args.out.is_none() && args.evaluate.is_none() {
        bail!("nothing to do: give --out FILE to train, --evaluate RUNS to evaluate, or both");
    }
    crate::preflight::check_output_files(&[(args.out.as_deref(), "--out")])?;
    if args.evaluate.is_some() {
        entrynav_studies::options::filter_list("filters", &args.filters)?;
    }
    if let Some(d) = &args.plots {
        crate::preflight::check_output_dir(d, "--plots")?;
    }
    let (cfg, dir) = load::resolve(&args.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &args.overrides.sets)?;
    let cfg =
        crate::atmosphere_file::truth_atmosphere(cfg, &args.atmosphere, args.no_perturbation)?;
    let scenario = load::build(cfg, &dir)?;
    crate::atmosphere_file::report_truth_table(&scenario);
    if let Some(file) = &args.atmosphere.atmosphere_file {
        crate::atmosphere_file::check_profile_covers(&scenario, file)?;
    }
    let trained = match &args.out {
        Some(out) => {
            let file =
                crate::threads::with_threads(args.workers.threads, || train(args, &scenario))?;
            let text = file.to_toml_string();
            NetworkFile::from_toml_str(&text, "written network").map_err(|e| anyhow::anyhow!(e))?;
            if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
                std::fs::create_dir_all(parent)
                    .with_context(|| format!("cannot create {}", parent.display()))?;
            }
            entrynav_studies::output::atomic_file::write(out, text)?;
            println!("wrote {}", out.display());
            Some(file.to_set().map_err(|e| anyhow::anyhow!(e))?)
        }
        None => None,
    };
    if let Some(runs) = args.evaluate {
        crate::threads::with_threads(args.workers.threads, || {
            evaluate(args, scenario, trained.as_ref(), runs)
        })?;
    }
    Ok(())
}

fn train(args: &TrainArgs, scenario: &entrynav::scenario::Scenario) -> Result<NetworkFile> {
    let mut tc = scenario
        .config
        .filter
        .density
        .clone()
        .unwrap_or_default()
        .training;
    if let Some(s) = args.seed {
        tc.seed = s;
    }
    if let Some(n) = args.trajectories {
        tc.trajectories = n;
    }
    if let Some(n) = args.epochs {
        tc.epochs = n;
    }
    if let Some(n) = args.batch_size {
        tc.batch_size = n;
    }
    if let Some(b) = &args.bands_km {
        tc.bands_km = if b.trim() == "none" {
            Vec::new()
        } else {
            b.split(',')
                .map(|v| v.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .with_context(|| format!("--bands-km '{b}': expected numbers, e.g. 0,40,70,130"))?
        };
    }
    tc.validate("training")
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    if scenario.filter_model().kind.is_cartesian() {
        bail!("train-density needs a spherical scenario (the network maps radius to density)");
    }
    let radius = scenario.planet.radius;
    let [lo, hi] = tc.fit_altitude_km;
    let fit = fit_onboard_exponential(&scenario.truth_model.atmosphere, lo, hi)
        .map_err(|e| anyhow::anyhow!(e))?;
    print_fit(&fit, radius, lo, hi);
    println!(
        "training: {} trajectories x {} s at {} s, 1-{}-1 tanh, {} epochs, batch {}, lr {:e}..{:e}, seed {}, {} threads",
        tc.trajectories,
        tc.duration_s,
        tc.sample_interval_s,
        tc.hidden,
        tc.epochs,
        tc.batch_size,
        tc.lr_max,
        tc.lr_min,
        tc.seed,
        rayon::current_num_threads()
    );
    let every = (tc.epochs / 10).max(1);
    let quiet = args.quiet;
    let progress = move |band: usize, epoch: usize, mse: f64| {
        if !quiet && (epoch % every == 0 || epoch == 1) {
            eprintln!("  band {band} epoch {epoch:>6}  train MSE {mse:.3e}");
        }
    };
    let clock = std::time::Instant::now();
    let (file, _) =
        train_density_networks(scenario, &tc, &progress).map_err(|e| anyhow::anyhow!(e))?;
    report(&file);
    println!(
        "training took {:.1} s wall (data generation included)",
        clock.elapsed().as_secs_f64()
    );
    Ok(file)
}

fn evaluate(
    args: &TrainArgs,
    scenario: entrynav::scenario::Scenario,
    networks: Option<&entrynav::estimation::adaptive::DensityNetworkSet>,
    runs: usize,
) -> Result<()> {
    use entrynav::sim::density::density_eval::{DensityEvalOptions, evaluate_density_filters};
    let kinds =
        entrynav_studies::filters::fitting_filters("filters", &args.filters, &scenario.onboard)?;
    let scenario = std::sync::Arc::new(scenario);
    let opts = DensityEvalOptions {
        runs,
        seed: args.mc_seed,
        keep_runs: 50,
    };
    let clock = std::time::Instant::now();
    let quiet = args.quiet;
    let progress = move |done: usize| {
        if !quiet && (done % 100 == 0 || done == runs) {
            eprintln!("  {done}/{runs} runs");
        }
    };
    let reports = evaluate_density_filters(&scenario, &kinds, networks, &opts, &progress)
        .map_err(|e| anyhow::anyhow!(e))?;
    println!(
        "density RMSPE (seed 001 eq. 70), scenario {}, {runs} runs, seed {} ({:.1} s wall):",
        scenario.config.name,
        args.mc_seed,
        clock.elapsed().as_secs_f64()
    );
    println!(
        "  {:<10} {:>22} {:>22} {:>8}",
        "filter", "profile @ true alt [%]", "at estimate [%]", "failed"
    );
    for r in &reports {
        println!(
            "  {:<10} {:>22.4} {:>22.4} {:>8}",
            r.filter, r.rmspe_profile_pct, r.rmspe_state_pct, r.failed
        );
    }
    if let Some(dir) = &args.plots {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        for r in &reports {
            let path = dir.join(format!(
                "{}_{}_density_error_runs.svg",
                scenario.config.name, r.filter
            ));
            fig10(&path, &scenario.config.name, r)?;
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}

/// Seed 001 Fig. 10 (the render crate's [`density_error_figure`]) written to `path`.
fn fig10(
    path: &std::path::Path,
    scenario: &str,
    r: &entrynav::sim::density::density_eval::DensityEvalReport,
) -> Result<()> {
    let svg = entrynav_render::density_figure::density_error_figure(scenario, r)?;
    Ok(entrynav_studies::output::atomic_file::write(path, svg)?)
}

fn report(file: &NetworkFile) {
    for (k, n) in file.networks.iter().enumerate() {
        let t = &n.training;
        let [p50, p99, max] = t.validation_rel_err_p50_p99_max;
        println!(
            "network {k} ({}-{} km, exponential rho_ref {:.4e} kg/m3 at {:.3} km, H {:.4} km): {} train / {} validation samples",
            n.altitude_band_km[0],
            n.altitude_band_km[1],
            n.trained_on_exponential[0],
            n.trained_on_exponential[1],
            n.trained_on_exponential[2],
            t.train_samples,
            t.validation_samples
        );
        println!(
            "  MSE train {:.3e} validation {:.3e}; validation |rel. density error| median {:.3}%, p99 {:.3}%, max {:.3}%, {:.1}% below 1%; {:.1} s",
            t.train_mse,
            t.validation_mse,
            100.0 * p50,
            100.0 * p99,
            100.0 * max,
            100.0 * t.validation_frac_below_1pct,
            t.wall_time_s
        );
    }
}
