//! `entrynav observe`: degree of observability δ(t) along a scenario's trajectory (seed 000 §2.4,
//! seed 002 §3) and the range Fisher information of its beacons (seed 002 §3.2, eq. 54).

use anyhow::{Context, Result, bail};
use clap::Args;
use entrynav::observability::fisher::max_det_bound;
use entrynav::observability::{
    AnalysisPoint, ChannelSet, DegreeSeries, FimEpoch, Method, Scaling, analysis_points,
    degree_series, max_det_directions, range_fim_series,
};
use entrynav::scenario::Scenario;
use entrynav_loader as load;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `entrynav observe`.
#[derive(Args)]
pub struct ObserveArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    pub scenario: String,
    /// How the observability matrix is computed: `lie` (exact Lie derivatives, seed 002 eq. 12),
    /// `quadratic` (the quadratic approximation, eq. 13-17) or `linear` (the linearisation,
    /// eq. 19).
    #[arg(long, default_value = "lie")]
    pub method: Method,
    /// Also analyse each IMU + one-beacon subsystem (seed 000 eq. 9, Fig. 3).
    #[arg(long)]
    pub subsystems: bool,
    /// Seconds between analysis points along the nominal truth trajectory.
    #[arg(long, default_value_t = 1.0)]
    pub step: f64,
    /// Print the range Fisher information at every point: det, trace, the bounds of seed 002
    /// eq. 27-28 and 37-41, and the geometry index I (eq. 54).
    #[arg(long)]
    pub fim: bool,
    /// With --fim: use only the scenario's first N range beacons, and compare with the best
    /// geometry of N free beacons (seed 002 Table 1, (N/3)^3).
    #[arg(long, value_name = "N")]
    pub beacons: Option<usize>,
    /// Also compute the posterior Cramér–Rao lower bound (the best RMSE any estimator can reach
    /// on the scenario's truth) over `--runs` truth runs, without a filter.
    #[arg(long)]
    pub pcrlb: bool,
    /// With --pcrlb: number of Monte Carlo truth runs the bound averages over.
    #[arg(long, default_value_t = 100)]
    pub runs: usize,
    /// With --pcrlb: master seed of the truth runs (the runs a `trade` with this seed flies).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Write the results as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write an SVG plot of δ(t) (log axis; and I(t) with --fim) to this file.
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

const RAW_NOTE: &str = "raw SI: delta = sigma_min/sigma_max of O with states in m, rad, m/s, kg/m^3 and outputs in their SI units (the papers' convention)";

/// Run the command.
pub fn run(args: &ObserveArgs) -> Result<()> {
    let method = args.method;
    let (cfg, dir) = load::resolve(&args.scenario, load::Base::CurrentDir)?.into_parts();
    let scenario = load::build(cfg, &dir)?;
    let points = analysis_points(&scenario, args.step)?;
    let scaling = Scaling::characteristic(scenario.filter_model());

    let started = Instant::now();
    let central = degree_series(
        &scenario,
        &points,
        &ChannelSet::centralised(&scenario),
        method,
        &scaling,
    )?;
    let central_elapsed = started.elapsed().as_secs_f64();
    let mut subsystems = Vec::new();
    if args.subsystems {
        let sets = ChannelSet::subsystems(&scenario);
        if sets.is_empty() {
            bail!(
                "scenario '{}' has no beacon channels: --subsystems needs range or range-rate \
                 beacons (each subsystem is the IMU plus one beacon)",
                scenario.config.name
            );
        }
        for set in &sets {
            let t0 = Instant::now();
            let s = degree_series(&scenario, &points, set, method, &scaling)?;
            subsystems.push((s, t0.elapsed().as_secs_f64()));
        }
    }
    let fim = if args.fim {
        let subset = match args.beacons {
            Some(n) => Some(first_range_beacons(&scenario, n)?),
            None => None,
        };
        Some(range_fim_series(&scenario, &points, subset.as_deref())?)
    } else {
        None
    };

    print_report(&scenario, &points, &scaling, &central, &subsystems, args);
    if let Some(f) = &fim {
        print_fim(f, args.beacons);
    }
    let pcrlb = if args.pcrlb {
        Some(crate::observe_pcrlb::run(&scenario, args.runs, args.seed)?)
    } else {
        None
    };
    if let Some(path) = &args.json {
        let mut v = to_json(
            &scenario,
            &scaling,
            &central,
            central_elapsed,
            &subsystems,
            fim.as_deref(),
        );
        if let Some(b) = &pcrlb {
            v["pcrlb"] = serde_json::to_value(b)?;
            v["pcrlb_runs"] = json!(args.runs);
            v["pcrlb_seed"] = json!(args.seed);
        }
        create_parent(path)?;
        std::fs::write(path, serde_json::to_string_pretty(&v)? + "\n")
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        create_parent(path)?;
        let subs: Vec<&DegreeSeries> = subsystems.iter().map(|(s, _)| s).collect();
        plot(path, &scenario, &central, &subs, fim.as_deref())?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Indices of the first `n` beacons that have a range channel.
fn first_range_beacons(scenario: &Scenario, n: usize) -> Result<Vec<usize>> {
    let mut ranged: Vec<usize> = scenario
        .channels
        .iter()
        .filter_map(|c| match c.channel {
            entrynav::sensors::Channel::Range(b) => Some(b),
            _ => None,
        })
        .collect();
    ranged.dedup();
    if n == 0 || n > ranged.len() {
        bail!(
            "--beacons {n}: scenario '{}' has {} range beacon(s)",
            scenario.config.name,
            ranged.len()
        );
    }
    ranged.truncate(n);
    Ok(ranged)
}

fn create_parent(path: &Path) -> Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    Ok(())
}

fn summary_line(s: &DegreeSeries) -> String {
    let f = |scaled: bool| match s.summary(scaled) {
        Some(m) => format!(
            "{:>10.3e} @{:>6.1} s {:>10.3e} @{:>6.1} s",
            m.min, m.t_min_s, m.max, m.t_max_s
        ),
        None => "(no points)".into(),
    };
    let ranks = |scaled: bool| {
        let r = s
            .samples
            .iter()
            .map(|x| if scaled { x.scaled.rank } else { x.raw.rank });
        let (lo, hi) = r.fold((usize::MAX, 0), |a, v| (a.0.min(v), a.1.max(v)));
        format!("{lo}..{hi}")
    };
    format!(
        "{:<24} {}  {:>6} | {}  {:>6}",
        s.name,
        f(false),
        ranks(false),
        f(true),
        ranks(true)
    )
}

fn print_report(
    scenario: &Scenario,
    points: &[AnalysisPoint],
    scaling: &Scaling,
    central: &DegreeSeries,
    subsystems: &[(DegreeSeries, f64)],
    args: &ObserveArgs,
) {
    let n = scaling.state.len();
    let last = points.last().map_or(0.0, |p| p.t);
    println!("scenario   {}", scenario.config.name);
    println!("states     {n}: {}", scaling.state_names.join(", "));
    println!(
        "method     {} (observability matrix rows: Lie orders 0..{})",
        central.method.name(),
        n - 1
    );
    println!(
        "points     {} (every {} s, t = 0 .. {last} s)",
        points.len(),
        args.step
    );
    println!("RAW        {RAW_NOTE}");
    println!("SCALED     {}", scaling_note(scaling));
    println!("           delta = 0 means numerically rank-deficient (rank < {n}): unobservable");
    println!();
    println!(
        "{:<24} {:<38}  {:>6} | {:<38}  {:>6}",
        "system", "RAW SI delta: min @t, max @t", "rank", "SCALED delta: min @t, max @t", "rank"
    );
    println!("{}", summary_line(central));
    for (s, _) in subsystems {
        println!("{}", summary_line(s));
    }
}

fn scaling_note(scaling: &Scaling) -> String {
    let sizes: Vec<String> = scaling
        .state_names
        .iter()
        .zip(&scaling.state)
        .map(|(n, s)| format!("{n} {s:e}"))
        .collect();
    format!(
        "delta of W*O*D: states divided by characteristic sizes [{}], each row divided by its \
         channel's noise 1-sigma, Lie order k rows times ({} s)^k (dimensionless)",
        sizes.join(", "),
        scaling.time_s
    )
}

fn print_fim(fim: &[FimEpoch], beacons: Option<usize>) {
    println!();
    println!(
        "Range Fisher information of the vehicle position (seed 002 eq. 36; unit vectors beacon->vehicle)"
    );
    println!(
        "  det F [m^-6], tr F [m^-2]; 3/trF (eq. 28) and trF^-1 (eq. 27) are lower bounds on tr P [m^2];"
    );
    println!("  det<= is eq. 38, detmax is eq. 40 for this many beacons; I is eq. 54");
    println!(
        "{:>7} {:>3} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11} {:>8}",
        "t [s]", "N", "det F", "tr F", "3/trF", "trF^-1", "det<=", "detmax", "I"
    );
    for e in fim {
        let s = &e.summary;
        let inv = s
            .trace_inverse
            .map_or_else(|| "singular".to_string(), |v| format!("{v:.4e}"));
        println!(
            "{:>7.1} {:>3} {:>11.4e} {:>11.4e} {:>11.4e} {:>11} {:>11.4e} {:>11.4e} {:>8.5}",
            e.t,
            s.count,
            s.det,
            s.trace,
            s.trace_lower_bound,
            inv,
            s.det_upper_bound,
            s.det_max,
            e.geometry_index
        );
    }
    let n = beacons.unwrap_or_else(|| fim.iter().map(|e| e.summary.count).max().unwrap_or(0));
    if n >= 3 {
        let best = max_det_directions(n, 8, 1);
        println!(
            "best geometry of {n} free beacons (seed 002 Table 1): max det(sum n n^T) = {:.6} \
             (projected gradient ascent) vs (N/3)^3 = {:.6}; I = det(sum n n^T) for unit sigma, \
             so I <= (N/3)^3",
            best.det,
            max_det_bound(n)
        );
    }
}

fn series_json(s: &DegreeSeries, elapsed_s: f64) -> Value {
    let stat = |scaled: bool| s.summary(scaled);
    let (raw, sc) = (stat(false), stat(true));
    json!({
        "name": s.name,
        "method": s.method.name(),
        "times_s": s.times(),
        "delta": s.deltas(false),
        "delta_min": raw.map(|m| m.min),
        "delta_max": raw.map(|m| m.max),
        "t_delta_min_s": raw.map(|m| m.t_min_s),
        "t_delta_max_s": raw.map(|m| m.t_max_s),
        "rank": s.samples.iter().map(|x| x.raw.rank).collect::<Vec<_>>(),
        "delta_scaled": s.deltas(true),
        "delta_scaled_min": sc.map(|m| m.min),
        "delta_scaled_max": sc.map(|m| m.max),
        "t_delta_scaled_min_s": sc.map(|m| m.t_min_s),
        "t_delta_scaled_max_s": sc.map(|m| m.t_max_s),
        "rank_scaled": s.samples.iter().map(|x| x.scaled.rank).collect::<Vec<_>>(),
        "outputs": s.samples.iter().map(|x| x.outputs).collect::<Vec<_>>(),
        "elapsed_s": elapsed_s,
    })
}

fn to_json(
    scenario: &Scenario,
    scaling: &Scaling,
    central: &DegreeSeries,
    elapsed_s: f64,
    subsystems: &[(DegreeSeries, f64)],
    fim: Option<&[FimEpoch]>,
) -> Value {
    let mut v = series_json(central, elapsed_s);
    let o = v.as_object_mut().expect("series_json builds an object");
    o.insert("scenario".into(), json!(scenario.config.name));
    o.insert("delta_units".into(), json!(RAW_NOTE));
    o.insert(
        "scaling".into(),
        json!({
            "description": scaling_note(scaling),
            "state_names": scaling.state_names,
            "state_scale": scaling.state,
            "time_s": scaling.time_s,
            "rows": "divided by the channel's noise 1-sigma (relative noise: at the analysis point)",
        }),
    );
    o.insert(
        "subsystems".into(),
        Value::Array(subsystems.iter().map(|(s, e)| series_json(s, *e)).collect()),
    );
    if let Some(f) = fim {
        let col = |g: &dyn Fn(&FimEpoch) -> Value| Value::Array(f.iter().map(g).collect());
        o.insert("fim_times_s".into(), col(&|e| json!(e.t)));
        o.insert(
            "fim_beacons".into(),
            col(&|e| {
                json!(
                    e.beacons
                        .iter()
                        .map(|&b| scenario.beacon_names[b].clone())
                        .collect::<Vec<_>>()
                )
            }),
        );
        o.insert("fim_det".into(), col(&|e| json!(e.summary.det)));
        o.insert("fim_trace".into(), col(&|e| json!(e.summary.trace)));
        o.insert(
            "fim_eigenvalues".into(),
            col(&|e| json!(e.summary.eigenvalues)),
        );
        o.insert(
            "fim_trace_inverse".into(),
            col(&|e| json!(e.summary.trace_inverse)),
        );
        o.insert(
            "fim_trace_lower_bound".into(),
            col(&|e| {
                json!(
                    e.summary
                        .trace_lower_bound
                        .is_finite()
                        .then_some(e.summary.trace_lower_bound)
                )
            }),
        );
        o.insert(
            "fim_det_upper_bound".into(),
            col(&|e| json!(e.summary.det_upper_bound)),
        );
        o.insert("fim_det_max".into(), col(&|e| json!(e.summary.det_max)));
        o.insert("geometry_index".into(), col(&|e| json!(e.geometry_index)));
    }
    v
}

fn plot(
    path: &Path,
    scenario: &Scenario,
    central: &DegreeSeries,
    subsystems: &[&DegreeSeries],
    fim: Option<&[FimEpoch]>,
) -> Result<()> {
    use plotters::prelude::*;
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("plot {}: {e}", path.display());
    let panels = if fim.is_some() { 3 } else { 2 };
    let root = SVGBackend::new(path, (1000, 380 * panels)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let areas = root.split_evenly((panels as usize, 1));
    let t_end = central.samples.last().map_or(1.0, |s| s.t).max(1e-9);
    let mut series: Vec<&DegreeSeries> = vec![central];
    series.extend_from_slice(subsystems);
    for (area, scaled) in areas.iter().zip([false, true]) {
        let pts: Vec<Vec<(f64, f64)>> = series
            .iter()
            .map(|s| {
                s.times()
                    .into_iter()
                    .zip(s.deltas(scaled))
                    .filter(|(_, d)| *d > 0.0 && d.is_finite())
                    .collect()
            })
            .collect();
        let all = pts.iter().flatten().map(|p| p.1);
        let (lo, hi) = all.fold((f64::INFINITY, 0.0_f64), |a, d| (a.0.min(d), a.1.max(d)));
        let (lo, hi) = if lo.is_finite() {
            (lo / 2.0, hi * 2.0)
        } else {
            (1e-20, 1.0)
        };
        // At least two decades, so that the log axis gets labelled ticks.
        let (lo, hi) = if hi / lo < 100.0 {
            let c = (lo * hi).sqrt();
            (c / 10.0, c * 10.0)
        } else {
            (lo, hi)
        };
        let label = if scaled { "scaled δ" } else { "raw SI δ" };
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!(
                    "{}: {label} = σmin/σmax ({}; δ = 0 not drawn)",
                    scenario.config.name,
                    central.method.name()
                ),
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..t_end, (lo..hi).log_scale())
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc("t [s]")
            .y_desc(label)
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| err(&e))?;
        for (i, (s, p)) in series.iter().zip(pts).enumerate() {
            let color = Palette99::pick(i).to_rgba();
            let name = if p.is_empty() {
                format!("{} (δ = 0 throughout: rank-deficient)", s.name)
            } else {
                s.name.clone()
            };
            chart
                .draw_series(LineSeries::new(p, color.stroke_width(2)))
                .map_err(|e| err(&e))?
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| err(&e))?;
    }
    if let Some(f) = fim {
        let top = f.iter().map(|e| e.geometry_index).fold(0.0_f64, f64::max);
        let mut chart = ChartBuilder::on(&areas[2])
            .caption(
                "geometry index I = Σ [n_i·(n_j × n_k)]² (seed 002 eq. 54)",
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..t_end, 0.0..(top * 1.1).max(1e-12))
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc("t [s]")
            .y_desc("I")
            .draw()
            .map_err(|e| err(&e))?;
        chart
            .draw_series(LineSeries::new(
                f.iter().map(|e| (e.t, e.geometry_index)),
                BLUE.stroke_width(2),
            ))
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
