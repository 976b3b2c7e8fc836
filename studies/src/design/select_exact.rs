//! The branch and bound of the site selection (`exact`,
//! `entrynav_optimizer::select::branch_bound`) with its progress (incumbent, bound, open nodes),
//! the run without a heuristic start, and the answer written as a scenario.

use crate::design::failure::study_error;
use crate::design::select_candidates::Candidates;
use crate::design::select_options::SelectOptions;
use crate::design::select_result::{ExactOnly, SelectionAnswer, SiteSelection};
use crate::design::sites::chosen;
use crate::error::StudyResult;
use crate::progress::{Progress, Step};
use crate::scenario::ScenarioInput;
use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::output::{self, template_noise};
use entrynav_optimizer::select::{BranchBoundOptions, BranchBoundProgress};
use entrynav_optimizer::{BranchBoundReport, Selection, SelectionProblem, Site};
use std::time::Duration;

/// Run the branch and bound from `start` (the heuristic answer, if any), reporting each batch as
/// a step of unit `nodes` whose task is the progress line.
pub fn run_exact(
    o: &SelectOptions,
    problem: &SelectionProblem,
    start: Option<&Selection>,
    progress: Progress<'_>,
) -> StudyResult<BranchBoundReport> {
    let opts = BranchBoundOptions {
        gap: o.gap,
        time_limit: o.time_limit.map(Duration::from_secs_f64),
        node_limit: o.node_limit,
        batch: o.batch,
        ..BranchBoundOptions::default()
    };
    let report = |p: &BranchBoundProgress| {
        let task = format!(
            "branch and bound: {} nodes, {} open, incumbent {:.6}, bound {:.6}, gap {:.2e}",
            p.nodes,
            p.open,
            p.incumbent,
            p.bound,
            p.bound - p.incumbent
        );
        progress(Step {
            unit: "nodes",
            task: &task,
            done: p.nodes as u64,
            total: 0,
            best: Some(p.incumbent),
        });
    };
    problem
        .branch_and_bound(&opts, start, &report)
        .map_err(study_error)
}

/// `exact` when the heuristic failed: the branch and bound alone, the enumeration and the
/// answer as a scenario (no check).
pub fn exact_only(
    input: &ScenarioInput,
    o: &SelectOptions,
    problem: SelectionProblem,
    (candidates, notes): (Candidates, Vec<String>),
    progress: Progress<'_>,
) -> StudyResult<SiteSelection> {
    let exact = run_exact(o, &problem, None, progress)?;
    let brute = problem.brute_force(o.brute_force_limit);
    let (design, design_toml) = selected_scenario(
        o,
        &input.config,
        &candidates.sites,
        &problem,
        (&exact.best, exact.bound, Some(&exact)),
    )?;
    Ok(SiteSelection {
        options: o.clone(),
        scenario: input.config.name.clone(),
        notes,
        candidates,
        answer: SelectionAnswer::ExactOnly(ExactOnly {
            problem,
            brute,
            exact,
        }),
        design,
        design_toml,
        check: None,
        threads: 1,
        wall_s: 0.0,
    })
}

/// The scenario with the answer's sites as its beacons (configuration and file text), its note
/// giving the value, the certified gap from `bound` and the proof's status.
pub fn selected_scenario(
    o: &SelectOptions,
    cfg: &ScenarioConfig,
    sites: &[Site],
    problem: &SelectionProblem,
    (answer, bound, exact): (&Selection, f64, Option<&BranchBoundReport>),
) -> StudyResult<(ScenarioConfig, String)> {
    let noise = template_noise(cfg, false).map_err(study_error)?;
    let note = format!(
        "Sites chosen by `entrynav optimize select` ({}, k = {}, grid {} deg{}): value {:.6}, \
         certified gap {:.3e}.",
        problem.criterion().name(),
        o.k,
        o.grid_deg,
        exact.map_or(String::new(), |e| format!(
            ", branch and bound: {}",
            e.status.name()
        )),
        answer.value,
        (bound - answer.value).max(0.0)
    );
    let stem = o.scenario_name.as_deref().unwrap_or("selected");
    let beacons = output::surface_beacons(&chosen(sites, &answer.indices), &noise);
    output::with_beacons(cfg, beacons, stem, &note).map_err(study_error)
}
