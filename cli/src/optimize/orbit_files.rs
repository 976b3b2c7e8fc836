//! The files `entrynav optimize orbiters` writes: the trajectory CSV, the scenario with the
//! optimized orbiters, the plot of the integrand and the JSON report.

use super::orbit_elements::{OrbiterAnswer, OrbiterInputs};
use super::*;

/// `--export-trajectory`: the trajectory and the objective's constants as CSV.
pub(super) fn export_trajectory(
    a: &OrbitersArgs,
    inputs: &OrbiterInputs,
    answer: &OrbiterAnswer,
) -> Result<()> {
    let Some(path) = &a.export_trajectory else {
        return Ok(());
    };
    let (problem, sol) = (&answer.problem, &answer.sol);
    let header = [
        ("objective", problem.objective().name().to_string()),
        ("orbiters", inputs.count.to_string()),
        ("altitude_m", format!("{:e}", inputs.altitude_m)),
        (
            "penalty_per_rad_s",
            format!("{:e}", problem.penalty_per_rad_s),
        ),
        ("log_det_floor", format!("{:e}", orbiters::LOG_DET_FLOOR)),
        ("our_value", format!("{:.12e}", sol.evaluation.value)),
        ("our_search_elapsed_s", format!("{:.6}", sol.elapsed_s)),
    ];
    write_text(path, &problem.trajectory().to_csv(&header))?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The scenario with the best orbiters (the PCRLB polish's, if any): configuration and the
/// text `--write-scenario` writes.
pub(super) fn orbiter_scenario(
    a: &OrbitersArgs,
    inputs: &OrbiterInputs,
    answer: &OrbiterAnswer,
) -> Result<(ScenarioConfig, String)> {
    let stem = a
        .common
        .write_scenario
        .as_deref()
        .map_or_else(|| "optimized".to_string(), file_stem);
    let (problem, opts) = (&answer.problem, &answer.opts);
    let note = match &answer.bound {
        Some(b) => format!(
            "Orbiter geometry optimized by `entrynav optimize orbiters --objective pcrlb` \
             (seed {}): final position PCRLB {:.3} m ({} optimum: {:.3} m).",
            opts.seed,
            b.bound_m,
            problem.objective().name(),
            b.proxy_bound_m
        ),
        None => format!(
            "Orbiter geometry optimized by `entrynav optimize orbiters` (seed {}): {} = {:.3}.",
            opts.seed,
            problem.objective().name(),
            answer.sol.evaluation.value
        ),
    };
    Ok(output::with_beacons(
        &inputs.cfg,
        output::orbiter_beacons(answer.best_elements(), inputs.altitude_m, &answer.noise),
        &stem,
        &note,
    )?)
}

/// `--plot`: the integrand along the entry, optimum against the scenario's orbiters.
pub(super) fn plot_orbiters(
    a: &OrbitersArgs,
    inputs: &OrbiterInputs,
    answer: &OrbiterAnswer,
) -> Result<()> {
    let Some(path) = &a.plot else {
        return Ok(());
    };
    let problem = &answer.problem;
    let ev = &answer.sol.evaluation;
    let t = &problem.trajectory().times;
    let curve = |name: String, integrand: &[f64], dashed: bool| crate::plot::Curve {
        name,
        points: t.iter().copied().zip(integrand.iter().copied()).collect(),
        dashed,
    };
    let mut curves = vec![curve(
        format!("optimum ({:.3})", ev.value),
        &ev.integrand,
        false,
    )];
    if let Some((_, r)) = &answer.reference {
        curves.push(curve(
            format!("scenario's orbiters ({:.3})", r.value),
            &r.integrand,
            true,
        ));
    }
    write_text(path, "")?;
    crate::plot::line_plot(
        path,
        &format!(
            "{}: {} integrand along the entry",
            inputs.cfg.name,
            problem.objective().name()
        ),
        "time (s)",
        match problem.objective() {
            OrbiterObjective::DetN3 => "det(N3)",
            OrbiterObjective::LogDet => "ln det FIM",
        },
        false,
        &curves,
    )?;
    println!("wrote {}", path.display());
    Ok(())
}

/// `--json`: the optimum, the search, the trajectory, the scenario's orbiters and the polish.
pub(super) fn write_orbiter_json(
    a: &OrbitersArgs,
    inputs: &OrbiterInputs,
    answer: &OrbiterAnswer,
    check: Option<&super::design_check::DesignCheck>,
    wall: Instant,
) -> Result<()> {
    let Some(path) = &a.common.json else {
        return Ok(());
    };
    let (cfg, problem, sol) = (&inputs.cfg, &answer.problem, &answer.sol);
    let traj = problem.trajectory();
    let ev = &sol.evaluation;
    let mut v = json!({
        "problem": "orbiters",
        "scenario": cfg.name,
        "objective": problem.objective().name(),
        "objective_definition": "integral over the trajectory (trapezoid rule) of det(N3) = [n1.(n2 x n3)]^2 (3 orbiters) or ln max(det sum n n^T, 1e-9); n_j unit vector orbiter->vehicle, hidden orbiters (eq. 58-60) contribute nothing",
        "value": ev.value,
        "upper_bound": problem.upper_bound(),
        "orbiters": inputs.count,
        "altitude_km": inputs.altitude_m / 1e3,
        "elements": elements_json(&sol.elements),
        "min_visibility_margin_deg": ev.min_margin_rad.to_degrees(),
        "visible_fraction": ev.visible_fraction,
        "evaluations": sol.search.evaluations,
        "elapsed_s": sol.elapsed_s,
        "wall_s": wall.elapsed().as_secs_f64(),
        "search": search_json(&sol.search, &answer.opts),
        "trajectory": {
            "samples": traj.len(),
            "step_s": a.step,
            "duration_s": traj.duration(),
            "rule": "trapezoid",
        },
        "reference": answer.reference.as_ref().map(|(el, r)| reference_json(cfg, el, r)),
        "check": check.map(super::design_check::DesignCheck::json),
    });
    if let Some(n) = &answer.nav {
        v["objective"] = json!(n.objective);
        if let Some(l) = &n.lincov {
            v["objective"] = json!(l.name());
            v["lincov"] = l.json();
        }
        v["geometric_objective"] = json!(problem.objective().name());
        v["navigation"] = json!({
            "objective": n.objective,
            "value": n.solution.value,
            "definition": "nominal-trajectory position PCRLB [m] (entrynav::sim::nominal_bound); nav = 1/2 (avg/avg_input + final/final_input)",
            "time_avg_pos_m": n.solution.series.time_avg(),
            "final_pos_m": n.solution.series.final_value(),
            "input_time_avg_pos_m": n.own.map(|o| o.0),
            "input_final_pos_m": n.own.map(|o| o.1),
            "times_s": n.solution.series.times_s,
            "pos_m": n.solution.series.pos_m,
        });
    }
    if let Some(b) = &answer.bound {
        v["pcrlb"] = json!({
            "objective": "final position PCRLB [m] (run 0 of seed 1), minimised by a Nelder-Mead polish from the geometric optimum",
            "final_pos_m": b.bound_m,
            "at_geometric_optimum_m": b.proxy_bound_m,
            "scenario_orbiters_m": answer.own_bound,
            "elements": elements_json(&b.elements),
            "evaluations": b.search.evaluations,
            "elapsed_s": b.elapsed_s,
        });
    }
    write_json(path, &v)
}

/// The `reference` object: the scenario's own orbiters evaluated by the same objective.
fn reference_json(cfg: &ScenarioConfig, el: &[OrbitElements], r: &OrbiterEvaluation) -> Value {
    let mut o = json!({
        "value": r.value,
        "min_visibility_margin_deg": r.min_margin_rad.to_degrees(),
        "visible_fraction": r.visible_fraction,
        "violation_rad_s": r.violation_rad_s,
    });
    o["elements"] = elements_json(el);
    o["source"] = json!(format!("scenario {} orbiters", cfg.name));
    if cfg.name == "orbiters-3" {
        o["paper_value"] = json!(237.963);
    }
    o
}

/// The elements of each orbiter in degrees.
fn elements_json(el: &[OrbitElements]) -> Value {
    Value::Array(
        el.iter()
            .map(|e| {
                let [raan, inc, f] = e.degrees();
                json!({"raan_deg": raan, "inc_deg": inc, "true_anomaly_deg": f})
            })
            .collect(),
    )
}
