//! The site selection on a candidate grid (`entrynav optimize select`): the certified choice of k
//! candidate sites (Joshi & Boyd relaxation bound with clarabel, then local search; with `exact`
//! the branch and bound of [`select_exact`](crate::design::select_exact)), or with `objective`
//! the local search on the nominal bound ([`select_bound`](crate::design::select_bound)); every
//! answer checked against the input design.

use crate::design::check::check_configs;
use crate::design::failure::study_error;
use crate::design::select_bound::select_on_bound;
use crate::design::select_candidates::{Candidates, load_candidates};
use crate::design::select_exact::{exact_only, run_exact, selected_scenario};
use crate::design::select_options::SelectOptions;
use crate::design::select_result::{Certified, SelectionAnswer, SiteSelection};
use crate::error::StudyResult;
use crate::progress::Progress;
use crate::scenario::ScenarioInput;
use crate::threads::with_threads;
use entrynav_optimizer::select::{separation_constraints, site_information};
use entrynav_optimizer::{GroundObjective, GroundProblem, Selection, SelectionCriterion};
use entrynav_optimizer::{SelectionProblem, Site};
use std::time::Instant;

/// Choose the sites of `input`'s scenario.
pub fn run_site_selection(
    input: &ScenarioInput,
    options: &SelectOptions,
    progress: Progress<'_>,
) -> StudyResult<SiteSelection> {
    options.validate()?;
    options.validate_steps(input.config.timing.duration_s)?;
    with_threads(options.threads, || {
        let wall = Instant::now();
        let mut s = match options.objective {
            Some(objective) => select_on_bound(input, options, objective)?,
            None => select_certified(input, options, progress)?,
        };
        s.threads = rayon::current_num_threads();
        s.wall_s = wall.elapsed().as_secs_f64();
        Ok(s)
    })
}

/// The information blocks of the candidates and the spacing constraints (with the number of
/// close pairs).
fn selection_problem(
    o: &SelectOptions,
    ground: &GroundProblem,
    sites: &[Site],
) -> StudyResult<(SelectionProblem, usize)> {
    let blocks = site_information(ground, sites, o.eig_epochs).map_err(study_error)?;
    let spacing = if o.min_separation_deg > 0.0 {
        separation_constraints(sites, o.min_separation_deg.to_radians()).map_err(study_error)?
    } else {
        Vec::new()
    };
    let pairs = spacing.len();
    let problem = SelectionProblem::new(blocks, o.k, SelectionCriterion::from(o.criterion))
        .map(|p| p.with_solver_verbose(o.solver_verbose))
        .and_then(|p| p.with_constraints(spacing))
        .map_err(study_error)?;
    Ok((problem, pairs))
}

/// The relaxation and its heuristics, the enumeration (within `brute_force_limit`), the proof
/// (`exact`, from the heuristic answer), the answers to certify and the check; the branch and
/// bound alone when the heuristic fails with `exact`.
fn select_certified(
    input: &ScenarioInput,
    o: &SelectOptions,
    progress: Progress<'_>,
) -> StudyResult<SiteSelection> {
    let cfg = &input.config;
    let load = entrynav_loader::file_loader(&input.dir);
    let ground = GroundProblem::new(
        cfg,
        &load,
        o.k.max(1),
        GroundObjective::LogDet,
        o.step,
        o.min_elevation_deg.to_radians(),
    )
    .map_err(study_error)?;
    let mut notes = Vec::new();
    let candidates = load_candidates(o, cfg, &ground, &mut notes)?;
    let (problem, close_pairs) = selection_problem(o, &ground, &candidates.sites)?;
    // The heuristic; with `exact` the branch and bound can go on without it.
    let report = match problem.solve() {
        Ok(r) => r,
        Err(e) if o.exact => {
            notes.push(format!(
                "the heuristic failed ({}); branch and bound starts without it",
                study_error(e)
            ));
            return exact_only(input, o, problem, (candidates, notes), progress);
        }
        Err(e) => return Err(study_error(e)),
    };
    let brute = problem.brute_force(o.brute_force_limit);
    let exact = match o.exact {
        true => Some(run_exact(o, &problem, Some(&report.improved), progress)?),
        false => None,
    };
    let certified = certified(&problem, &candidates);
    let c = Certified {
        problem,
        close_pairs,
        report,
        brute,
        exact,
        certified,
    };
    let (design, design_toml) = selected_scenario(
        o,
        cfg,
        &candidates.sites,
        &c.problem,
        (c.answer(), c.bound(), c.exact.as_ref()),
    )?;
    let criterion = c.problem.criterion().name();
    let check = check_configs(cfg, &design, &input.dir, criterion, o.check())?;
    Ok(SiteSelection {
        options: o.clone(),
        scenario: cfg.name.clone(),
        notes,
        candidates,
        answer: SelectionAnswer::Certified(Box::new(c)),
        design,
        design_toml,
        check,
        threads: 1,
        wall_s: 0.0,
    })
}

/// The value of each answer to certify, labelled.
fn certified(problem: &SelectionProblem, candidates: &Candidates) -> Vec<(String, Selection)> {
    candidates
        .extra
        .iter()
        .map(|(label, idx)| {
            let s = Selection {
                indices: idx.clone(),
                value: problem.value(idx),
            };
            (label.clone(), s)
        })
        .collect()
}
