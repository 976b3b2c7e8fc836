//! `optimize ground|orbiters --objective lincov-avg|lincov-final|lincov-nav`: the nominal
//! bound's optimum of the same figure, polished on the position RMSE that LinCov predicts for
//! the filter (`--lincov-filter`, default the check's filter, ekf), with the input design scored
//! the same way.

use super::progress_bar;
use anyhow::{Result, bail};
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
pub(super) struct LinCovStage {
    figure: LinCovFigure,
    filter: FilterKind,
    /// The input design's figures (its own surface sites and mask), when it has sites.
    input: Option<LinCovFigures>,
    /// At the bound optimum the polish started from.
    start: LinCovFigures,
    /// At the polished sites.
    end: LinCovFigures,
    value: f64,
    evaluations: usize,
    elapsed_s: f64,
    opts: SearchOptions,
}

/// Polish `sol` (the bound search's optimum on `problem`) on LinCov of `filter_name`; returns the
/// polished solution (its evaluation is the bound problem's) and the stage.
#[allow(clippy::too_many_arguments)]
pub(super) fn polish_ground(
    problem: &GroundProblem,
    sol: GroundSolution,
    figure: LinCovFigure,
    filter_name: &str,
    own: &[Site],
    own_mask_rad: f64,
    seed: u64,
    quiet: bool,
) -> Result<(GroundSolution, LinCovStage)> {
    let filter = FilterKind::parse(filter_name)?;
    let mut score = LinCovScore::new(problem.scenario(), filter, figure)?;
    let input = if own.is_empty() {
        if figure == LinCovFigure::Navigation {
            bail!(
                "--objective lincov-nav is relative to the scenario's own surface beacons and \
                 '{}' has none; use lincov-avg or lincov-final",
                problem.scenario().config.name
            );
        }
        None
    } else {
        score = score.with_reference(problem.beacons_masked(own, own_mask_rad))?;
        score.reference()
    };
    let opts = default_lincov_polish(seed);
    let bar = progress_bar(quiet, format!("LinCov polish ({})", filter.name()));
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let p = problem.polish_on_lincov(&score, &sol, &opts, &progress)?;
    bar.finish_and_clear();
    let evaluation = problem.evaluate(&p.sites)?;
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
#[allow(clippy::too_many_arguments)]
pub(super) fn polish_orbiters(
    problem: &OrbiterNavProblem,
    working: &Scenario,
    sol: &mut OrbiterNavSolution,
    figure: LinCovFigure,
    filter_name: &str,
    own: Option<&[OrbitElements]>,
    noise: &BeaconNoise,
    seed: u64,
    quiet: bool,
) -> Result<LinCovStage> {
    let filter = FilterKind::parse(filter_name)?;
    let mut score = LinCovScore::new(working, filter, figure)?;
    let altitude = problem.geometry().altitude_m();
    let input = match own {
        Some(el) => {
            score = score.with_reference(orbiter_beacons(el, altitude, noise))?;
            score.reference()
        }
        None if figure == LinCovFigure::Navigation => bail!(
            "--objective lincov-nav is relative to the scenario's own orbiters at the same \
             altitude and count, which '{}' does not have; use lincov-avg or lincov-final",
            working.config.name
        ),
        None => None,
    };
    let opts = default_lincov_polish(seed);
    let bar = progress_bar(quiet, format!("LinCov polish ({})", filter.name()));
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let p = problem.polish_on_lincov(&score, &sol.elements, noise, &opts, &progress)?;
    bar.finish_and_clear();
    sol.value = problem.value(&p.elements)?;
    sol.series = problem.series(&p.elements)?;
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

impl LinCovStage {
    /// The objective's name (`lincov-*`).
    pub(super) fn name(&self) -> &'static str {
        self.figure.name()
    }

    /// The lines `optimize ground` prints.
    pub(super) fn print(&self) {
        let f = |x: &LinCovFigures| {
            format!(
                "{:.2} m time-averaged, {:.2} m final, NEES/dof {:.2}",
                x.avg_m, x.final_m, x.nees_ratio
            )
        };
        println!();
        println!(
            "lincov      {} = {:.6e}: {}",
            self.figure.name(),
            self.value,
            self.figure.units(self.filter)
        );
        if let Some(i) = &self.input {
            println!(
                "  predicted {} position RMSE, input:         {}",
                self.filter.name(),
                f(i)
            );
        }
        println!(
            "  predicted {} position RMSE, bound optimum: {}",
            self.filter.name(),
            f(&self.start)
        );
        println!(
            "  predicted {} position RMSE, polished:      {}",
            self.filter.name(),
            f(&self.end)
        );
        println!(
            "  polish: {} LinCov evaluations in {:.1} s (Nelder-Mead from the bound's optimum, \
             {} iterations per round, simplex {} of the box)",
            self.evaluations, self.elapsed_s, self.opts.polish_iterations, self.opts.polish_step
        );
    }

    /// Under `lincov` in the JSON.
    pub(super) fn json(&self) -> Value {
        let f = |x: &LinCovFigures| {
            json!({
                "time_avg_pos_m": x.avg_m,
                "final_pos_m": x.final_m,
                "nees_dof": x.nees_ratio,
            })
        };
        json!({
            "objective": self.figure.name(),
            "units": self.figure.units(self.filter),
            "filter": self.filter.name(),
            "value": self.value,
            "input": self.input.as_ref().map(f),
            "bound_optimum": f(&self.start),
            "optimum": f(&self.end),
            "evaluations": self.evaluations,
            "elapsed_s": self.elapsed_s,
            "polish_iterations": self.opts.polish_iterations,
            "polish_step": self.opts.polish_step,
        })
    }
}
