//! `objective = lincov-avg | lincov-final | lincov-nav` of the ground and orbiter designs: the
//! nominal bound's optimum of the same figure, polished on the position RMSE that LinCov predicts
//! for the filter (`lincov_filter`, default ekf), with the input design scored the same way.

use crate::design::failure::study_error;
use crate::design::progress::evaluations;
use crate::error::{StudyError, StudyResult};
use crate::progress::Progress;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav_optimizer::ground::default_lincov_polish;
use entrynav_optimizer::output::{BeaconNoise, orbiter_beacons};
use entrynav_optimizer::{
    GroundProblem, GroundSolution, LinCovFigure, LinCovFigures, LinCovScore, OrbitElements,
    OrbiterNavProblem, OrbiterNavSolution, SearchOptions, Site,
};
use serde_json::{Value, json};

/// The LinCov polish of an optimum.
#[derive(Debug, Clone)]
pub struct LinCovStage {
    /// The figure polished on.
    pub figure: LinCovFigure,
    /// The filter whose LinCov scores the designs.
    pub filter: FilterKind,
    /// The input design's figures, when it has beacons to score.
    pub input: Option<LinCovFigures>,
    /// At the bound optimum the polish started from.
    pub start: LinCovFigures,
    /// At the polished design.
    pub end: LinCovFigures,
    /// The objective's value at the polished design.
    pub value: f64,
    /// LinCov evaluations of the polish.
    pub evaluations: usize,
    /// Its wall time \[s\].
    pub elapsed_s: f64,
    /// The polish's settings.
    pub opts: SearchOptions,
}

/// The label of the polish's progress.
fn label(filter: FilterKind) -> String {
    format!("LinCov polish ({})", filter.name())
}

/// Polish `sol` (the bound search's optimum on `problem`) on LinCov of `filter_name`, the input
/// design being `own` with elevation mask `own_mask_rad`; returns the polished solution (its
/// evaluation is the bound problem's) and the stage.
pub fn polish_ground(
    problem: &GroundProblem,
    sol: GroundSolution,
    (figure, filter_name): (LinCovFigure, &str),
    (own, own_mask_rad): (&[Site], f64),
    seed: u64,
    progress: Progress<'_>,
) -> StudyResult<(GroundSolution, LinCovStage)> {
    let filter = FilterKind::parse(filter_name).map_err(study_error)?;
    let mut score = LinCovScore::new(problem.scenario(), filter, figure).map_err(study_error)?;
    let input = if own.is_empty() {
        if figure == LinCovFigure::Navigation {
            return Err(StudyError::Refused(format!(
                "--objective lincov-nav is relative to the scenario's own surface beacons and \
                 '{}' has none; use lincov-avg or lincov-final",
                problem.scenario().config.name
            )));
        }
        None
    } else {
        score = score
            .with_reference(problem.beacons_masked(own, own_mask_rad))
            .map_err(study_error)?;
        score.reference()
    };
    let opts = default_lincov_polish(seed);
    let task = label(filter);
    let p = problem
        .polish_on_lincov(&score, &sol, &opts, &evaluations(progress, &task))
        .map_err(study_error)?;
    let evaluation = problem.evaluate(&p.sites).map_err(study_error)?;
    let stage = LinCovStage {
        figure,
        filter,
        input,
        start: p.start_figures,
        end: p.figures,
        value: p.value,
        evaluations: p.search.evaluations,
        elapsed_s: p.elapsed_s,
        opts,
    };
    let polished = GroundSolution {
        sites: p.sites,
        evaluation,
        search: sol.search,
        elapsed_s: sol.elapsed_s + p.elapsed_s,
    };
    Ok((polished, stage))
}

/// Polish `sol` (the bound search's optimum on `problem`, whose working scenario is `working`)
/// on LinCov of `filter_name`; `own` is the scenario's own constellation when comparable
/// (needed by lincov-nav). The solution's elements, value and series become the polished
/// constellation's (value and series: the bound's).
pub fn polish_orbiters(
    (problem, working): (&OrbiterNavProblem, &Scenario),
    sol: &mut OrbiterNavSolution,
    (figure, filter_name): (LinCovFigure, &str),
    own: Option<&[OrbitElements]>,
    (noise, seed): (&BeaconNoise, u64),
    progress: Progress<'_>,
) -> StudyResult<LinCovStage> {
    let filter = FilterKind::parse(filter_name).map_err(study_error)?;
    let mut score = LinCovScore::new(working, filter, figure).map_err(study_error)?;
    let altitude = problem.geometry().altitude_m();
    let input = match own {
        Some(el) => {
            score = score
                .with_reference(orbiter_beacons(el, altitude, noise))
                .map_err(study_error)?;
            score.reference()
        }
        None if figure == LinCovFigure::Navigation => {
            return Err(StudyError::Refused(format!(
                "--objective lincov-nav is relative to the scenario's own orbiters at the same \
                 altitude and count, which '{}' does not have; use lincov-avg or lincov-final",
                working.config.name
            )));
        }
        None => None,
    };
    let opts = default_lincov_polish(seed);
    let task = label(filter);
    let p = problem
        .polish_on_lincov(
            &score,
            &sol.elements,
            noise,
            &opts,
            &evaluations(progress, &task),
        )
        .map_err(study_error)?;
    sol.value = problem.value(&p.elements).map_err(study_error)?;
    sol.series = problem.series(&p.elements).map_err(study_error)?;
    sol.elements = p.elements;
    sol.elapsed_s += p.elapsed_s;
    Ok(LinCovStage {
        figure,
        filter,
        input,
        start: p.start_figures,
        end: p.figures,
        value: p.value,
        evaluations: p.search.evaluations,
        elapsed_s: p.elapsed_s,
        opts,
    })
}

/// A design's LinCov figures in the JSON.
pub fn figures_json(x: &LinCovFigures) -> Value {
    json!({
        "time_avg_pos_m": x.avg_m,
        "final_pos_m": x.final_m,
        "nees_dof": x.nees_ratio,
    })
}

impl LinCovStage {
    /// The objective's name (`lincov-*`).
    pub fn name(&self) -> &'static str {
        self.figure.name()
    }

    /// Under `lincov` in the JSON.
    pub fn json(&self) -> Value {
        json!({
            "objective": self.figure.name(),
            "units": self.figure.units(self.filter),
            "filter": self.filter.name(),
            "value": self.value,
            "input": self.input.as_ref().map(figures_json),
            "bound_optimum": figures_json(&self.start),
            "optimum": figures_json(&self.end),
            "evaluations": self.evaluations,
            "elapsed_s": self.elapsed_s,
            "polish_iterations": self.opts.polish_iterations,
            "polish_step": self.opts.polish_step,
        })
    }
}
