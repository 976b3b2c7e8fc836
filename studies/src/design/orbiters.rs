//! The orbiter design (`entrynav optimize orbiters`): orbiter elements (Ω, i, f) on circular
//! orbits (seed 002 §4.2) — the geometric objectives (eq. 57, ln det FIM), the PCRLB polish
//! (`pcrlb`), the nominal position bound (`nav`, `pcrlb-avg`, `pcrlb-final`) and its LinCov polish
//! (`lincov-*`) — checked against the scenario's own orbiters by a Monte Carlo.

use crate::design::check::check_configs;
use crate::design::choices::OrbiterObjectiveName;
use crate::design::failure::study_error;
use crate::design::lincov_stage::polish_orbiters;
use crate::design::orbiters_options::OrbiterOptions;
use crate::design::orbiters_result::{NavAnswer, OrbiterDesign};
use crate::design::progress::evaluations;
use crate::design::sites::scenario_orbits;
use crate::error::{StudyError, StudyResult};
use crate::progress::{Progress, Step};
use crate::scenario::ScenarioInput;
use crate::threads::with_threads;
use entrynav::beacons::BeaconConfig;
use entrynav_optimizer::orbiters::default_search;
use entrynav_optimizer::orbiters_bound::{OrbiterBoundProblem, default_bound_polish};
use entrynav_optimizer::output::{self, BeaconNoise, template_noise};
use entrynav_optimizer::{
    BoundFigure, OrbitElements, OrbiterNavProblem, OrbiterProblem, OrbiterSolution, SearchOptions,
    Trajectory,
};
use std::time::Instant;

/// Design the orbiters of `input`'s scenario.
pub fn run_orbiter_design(
    input: &ScenarioInput,
    options: &OrbiterOptions,
    progress: Progress<'_>,
) -> StudyResult<OrbiterDesign> {
    options.validate()?;
    options.validate_steps(input.config.timing.duration_s)?;
    with_threads(options.threads, || {
        let wall = Instant::now();
        let mut d = solve(input, options, progress)?;
        (d.design, d.design_toml) = d.written_scenario(&input.config)?;
        d.check = check_configs(
            &input.config,
            &d.design,
            &input.dir,
            d.objective_name(),
            options.check(),
        )?;
        d.wall_s = wall.elapsed().as_secs_f64();
        Ok(d)
    })
}

/// A scenario's own circular orbiters: (altitude \[m\], elements).
type OwnOrbits = Vec<(f64, OrbitElements)>;

/// What the search starts from and works with.
struct Setup<'a> {
    input: &'a ScenarioInput,
    o: &'a OrbiterOptions,
    /// The scenario's own orbiters: (altitude \[m\], elements).
    own: OwnOrbits,
    count: usize,
    altitude_m: f64,
    /// The scenario's own orbiters are as many, at the same altitude.
    comparable: bool,
    noise: BeaconNoise,
    opts: SearchOptions,
    progress: Progress<'a>,
    task: String,
}

/// The scenario's own circular orbiters, the orbiter count (default: the scenario's, at least
/// 3) and the altitude \[m\] (default: the scenario's first circular orbiter).
fn constellation(
    input: &ScenarioInput,
    o: &OrbiterOptions,
) -> StudyResult<(OwnOrbits, usize, f64)> {
    let cfg = &input.config;
    let own = scenario_orbits(cfg);
    let count = o.orbiters.unwrap_or_else(|| {
        cfg.beacons
            .iter()
            .filter(|b| matches!(b, BeaconConfig::Orbiter(_)))
            .count()
            .max(3)
    });
    let altitude_m = match (o.altitude_km, own.first()) {
        (Some(km), _) => km * 1e3,
        (None, Some((alt, _))) => *alt,
        (None, None) => {
            return Err(StudyError::Refused(format!(
                "scenario '{}' has no circular orbiter to take the altitude from; give \
                 --altitude-km",
                cfg.name
            )));
        }
    };
    Ok((own, count, altitude_m))
}

/// The global search on the geometric objective, the PCRLB polish (`pcrlb`) or the search on the
/// nominal bound, and the evaluation of the scenario's own orbiters.
fn solve(
    input: &ScenarioInput,
    o: &OrbiterOptions,
    progress: Progress<'_>,
) -> StudyResult<OrbiterDesign> {
    let cfg = &input.config;
    let (own, count, altitude_m) = constellation(input, o)?;
    let scenario = input.build()?;
    let trajectory = Trajectory::from_scenario(&scenario, o.step).map_err(study_error)?;
    let geometric = o.objective.and_then(OrbiterObjectiveName::geometric);
    let problem =
        OrbiterProblem::new(trajectory, count, altitude_m, geometric).map_err(study_error)?;
    let comparable =
        own.len() == count && own.iter().all(|(alt, _)| (alt - altitude_m).abs() < 1e-6);
    let s = Setup {
        input,
        o,
        own,
        count,
        altitude_m,
        comparable,
        opts: o.search().resolve(default_search(o.seed)),
        noise: template_noise(cfg, true).map_err(study_error)?,
        progress,
        task: format!("{} orbiters", cfg.name),
    };
    progress(Step::of(
        "evaluations",
        &s.task,
        0,
        s.opts.budget(3 * s.count) as u64,
    ));
    let report = evaluations(progress, &s.task);
    let bound_problem = (o.objective == Some(OrbiterObjectiveName::Pcrlb))
        .then(|| OrbiterBoundProblem::new(problem.clone(), cfg.clone(), s.noise));
    let bound = bound_problem
        .as_ref()
        .map(|b| b.optimize(&s.opts, &default_bound_polish(o.seed), &report))
        .transpose()
        .map_err(study_error)?;
    let own_elements: Vec<OrbitElements> = s.own.iter().map(|(_, e)| *e).collect();
    // Default: `nav` against the scenario's own orbiters, or `pcrlb-avg` without comparable ones.
    let chosen = o.objective.unwrap_or(if s.comparable {
        OrbiterObjectiveName::Nav
    } else {
        OrbiterObjectiveName::PcrlbAvg
    });
    let nav = match chosen.bound_figure() {
        Some(figure) => Some(nav_search(&s, &problem, chosen, figure, &own_elements)?),
        None => None,
    };
    let sol = match (&bound, &nav) {
        (Some(b), _) => b.proxy.clone(),
        (None, Some(n)) => OrbiterSolution {
            elements: n.solution.elements.clone(),
            evaluation: problem
                .evaluate(&n.solution.elements)
                .map_err(study_error)?,
            search: n.solution.search.clone(),
            elapsed_s: n.solution.elapsed_s,
        },
        (None, None) => problem.optimize(&s.opts, &report).map_err(study_error)?,
    };
    let reference = match s.comparable {
        true => {
            let ev = problem.evaluate(&own_elements).map_err(study_error)?;
            Some((own_elements.clone(), ev))
        }
        false => None,
    };
    let own_bound = match (&bound_problem, &reference) {
        (Some(bp), Some((el, _))) => Some(bp.final_position_bound(el).map_err(study_error)?),
        _ => None,
    };
    Ok(OrbiterDesign {
        options: o.clone(),
        scenario: cfg.name.clone(),
        count: s.count,
        altitude_m: s.altitude_m,
        problem,
        opts: s.opts,
        noise: s.noise,
        sol,
        bound,
        own_bound,
        reference,
        nav,
        design: cfg.clone(),
        design_toml: String::new(),
        check: None,
        wall_s: 0.0,
    })
}

/// The full global search on the nominal position bound of `figure` (and its LinCov polish for
/// lincov-*), with the (time-averaged, final) bound of the scenario's own orbiters.
fn nav_search(
    s: &Setup<'_>,
    problem: &OrbiterProblem,
    chosen: OrbiterObjectiveName,
    figure: BoundFigure,
    own_elements: &[OrbitElements],
) -> StudyResult<NavAnswer> {
    let cfg = &s.input.config;
    // The working scenario: the base with `count` orbiters at the altitude (their places do not
    // matter: the bound's set-up reads only the truth and the epochs).
    let mut working = cfg.clone();
    let placeholder: Vec<OrbitElements> = (0..s.count)
        .map(|k| OrbitElements::from_degrees(120.0 * k as f64, 45.0, 0.0))
        .collect();
    working.beacons = output::orbiter_beacons(&placeholder, s.altitude_m, &s.noise);
    let working = entrynav_loader::build(working, &s.input.dir)?;
    let p = OrbiterNavProblem::new(problem.clone(), &working, s.noise.range_sigma_m, figure)
        .map_err(study_error)?;
    let p = if s.comparable || figure == BoundFigure::Navigation {
        if !s.comparable {
            return Err(StudyError::Refused(format!(
                "--objective nav is relative to the scenario's own {} orbiters at {} km, which \
                 '{}' does not have; use pcrlb-avg or pcrlb-final",
                s.count,
                s.altitude_m / 1e3,
                cfg.name
            )));
        }
        p.with_reference(own_elements).map_err(study_error)?
    } else {
        p
    };
    let mut solution = p
        .optimize(&s.opts, &evaluations(s.progress, &s.task))
        .map_err(study_error)?;
    let lincov = match chosen.lincov_figure() {
        Some(lf) => Some(polish_orbiters(
            (&p, &working),
            &mut solution,
            (lf, &s.o.lincov_filter),
            s.comparable.then_some(own_elements),
            (&s.noise, s.o.seed),
            s.progress,
        )?),
        None => None,
    };
    let own = match s.comparable {
        true => {
            let b = p.series(own_elements).map_err(study_error)?;
            Some((b.time_avg(), b.final_value()))
        }
        false => None,
    };
    Ok(NavAnswer {
        objective: figure.name(),
        solution,
        lincov,
        own,
    })
}
