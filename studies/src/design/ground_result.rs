//! What the ground-site design returns: the optimum and its δ(t), the scenario's own sites
//! evaluated the same way, the nominal bound of both, the optimum as a scenario, the check
//! against the input, and the JSON `entrynav optimize ground --json` writes.

use crate::design::check::{DesignCheck, verdict};
use crate::design::ground_options::GroundOptions;
use crate::design::lincov_stage::LinCovStage;
use crate::design::search::search_json;
use crate::design::sites::sites_json;
use crate::error::StudyResult;
use entrynav::observability::{DegreeSeries, Method};
use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::ground::GroundEvaluation;
use entrynav_optimizer::{GroundObjective, GroundSolution, SearchOptions, Site};
use serde_json::{Value, json};

/// The δ range seed 002 §5.1 reports for its optimum on ground-beacons-3 (raw SI).
pub const PAPER_DELTA_RANGE: [f64; 2] = [1.413e-8, 2.945e-7];

/// A ground-site design.
#[derive(Debug, Clone)]
pub struct GroundDesign {
    /// The options it ran with.
    pub options: GroundOptions,
    /// The scenario's name.
    pub scenario: String,
    /// Number of beacons placed.
    pub count: usize,
    /// The search's objective (for lincov-*, the bound of the same figure).
    pub objective: GroundObjective,
    /// The objective the user chose (its name).
    pub objective_name: &'static str,
    /// The observability method of δ.
    pub method: Method,
    /// The scenario's own surface sites.
    pub own: Vec<Site>,
    /// Their elevation mask \[deg\].
    pub own_mask_deg: f64,
    /// Whether every site must see the whole entry (eq. 52).
    pub whole_entry: bool,
    /// The required minimum elevation \[rad\].
    pub min_elevation_rad: f64,
    /// What the scaled δ is scaled by, in words.
    pub scaling: String,
    /// The search's settings.
    pub opts: SearchOptions,
    /// The optimum (after the LinCov polish, if any).
    pub solution: GroundSolution,
    /// The optimum's objective at the reporting step.
    pub evaluation: GroundEvaluation,
    /// δ(t) of the optimum.
    pub delta: DegreeSeries,
    /// The scenario's own sites, when there are as many: evaluation and δ(t).
    pub reference: Option<(GroundEvaluation, DegreeSeries)>,
    /// Nominal position bound (time-averaged, final) \[m\] of the optimum and of the input's own
    /// sites (any count), where the scenario has one.
    pub bounds: Option<[(f64, f64); 2]>,
    /// The optimum as a scenario configuration.
    pub design: ScenarioConfig,
    /// Its file text (what `--write-scenario` writes).
    pub design_toml: String,
    /// The check against the input design (`None`: skipped).
    pub check: Option<DesignCheck>,
    /// lincov-*: the polish on LinCov.
    pub lincov: Option<LinCovStage>,
    /// Wall time of the study \[s\].
    pub wall_s: f64,
}

/// Smallest and largest δ of a series (0 when it has none).
pub fn delta_range(d: &DegreeSeries, scaled: bool) -> (f64, f64) {
    d.summary(scaled).map_or((0.0, 0.0), |s| (s.min, s.max))
}

fn delta_json(d: &DegreeSeries) -> Value {
    let r = d.summary(false);
    let s = d.summary(true);
    json!({
        "method": d.method.name(),
        "delta_raw_min": r.map(|m| m.min),
        "delta_raw_max": r.map(|m| m.max),
        "t_delta_raw_min_s": r.map(|m| m.t_min_s),
        "delta_scaled_min": s.map(|m| m.min),
        "delta_scaled_max": s.map(|m| m.max),
        "times_s": d.times(),
        "delta_raw": d.deltas(false),
        "delta_scaled": d.deltas(true),
    })
}

fn degrees(e: &[f64]) -> Vec<f64> {
    e.iter().map(|e| e.to_degrees()).collect()
}

impl GroundDesign {
    /// Whether the scenario is seed 002's (its paper range applies).
    pub fn is_paper(&self) -> bool {
        self.scenario == "ground-beacons-3"
    }

    /// The error to end with when the check found the optimum worse than the input.
    pub fn verdict(&self) -> StudyResult<()> {
        verdict(self.check.as_ref())
    }

    /// The JSON `entrynav optimize ground --json` writes.
    pub fn to_json(&self) -> Value {
        let (o, ev, sol) = (&self.options, &self.evaluation, &self.solution);
        json!({
            "problem": "ground",
            "scenario": self.scenario,
            "objective": self.objective_name,
            "objective_units": self.objective.units(),
            "search_objective": self.objective.name(),
            "lincov": self.lincov.as_ref().map(LinCovStage::json),
            "value": ev.value,
            "beacons": self.count,
            "sites": sites_json(&sol.sites),
            "min_elevation_deg": degrees(&ev.min_elevation_rad),
            "delta": delta_json(&self.delta),
            "evaluations": sol.search.evaluations,
            "elapsed_s": sol.elapsed_s,
            "wall_s": self.wall_s,
            "search": search_json(&sol.search, &self.opts),
            "search_step_s": o.search_step,
            "report_step_s": o.step,
            "delta_units": "raw SI: sigma_min/sigma_max of O with states in m, rad, m/s and outputs in m; scaled: see scaling",
            "scaling": self.scaling,
            "reference": self.reference.as_ref().map(|(r, d)| json!({
                "source": format!("scenario {} surface beacons", self.scenario),
                "sites": sites_json(&self.own),
                "value": r.value,
                "min_elevation_deg": degrees(&r.min_elevation_rad),
                "delta": delta_json(d),
            })),
            "paper_delta_range": self.is_paper().then(|| json!(PAPER_DELTA_RANGE)),
            "min_separation_deg": o.min_separation_deg,
            "whole_entry_visibility": self.whole_entry,
            "elevation_mask_deg": o.elevation_mask_deg,
            "input_elevation_mask_deg": self.own_mask_deg,
            "closest_pair_deg": ev.closest_pair_rad.map(f64::to_degrees),
            "nominal_bound": self.bounds.map(|b| json!({
                "optimum": {"time_avg_pos_m": b[0].0, "final_pos_m": b[0].1},
                "input": {"time_avg_pos_m": b[1].0, "final_pos_m": b[1].1},
            })),
            "check": self.check.as_ref().map(DesignCheck::json),
        })
    }
}
