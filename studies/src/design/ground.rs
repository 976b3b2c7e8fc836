//! The ground-site design (`entrynav optimize ground`): surface-beacon sites visible during the
//! whole entry (seed 002 §4.1), by default those that minimise the nominal position bound
//! relative to the input design, at least `min_separation_deg` apart, and checked against the
//! input by a Monte Carlo.

use crate::design::check::check_configs;
use crate::design::failure::study_error;
use crate::design::ground_options::GroundOptions;
use crate::design::ground_result::GroundDesign;
use crate::design::lincov_stage::polish_ground;
use crate::design::progress::evaluations;
use crate::design::sites::{scenario_mask_deg, scenario_sites};
use crate::error::StudyResult;
use crate::progress::Progress;
use crate::scenario::ScenarioInput;
use crate::threads::with_threads;
use entrynav::beacons::BeaconConfig;
use entrynav::observability::Method;
use entrynav_optimizer::ground::default_search;
use entrynav_optimizer::output;
use entrynav_optimizer::{GroundProblem, Site};
use std::time::Instant;

/// Design the ground sites of `input`'s scenario.
pub fn run_ground_design(
    input: &ScenarioInput,
    options: &GroundOptions,
    progress: Progress<'_>,
) -> StudyResult<GroundDesign> {
    options.validate()?;
    options.validate_steps(input.config.timing.duration_s)?;
    with_threads(options.threads, || design(input, options, progress))
}

/// The problem at trajectory step `step` (the search's or the report's).
fn problem(
    input: &ScenarioInput,
    o: &GroundOptions,
    count: usize,
    step: f64,
) -> StudyResult<GroundProblem> {
    let cfg = &input.config;
    let load = entrynav_loader::file_loader(&input.dir);
    let objective = o.objective.search(Method::from(o.method), o.scaled);
    let p = GroundProblem::new(
        cfg,
        &load,
        count,
        objective,
        step,
        o.min_elevation_deg.to_radians(),
    )
    .and_then(|p| p.with_min_separation(o.min_separation_deg.to_radians()))
    .and_then(|p| p.with_elevation_mask(o.elevation_mask_deg.to_radians()))
    .map_err(study_error)?;
    let p = if o.partial_visibility {
        p.with_partial_visibility()
    } else {
        p
    };
    if !objective.is_bound() {
        return Ok(p);
    }
    let own = scenario_sites(cfg);
    p.with_reference(&own, scenario_mask_deg(cfg).to_radians())
        .map_err(study_error)
}

/// The search at `search_step`, the LinCov polish (lincov-*), then the objective and δ(t) of the
/// optimum and of the scenario's own sites (same count only) at `step`, and the check.
fn design(
    input: &ScenarioInput,
    o: &GroundOptions,
    progress: Progress<'_>,
) -> StudyResult<GroundDesign> {
    let wall = Instant::now();
    let cfg = &input.config;
    let own = scenario_sites(cfg);
    let own_mask_deg = scenario_mask_deg(cfg);
    let count = o
        .beacons
        .unwrap_or(if own.is_empty() { 3 } else { own.len() });
    let method = Method::from(o.method);
    let objective = o.objective.search(method, o.scaled);
    let objective_name = o
        .objective
        .lincov_figure()
        .map_or(objective.name(), |f| f.name());
    let search_problem = problem(input, o, count, o.search_step)?;
    let report = problem(input, o, count, o.step)?;
    let opts = o.search().resolve(default_search(o.seed));
    let task = format!("{} ground x{count}", cfg.name);
    let sol = search_problem
        .optimize(&opts, &evaluations(progress, &task))
        .map_err(study_error)?;
    let (solution, lincov) = match o.objective.lincov_figure() {
        Some(figure) => {
            let (s, stage) = polish_ground(
                &search_problem,
                sol,
                (figure, &o.lincov_filter),
                (&own, own_mask_deg.to_radians()),
                o.seed,
                progress,
            )?;
            (s, Some(stage))
        }
        None => (sol, None),
    };
    let evaluation = report.evaluate(&solution.sites).map_err(study_error)?;
    let delta = report
        .delta_series(&solution.sites, method)
        .map_err(study_error)?;
    let reference = if own.len() == count {
        let r = report.evaluate(&own).map_err(study_error)?;
        let d = report.delta_series(&own, method).map_err(study_error)?;
        Some((r, d))
    } else {
        None
    };
    // The nominal bound of both designs, whatever the objective (cheap; None where the scenario
    // has no such bound, e.g. range rate).
    let bound = |s: &[Site], mask_deg: f64| {
        report
            .bound_series_masked(s, f64::to_radians(mask_deg))
            .ok()
            .map(|b| (b.time_avg(), b.final_value()))
    };
    let bounds = bound(&solution.sites, o.elevation_mask_deg)
        .zip(bound(&own, own_mask_deg))
        .map(|(a, b)| [a, b]);
    let (design, design_toml) = written(
        input,
        o,
        &report,
        &solution.sites,
        (objective_name, evaluation.value),
    )?;
    let check = check_configs(cfg, &design, &input.dir, objective_name, o.check())?;
    Ok(GroundDesign {
        options: o.clone(),
        scenario: cfg.name.clone(),
        count,
        objective,
        objective_name,
        method,
        own,
        own_mask_deg,
        whole_entry: report.whole_entry(),
        min_elevation_rad: report.min_elevation(),
        scaling: scaling_note(&report),
        opts,
        solution,
        evaluation,
        delta,
        reference,
        bounds,
        design,
        design_toml,
        check,
        lincov,
        wall_s: wall.elapsed().as_secs_f64(),
    })
}

/// The optimum as a scenario: its sites (with the placed sites' mask) as the beacons.
fn written(
    input: &ScenarioInput,
    o: &GroundOptions,
    report: &GroundProblem,
    sites: &[Site],
    (objective_name, value): (&str, Option<f64>),
) -> StudyResult<(entrynav::scenario::ScenarioConfig, String)> {
    let mut beacons = output::surface_beacons(sites, &report.noise());
    for b in &mut beacons {
        if let BeaconConfig::Surface(c) = b {
            c.elevation_mask_deg = (o.elevation_mask_deg > 0.0).then_some(o.elevation_mask_deg);
        }
    }
    output::with_beacons(
        &input.config,
        beacons,
        o.scenario_name.as_deref().unwrap_or("optimized"),
        &format!(
            "Ground sites optimized by `entrynav optimize ground` ({objective_name}, seed {}, sites \
             at least {} deg apart): value {}.",
            o.seed,
            o.min_separation_deg,
            fmt_value(value)
        ),
    )
    .map_err(study_error)
}

/// An objective value, or `infeasible`.
pub fn fmt_value(v: Option<f64>) -> String {
    v.map_or("infeasible".to_string(), |v| format!("{v:.6e}"))
}

/// What the scaled δ is scaled by.
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
