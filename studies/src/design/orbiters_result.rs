//! What the orbiter design returns: the optimum (geometric, PCRLB-polished or on the nominal
//! bound), the scenario's own orbiters evaluated the same way, the optimum as a scenario, the
//! check against the input, the trajectory CSV and the JSON `entrynav optimize orbiters --json`
//! writes.

use crate::design::check::{DesignCheck, verdict};
use crate::design::failure::study_error;
use crate::design::lincov_stage::LinCovStage;
use crate::design::orbiters_options::OrbiterOptions;
use crate::design::search::search_json;
use crate::design::sites::elements_json;
use crate::error::StudyResult;
use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::orbiters::{LOG_DET_FLOOR, OrbiterEvaluation};
use entrynav_optimizer::output::{self, BeaconNoise};
use entrynav_optimizer::{
    OrbitElements, OrbiterBoundSolution, OrbiterNavSolution, OrbiterObjective, OrbiterProblem,
    OrbiterSolution, SearchOptions,
};
use serde_json::{Value, json};

/// The value seed 002 Table 6 reports for its orbiters on orbiters-3.
pub const PAPER_VALUE: f64 = 237.963;

/// The search on the nominal position bound.
#[derive(Debug, Clone)]
pub struct NavAnswer {
    /// Objective name (`nav`, `pcrlb-avg`, `pcrlb-final`).
    pub objective: &'static str,
    /// The optimum on the bound (after the LinCov polish, if any).
    pub solution: OrbiterNavSolution,
    /// lincov-*: the polish of the bound's optimum on LinCov.
    pub lincov: Option<LinCovStage>,
    /// The (time-averaged, final) bound of the scenario's own orbiters, when comparable.
    pub own: Option<(f64, f64)>,
}

/// An orbiter design.
#[derive(Debug, Clone)]
pub struct OrbiterDesign {
    /// The options it ran with.
    pub options: OrbiterOptions,
    /// The scenario's name.
    pub scenario: String,
    /// Number of orbiters.
    pub count: usize,
    /// Their altitude \[m\].
    pub altitude_m: f64,
    /// The geometric problem (trajectory, objective, upper bound).
    pub problem: OrbiterProblem,
    /// The search's settings.
    pub opts: SearchOptions,
    /// The range noise of the orbiters written.
    pub noise: BeaconNoise,
    /// The geometric optimum (with `pcrlb`, the proxy the polish started from).
    pub sol: OrbiterSolution,
    /// `pcrlb`: the polish on the final position PCRLB.
    pub bound: Option<OrbiterBoundSolution>,
    /// `pcrlb`: the bound of the scenario's own orbiters, when comparable.
    pub own_bound: Option<f64>,
    /// The scenario's own orbiters (the paper's Table 6 for orbiters-3), when comparable.
    pub reference: Option<(Vec<OrbitElements>, OrbiterEvaluation)>,
    /// `nav | pcrlb-avg | pcrlb-final | lincov-*`: the search on the nominal bound.
    pub nav: Option<NavAnswer>,
    /// The optimum as a scenario configuration.
    pub design: ScenarioConfig,
    /// Its file text (what `--write-scenario` writes).
    pub design_toml: String,
    /// The check against the input design (`None`: skipped).
    pub check: Option<DesignCheck>,
    /// Wall time of the study \[s\].
    pub wall_s: f64,
}

impl OrbiterDesign {
    /// The elements written to the scenario file: the PCRLB polish's, else the optimum's.
    pub fn best_elements(&self) -> &[OrbitElements] {
        self.bound
            .as_ref()
            .map_or(&self.sol.elements, |b| &b.elements)
    }

    /// The objective that produced the design.
    pub fn objective_name(&self) -> &'static str {
        match (&self.bound, &self.nav) {
            (Some(_), _) => "pcrlb",
            (None, Some(n)) => n.lincov.as_ref().map_or(n.objective, LinCovStage::name),
            (None, None) => self.problem.objective().name(),
        }
    }

    /// What the geometric objective integrates over time, in words and by its short name.
    pub fn integrand(&self) -> (&'static str, &'static str) {
        match self.problem.objective() {
            OrbiterObjective::DetN3 => ("det(N3) = [n1.(n2 x n3)]^2 (eq. 57, 62)", "det(N3)"),
            OrbiterObjective::LogDet => ("ln max(det sum n n^T, 1e-9)", "ln det FIM"),
        }
    }

    /// Whether the scenario is seed 002's orbiters-3 (its Table 6 value applies).
    pub fn is_paper(&self) -> bool {
        self.scenario == "orbiters-3"
    }

    /// The error to end with when the check found the optimum worse than the input.
    pub fn verdict(&self) -> StudyResult<()> {
        verdict(self.check.as_ref())
    }

    /// The scenario `base` with the best orbiters: configuration and file text.
    pub fn written_scenario(&self, base: &ScenarioConfig) -> StudyResult<(ScenarioConfig, String)> {
        let (name, seed) = (self.problem.objective().name(), self.opts.seed);
        let note = match &self.bound {
            Some(b) => format!(
                "Orbiter geometry optimized by `entrynav optimize orbiters --objective pcrlb` \
                 (seed {seed}): final position PCRLB {:.3} m ({name} optimum: {:.3} m).",
                b.bound_m, b.proxy_bound_m
            ),
            None => format!(
                "Orbiter geometry optimized by `entrynav optimize orbiters` (seed {seed}): {name} \
                 = {:.3}.",
                self.sol.evaluation.value
            ),
        };
        let beacons = output::orbiter_beacons(self.best_elements(), self.altitude_m, &self.noise);
        let stem = self.options.scenario_name.as_deref().unwrap_or("optimized");
        output::with_beacons(base, beacons, stem, &note).map_err(study_error)
    }

    /// The trajectory and the objective's constants as CSV (`--export-trajectory`, for
    /// scripts/bench_orbiters_vs_scipy.py).
    pub fn trajectory_csv(&self) -> String {
        let (problem, sol) = (&self.problem, &self.sol);
        let header = [
            ("objective", problem.objective().name().to_string()),
            ("orbiters", self.count.to_string()),
            ("altitude_m", format!("{:e}", self.altitude_m)),
            (
                "penalty_per_rad_s",
                format!("{:e}", problem.penalty_per_rad_s),
            ),
            ("log_det_floor", format!("{:e}", LOG_DET_FLOOR)),
            ("our_value", format!("{:.12e}", sol.evaluation.value)),
            ("our_search_elapsed_s", format!("{:.6}", sol.elapsed_s)),
        ];
        problem.trajectory().to_csv(&header)
    }

    /// The JSON `entrynav optimize orbiters --json` writes.
    pub fn to_json(&self) -> Value {
        let (problem, sol) = (&self.problem, &self.sol);
        let traj = problem.trajectory();
        let ev = &sol.evaluation;
        let mut v = json!({
            "problem": "orbiters",
            "scenario": self.scenario,
            "objective": problem.objective().name(),
            "objective_definition": "integral over the trajectory (trapezoid rule) of det(N3) = [n1.(n2 x n3)]^2 (3 orbiters) or ln max(det sum n n^T, 1e-9); n_j unit vector orbiter->vehicle, hidden orbiters (eq. 58-60) contribute nothing",
            "value": ev.value,
            "upper_bound": problem.upper_bound(),
            "orbiters": self.count,
            "altitude_km": self.altitude_m / 1e3,
            "elements": elements_json(&sol.elements),
            "min_visibility_margin_deg": ev.min_margin_rad.to_degrees(),
            "visible_fraction": ev.visible_fraction,
            "evaluations": sol.search.evaluations,
            "elapsed_s": sol.elapsed_s,
            "wall_s": self.wall_s,
            "search": search_json(&sol.search, &self.opts),
            "trajectory": {
                "samples": traj.len(),
                "step_s": self.options.step,
                "duration_s": traj.duration(),
                "rule": "trapezoid",
            },
            "reference": self.reference.as_ref().map(|(el, r)| self.reference_json(el, r)),
            "check": self.check.as_ref().map(DesignCheck::json),
        });
        if let Some(n) = &self.nav {
            v["objective"] = json!(n.objective);
            if let Some(l) = &n.lincov {
                v["objective"] = json!(l.name());
                v["lincov"] = l.json();
            }
            v["geometric_objective"] = json!(problem.objective().name());
            v["navigation"] = nav_json(n);
        }
        if let Some(b) = &self.bound {
            v["pcrlb"] = json!({
                "objective": "final position PCRLB [m] (run 0 of seed 1), minimised by a Nelder-Mead polish from the geometric optimum",
                "final_pos_m": b.bound_m,
                "at_geometric_optimum_m": b.proxy_bound_m,
                "scenario_orbiters_m": self.own_bound,
                "elements": elements_json(&b.elements),
                "evaluations": b.search.evaluations,
                "elapsed_s": b.elapsed_s,
            });
        }
        v
    }

    /// The `reference` object: the scenario's own orbiters evaluated by the same objective.
    fn reference_json(&self, el: &[OrbitElements], r: &OrbiterEvaluation) -> Value {
        let mut o = json!({
            "value": r.value,
            "min_visibility_margin_deg": r.min_margin_rad.to_degrees(),
            "visible_fraction": r.visible_fraction,
            "violation_rad_s": r.violation_rad_s,
        });
        o["elements"] = elements_json(el);
        o["source"] = json!(format!("scenario {} orbiters", self.scenario));
        if self.is_paper() {
            o["paper_value"] = json!(PAPER_VALUE);
        }
        o
    }
}

/// The `navigation` object: the search on the nominal bound.
fn nav_json(n: &NavAnswer) -> Value {
    json!({
        "objective": n.objective,
        "value": n.solution.value,
        "definition": "nominal-trajectory position PCRLB [m] (entrynav::sim::nominal_bound); nav = 1/2 (avg/avg_input + final/final_input)",
        "time_avg_pos_m": n.solution.series.time_avg(),
        "final_pos_m": n.solution.series.final_value(),
        "input_time_avg_pos_m": n.own.map(|o| o.0),
        "input_final_pos_m": n.own.map(|o| o.1),
        "times_s": n.solution.series.times_s,
        "pos_m": n.solution.series.pos_m,
    })
}
