//! `entrynav optimize ground`: surface-beacon sites visible during the whole entry (seed 002 §4.1),
//! by default those that minimise the nominal position bound relative to the input design, at
//! least `--min-separation-deg` apart, and checked against the input by a Monte Carlo.
//!
//! Order: search, check, write every file asked for, then print (so a closed standard output
//! never costs a file), and exit code 1 when the check finds the optimum worse.

use super::design_check::{DesignCheck, check_configs, print_check, verdict};
use super::lincov_polish::{self, LinCovStage};
use super::*;
use entrynav_optimizer::{GroundSolution, LinCovFigure};

/// The scenario's surface beacons as sites (lat/lon/altitude or planet-fixed position).
pub(super) fn scenario_sites(cfg: &ScenarioConfig) -> Vec<Site> {
    let radius = cfg.planet.resolve().radius;
    cfg.beacons
        .iter()
        .filter_map(|b| match b {
            BeaconConfig::Surface(s) => match (s.lat_deg, s.lon_deg, s.position_km) {
                (Some(lat), Some(lon), _) => Some(Site {
                    altitude_m: s.altitude_km.unwrap_or(0.0) * 1e3,
                    ..Site::from_degrees(lat, lon)
                }),
                (_, _, Some(p)) => {
                    let p = p.map(|c| c * 1e3);
                    let (r, lon, lat) = entrynav::frames::position_to_spherical(&p);
                    Some(Site {
                        lat,
                        lon,
                        altitude_m: r - radius,
                    })
                }
                _ => None,
            },
            BeaconConfig::Orbiter(_) => None,
        })
        .collect()
}

pub(super) fn sites_json(sites: &[Site]) -> Value {
    Value::Array(
        sites
            .iter()
            .map(|s| {
                let [lat, lon] = s.degrees();
                json!({"lat_deg": lat, "lon_deg": lon})
            })
            .collect(),
    )
}

pub(super) fn print_sites(sites: &[Site], elevation: Option<&[f64]>) {
    println!(
        "  {:<6} {:>11} {:>11} {:>22}",
        "site", "lat [deg]", "lon [deg]", "min elevation [deg]"
    );
    for (k, s) in sites.iter().enumerate() {
        let [lat, lon] = s.degrees();
        let e = elevation
            .and_then(|e| e.get(k))
            .map_or(String::new(), |e| format!("{:.4}", e.to_degrees()));
        println!("  {:<6} {lat:>11.4} {lon:>11.4} {e:>22}", k + 1);
    }
}

struct DeltaStats {
    raw: DegreeSeries,
}

impl DeltaStats {
    fn min(&self, scaled: bool) -> f64 {
        self.raw.summary(scaled).map_or(0.0, |s| s.min)
    }
    fn max(&self, scaled: bool) -> f64 {
        self.raw.summary(scaled).map_or(0.0, |s| s.max)
    }
    fn json(&self) -> Value {
        let r = self.raw.summary(false);
        let s = self.raw.summary(true);
        json!({
            "method": self.raw.method.name(),
            "delta_raw_min": r.map(|m| m.min),
            "delta_raw_max": r.map(|m| m.max),
            "t_delta_raw_min_s": r.map(|m| m.t_min_s),
            "delta_scaled_min": s.map(|m| m.min),
            "delta_scaled_max": s.map(|m| m.max),
            "times_s": self.raw.times(),
            "delta_raw": self.raw.deltas(false),
            "delta_scaled": self.raw.deltas(true),
        })
    }
}

/// What `optimize ground` starts from: the scenario, its own surface sites and the objective.
struct GroundInputs {
    cfg: ScenarioConfig,
    dir: PathBuf,
    /// The scenario's surface beacons as sites.
    own: Vec<Site>,
    /// Their elevation mask \[deg\] (the first surface beacon's; 0: the horizon).
    own_mask_deg: f64,
    count: usize,
    method: Method,
    /// The search's objective (for lincov-*, the bound of the same figure).
    objective: GroundObjective,
    /// lincov-*: the figure the bound's optimum is polished on.
    lincov: Option<LinCovFigure>,
}

impl GroundInputs {
    /// The objective the user chose.
    fn objective_name(&self) -> &'static str {
        self.lincov
            .map_or(self.objective.name(), LinCovFigure::name)
    }
}

/// The search's answer re-evaluated at the reporting step, and the scenario's own sites.
struct GroundAnswer {
    /// The problem at the reporting step (`--step`).
    report: GroundProblem,
    opts: SearchOptions,
    sol: GroundSolution,
    /// The optimum's objective at the reporting step.
    ev: GroundEvaluation,
    delta: DeltaStats,
    /// The scenario's own sites, when there are as many.
    reference: Option<(GroundEvaluation, DeltaStats)>,
    /// Nominal position bound (time-averaged, final) \[m\] of the optimum and of the input's
    /// own sites (any count).
    bounds: Option<[(f64, f64); 2]>,
    /// The optimum as a scenario (configuration and file text).
    written: (ScenarioConfig, String),
    /// The Monte Carlo check against the input design (`None` with `--no-check`).
    check: Option<DesignCheck>,
    /// lincov-*: the polish on LinCov.
    lincov: Option<LinCovStage>,
}

pub(super) fn run_ground(a: &GroundArgs) -> Result<()> {
    let wall = Instant::now();
    let inputs = load_ground_inputs(a)?;
    let mut answer = solve_ground(a, &inputs)?;
    answer.check = check_configs(
        &inputs.cfg,
        &answer.written.0,
        &inputs.dir,
        inputs.objective_name(),
        &a.check,
    )?;
    // Files first, each attempted; then the tables and what was written.
    let notes = [
        write_ground_scenario(a, &answer),
        plot_ground(a, &inputs, &answer),
        write_ground_json(a, &inputs, &answer, wall),
    ];
    print_ground(a, &inputs, &answer, wall);
    let mut failures = Vec::new();
    for n in notes {
        match n {
            Ok(Some(note)) => println!("{note}"),
            Ok(None) => {}
            Err(e) => failures.push(format!("{e:#}")),
        }
    }
    if !failures.is_empty() {
        return Err(crate::exit::Runtime(failures.join("; also: ")).into());
    }
    verdict(answer.check.as_ref())
}

/// The scenario with its overrides, the beacon count (default: the scenario's surface beacons,
/// or 3) and the objective.
fn load_ground_inputs(a: &GroundArgs) -> Result<GroundInputs> {
    let c = &a.common;
    let (cfg, dir) = load::resolve(&c.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &c.sets)?;
    crate::exit::warn_implausible(&cfg);
    let own = scenario_sites(&cfg);
    let count = a
        .beacons
        .unwrap_or(if own.is_empty() { 3 } else { own.len() });
    let method = Method::from(a.method);
    let objective = match a.objective {
        GroundObjectiveArg::MinDelta => GroundObjective::MinDelta {
            method,
            scaled: a.scaled,
        },
        GroundObjectiveArg::Logdet => GroundObjective::LogDet,
        GroundObjectiveArg::MinEig => GroundObjective::MinEig,
        GroundObjectiveArg::PcrlbAvg => GroundObjective::PcrlbAvg,
        GroundObjectiveArg::PcrlbFinal => GroundObjective::PcrlbFinal,
        GroundObjectiveArg::Nav | GroundObjectiveArg::LincovNav => GroundObjective::Navigation,
        GroundObjectiveArg::LincovAvg => GroundObjective::PcrlbAvg,
        GroundObjectiveArg::LincovFinal => GroundObjective::PcrlbFinal,
    };
    let lincov = match a.objective {
        GroundObjectiveArg::LincovAvg => Some(LinCovFigure::Average),
        GroundObjectiveArg::LincovFinal => Some(LinCovFigure::Final),
        GroundObjectiveArg::LincovNav => Some(LinCovFigure::Navigation),
        _ => None,
    };
    let own_mask_deg = cfg
        .beacons
        .iter()
        .find_map(|b| match b {
            BeaconConfig::Surface(c) => Some(c.elevation_mask_deg.unwrap_or(0.0)),
            BeaconConfig::Orbiter(_) => None,
        })
        .unwrap_or(0.0);
    Ok(GroundInputs {
        cfg,
        dir,
        own,
        own_mask_deg,
        count,
        method,
        objective,
        lincov,
    })
}

/// The search at `--search-step`, then the objective and δ(t) of the optimum and of the
/// scenario's own sites (same count only) at `--step`.
fn solve_ground(a: &GroundArgs, inputs: &GroundInputs) -> Result<GroundAnswer> {
    let c = &a.common;
    let (cfg, count, objective) = (&inputs.cfg, inputs.count, inputs.objective);
    let load = loader(&inputs.dir);
    let whole_entry = !a.partial_visibility;
    let min_el = a.min_elevation_deg.to_radians();
    let sep = a.min_separation_deg.to_radians();
    let mask = a.elevation_mask_deg.to_radians();
    let setup = |step: f64| -> Result<GroundProblem> {
        let p = GroundProblem::new(cfg, &load, count, objective, step, min_el)?
            .with_min_separation(sep)?
            .with_elevation_mask(mask)?;
        let p = if whole_entry {
            p
        } else {
            p.with_partial_visibility()
        };
        Ok(if objective.is_bound() {
            p.with_reference(&inputs.own, inputs.own_mask_deg.to_radians())?
        } else {
            p
        })
    };
    let search_problem = setup(a.search_step)?;
    let report = setup(a.step)?;
    let opts = c.search(ground::default_search(c.seed));
    let bar = progress_bar(c.quiet, format!("{} ground x{count}", cfg.name));
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let sol = search_problem.optimize(&opts, &progress)?;
    bar.finish_and_clear();
    let (sol, lincov) = match inputs.lincov {
        Some(figure) => {
            let (s, stage) = lincov_polish::polish_ground(
                &search_problem,
                sol,
                figure,
                &a.lincov_filter,
                &inputs.own,
                inputs.own_mask_deg.to_radians(),
                c.seed,
                c.quiet,
            )?;
            (s, Some(stage))
        }
        None => (sol, None),
    };
    let ev = report.evaluate(&sol.sites)?;
    let delta = DeltaStats {
        raw: report.delta_series(&sol.sites, inputs.method)?,
    };
    let reference = if inputs.own.len() == count {
        let r_ev = report.evaluate(&inputs.own)?;
        let d = DeltaStats {
            raw: report.delta_series(&inputs.own, inputs.method)?,
        };
        Some((r_ev, d))
    } else {
        None
    };
    // The nominal bound of both designs, whatever the objective (cheap; None where the scenario
    // has no such bound, e.g. range rate).
    let bounds = (|| -> Option<[(f64, f64); 2]> {
        let pair = |s: &[Site], mask_deg: f64| {
            report
                .bound_series_masked(s, mask_deg.to_radians())
                .ok()
                .map(|b| (b.time_avg(), b.final_value()))
        };
        Some([
            pair(&sol.sites, a.elevation_mask_deg)?,
            pair(&inputs.own, inputs.own_mask_deg)?,
        ])
    })();
    let mut beacons = output::surface_beacons(&sol.sites, &report.noise());
    for b in &mut beacons {
        if let BeaconConfig::Surface(c) = b {
            c.elevation_mask_deg = (a.elevation_mask_deg > 0.0).then_some(a.elevation_mask_deg);
        }
    }
    let written = output::with_beacons(
        &inputs.cfg,
        beacons,
        &file_stem(
            c.write_scenario
                .as_deref()
                .unwrap_or(Path::new("optimized")),
        ),
        &format!(
            "Ground sites optimized by `entrynav optimize ground` ({}, seed {}, sites at least \
             {} deg apart): value {}.",
            inputs.objective_name(),
            opts.seed,
            a.min_separation_deg,
            fmt_value(ev.value)
        ),
    )?;
    Ok(GroundAnswer {
        report,
        opts,
        sol,
        ev,
        delta,
        reference,
        bounds,
        written,
        check: None,
        lincov,
    })
}

/// An objective value, or `infeasible`.
fn fmt_value(v: Option<f64>) -> String {
    v.map_or("infeasible".to_string(), |v| format!("{v:.6e}"))
}

/// The δ line of a geometry: raw SI and scaled minimum and maximum.
fn print_delta(method: Method, d: &DeltaStats) {
    println!(
        "  delta ({}) raw SI: min {:.4e}, max {:.4e};  scaled: min {:.4e}, max {:.4e}",
        method.name(),
        d.min(false),
        d.max(false),
        d.min(true),
        d.max(true)
    );
}

/// The problem, the optimum, the scenario's own sites, the paper's range, units and search.
fn print_ground(a: &GroundArgs, inputs: &GroundInputs, answer: &GroundAnswer, wall: Instant) {
    let (cfg, objective) = (&inputs.cfg, inputs.objective);
    let paper = cfg.name == "ground-beacons-3";
    println!("scenario    {}", cfg.name);
    let visibility = if answer.report.whole_entry() {
        format!(
            "each visible during the whole entry (eq. 52, min elevation {:.3} deg)",
            answer.report.min_elevation().to_degrees()
        )
    } else {
        "each seeing part of the entry".to_string()
    };
    println!(
        "problem     {} ground beacons on the reference sphere, {visibility}, at least {} deg \
         apart, measuring above a {} deg elevation mask (input's sites: {} deg)",
        inputs.count, a.min_separation_deg, a.elevation_mask_deg, inputs.own_mask_deg
    );
    println!("objective   {}: {}", objective.name(), objective.units());
    println!(
        "            search on samples every {} s, reported every {} s",
        a.search_step, a.step
    );
    println!();
    println!(
        "optimum     {} = {}",
        objective.name(),
        fmt_value(answer.ev.value)
    );
    print_sites(&answer.sol.sites, Some(&answer.ev.min_elevation_rad));
    print_delta(inputs.method, &answer.delta);
    if let Some(b) = &answer.bounds {
        print_bound("optimum", b[0]);
        print_bound("input  ", b[1]);
    }
    if let Some((r, d)) = &answer.reference {
        println!();
        println!(
            "scenario's own sites{}: {} = {}",
            if paper {
                " (hand-placed like seed 002 Fig. 4)"
            } else {
                ""
            },
            objective.name(),
            fmt_value(r.value)
        );
        print_sites(&inputs.own, Some(&r.min_elevation_rad));
        print_delta(inputs.method, d);
    }
    if paper {
        println!();
        println!(
            "paper (seed 002 Sec. 5.1, its optimum): delta from 1.413e-8 to 2.945e-7 along the \
             entry (raw SI)"
        );
    }
    println!();
    println!(
        "units       raw SI delta: states r [m], lon, lat [rad], v [m/s], fpa, heading [rad], \
         outputs [m], Lie order k rows in m/s^k; scaled: {}",
        scaling_note(&answer.report)
    );
    if let Some(l) = &answer.lincov {
        l.print();
    }
    print_search(&answer.sol.search, answer.sol.elapsed_s, wall, &answer.opts);
    print_check(answer.check.as_ref());
}

/// The nominal position bound line of a design.
fn print_bound(label: &str, (avg, last): (f64, f64)) {
    println!("  nominal position PCRLB, {label}: {avg:.2} m time-averaged, {last:.2} m final");
}

/// `--write-scenario`: the scenario with the optimum's sites.
fn write_ground_scenario(a: &GroundArgs, answer: &GroundAnswer) -> Result<Option<String>> {
    let Some(path) = &a.common.write_scenario else {
        return Ok(None);
    };
    write_text(path, &answer.written.1)?;
    Ok(Some(format!("wrote {}", path.display())))
}

/// `--plot`: raw δ(t) of the optimum and of the scenario's sites.
fn plot_ground(
    a: &GroundArgs,
    inputs: &GroundInputs,
    answer: &GroundAnswer,
) -> Result<Option<String>> {
    let Some(path) = &a.plot else {
        return Ok(None);
    };
    let pts = |d: &DegreeSeries| -> Vec<(f64, f64)> {
        d.times().into_iter().zip(d.deltas(false)).collect()
    };
    let mut curves = vec![entrynav_render::chart::Curve {
        name: format!("optimum (min {:.3e})", answer.delta.min(false)),
        points: pts(&answer.delta.raw),
        dashed: false,
    }];
    if let Some((_, d)) = &answer.reference {
        curves.push(entrynav_render::chart::Curve {
            name: format!("scenario's sites (min {:.3e})", d.min(false)),
            points: pts(&d.raw),
            dashed: true,
        });
    }
    write_text(path, "")?;
    crate::figures::write_line_plot(
        path,
        &format!(
            "{}: raw SI δ = σmin/σmax ({}) along the entry",
            inputs.cfg.name,
            inputs.method.name()
        ),
        "time (s)",
        "δ (raw SI)",
        true,
        &curves,
    )?;
    Ok(Some(format!("wrote {}", path.display())))
}

/// `--json`: the optimum, its δ(t), the search and the scenario's own sites.
fn write_ground_json(
    a: &GroundArgs,
    inputs: &GroundInputs,
    answer: &GroundAnswer,
    wall: Instant,
) -> Result<Option<String>> {
    let Some(path) = &a.common.json else {
        return Ok(None);
    };
    let (cfg, objective, ev) = (&inputs.cfg, inputs.objective, &answer.ev);
    let degrees = |e: &[f64]| e.iter().map(|e| e.to_degrees()).collect::<Vec<_>>();
    let v = json!({
        "problem": "ground",
        "scenario": cfg.name,
        "objective": inputs.objective_name(),
        "objective_units": objective.units(),
        "search_objective": objective.name(),
        "lincov": answer.lincov.as_ref().map(LinCovStage::json),
        "value": ev.value,
        "beacons": inputs.count,
        "sites": sites_json(&answer.sol.sites),
        "min_elevation_deg": degrees(&ev.min_elevation_rad),
        "delta": answer.delta.json(),
        "evaluations": answer.sol.search.evaluations,
        "elapsed_s": answer.sol.elapsed_s,
        "wall_s": wall.elapsed().as_secs_f64(),
        "search": search_json(&answer.sol.search, &answer.opts),
        "search_step_s": a.search_step,
        "report_step_s": a.step,
        "delta_units": "raw SI: sigma_min/sigma_max of O with states in m, rad, m/s and outputs in m; scaled: see scaling",
        "scaling": scaling_note(&answer.report),
        "reference": answer.reference.as_ref().map(|(r, d)| json!({
            "source": format!("scenario {} surface beacons", cfg.name),
            "sites": sites_json(&inputs.own),
            "value": r.value,
            "min_elevation_deg": degrees(&r.min_elevation_rad),
            "delta": d.json(),
        })),
        "paper_delta_range": (cfg.name == "ground-beacons-3").then(|| json!([1.413e-8, 2.945e-7])),
        "min_separation_deg": a.min_separation_deg,
        "whole_entry_visibility": answer.report.whole_entry(),
        "elevation_mask_deg": a.elevation_mask_deg,
        "input_elevation_mask_deg": inputs.own_mask_deg,
        "closest_pair_deg": ev.closest_pair_rad.map(f64::to_degrees),
        "nominal_bound": answer.bounds.map(|b| json!({
            "optimum": {"time_avg_pos_m": b[0].0, "final_pos_m": b[0].1},
            "input": {"time_avg_pos_m": b[1].0, "final_pos_m": b[1].1},
        })),
        "check": answer.check.as_ref().map(DesignCheck::json),
    });
    write_text(path, &(serde_json::to_string_pretty(&v)? + "\n"))?;
    Ok(Some(format!("wrote {}", path.display())))
}

fn scaling_note(p: &GroundProblem) -> String {
    let s = p.scaling();
    let sizes: Vec<String> = s
        .state_names
        .iter()
        .zip(&s.state)
        .map(|(n, v)| format!("{n} {v:e}"))
        .collect();
    format!(
        "delta of W*O*D with characteristic sizes [{}], rows divided by the range noise 1-sigma, \
         Lie order k rows times ({} s)^k",
        sizes.join(", "),
        s.time_s
    )
}
