//! `entrynav optimize orbiters`: orbiter elements (Ω, i, f) on circular orbits (seed 002 §4.2).

use super::*;

/// The scenario's own orbiters on circular orbits: (altitude [m], elements).
fn scenario_orbits(cfg: &ScenarioConfig) -> Vec<(f64, OrbitElements)> {
    cfg.beacons
        .iter()
        .filter_map(|b| match b {
            BeaconConfig::Orbiter(o) => o.circular.map(|c| {
                (
                    c.altitude_km * 1e3,
                    OrbitElements::from_degrees(c.raan_deg, c.inc_deg, c.true_anomaly_deg),
                )
            }),
            BeaconConfig::Surface(_) => None,
        })
        .collect()
}

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

fn print_elements(el: &[OrbitElements]) {
    println!(
        "  {:<10} {:>10} {:>10} {:>10}",
        "orbiter", "RAAN [deg]", "i [deg]", "f [deg]"
    );
    for (k, e) in el.iter().enumerate() {
        let [raan, inc, f] = e.degrees();
        println!("  {:<10} {raan:>10.3} {inc:>10.3} {f:>10.3}", k + 1);
    }
}

pub(super) fn run_orbiters(a: &OrbitersArgs) -> Result<()> {
    let wall = Instant::now();
    let c = &a.common;
    let (cfg, dir) = load::resolve(&c.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &c.sets)?;
    let own = scenario_orbits(&cfg);
    let count = a.orbiters.unwrap_or_else(|| {
        cfg.beacons
            .iter()
            .filter(|b| matches!(b, BeaconConfig::Orbiter(_)))
            .count()
            .max(3)
    });
    let altitude_m = match (a.altitude_km, own.first()) {
        (Some(km), _) => km * 1e3,
        (None, Some((alt, _))) => *alt,
        (None, None) => bail!(
            "scenario '{}' has no circular orbiter to take the altitude from; give --altitude-km",
            cfg.name
        ),
    };
    let on_bound = a.objective == Some(OrbiterObjectiveArg::Pcrlb);
    let objective = a.objective.and_then(OrbiterObjectiveArg::geometric);
    let scenario = load::build(cfg.clone(), &dir)?;
    let trajectory = Trajectory::from_scenario(&scenario, a.step)?;
    let problem = OrbiterProblem::new(trajectory, count, altitude_m, objective)?;
    let opts = c.search(orbiters::default_search(c.seed));
    let dim = 3 * count;
    let bar = progress_bar(c.quiet, format!("{} orbiters", cfg.name));
    bar.set_length(opts.budget(dim) as u64);
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let noise = template_noise(&cfg, true)?;
    let bound_problem =
        on_bound.then(|| OrbiterBoundProblem::new(problem.clone(), cfg.clone(), noise));
    let bound = bound_problem
        .as_ref()
        .map(|b| {
            let polish = orbiters_bound::default_bound_polish(c.seed);
            b.optimize(&opts, &polish, &progress)
        })
        .transpose()?;
    let sol = match &bound {
        Some(b) => b.proxy.clone(),
        None => problem.optimize(&opts, &progress)?,
    };
    bar.finish_and_clear();

    // The scenario's own orbiters (the paper's Table 6 for orbiters-3), when comparable.
    let reference: Option<(Vec<OrbitElements>, OrbiterEvaluation)> = (own.len() == count
        && own.iter().all(|(alt, _)| (alt - altitude_m).abs() < 1e-6))
    .then(|| {
        let el: Vec<OrbitElements> = own.iter().map(|(_, e)| *e).collect();
        problem.evaluate(&el).map(|ev| (el, ev))
    })
    .transpose()?;

    let traj = problem.trajectory();
    let ev = &sol.evaluation;
    println!("scenario    {}", cfg.name);
    println!(
        "problem     {count} orbiters on circular orbits at {:.1} km (seed 002 eq. 55-56), \
         line of sight by eq. 58-60",
        altitude_m / 1e3
    );
    println!(
        "objective   {} = integral over t of {} (trapezoid over {} samples, {:.0} s; \
         upper bound {:.3})",
        problem.objective().name(),
        match problem.objective() {
            OrbiterObjective::DetN3 => "det(N3) = [n1.(n2 x n3)]^2 (eq. 57, 62)",
            OrbiterObjective::LogDet => "ln max(det sum n n^T, 1e-9)",
        },
        traj.len(),
        traj.duration(),
        problem.upper_bound()
    );
    println!();
    println!("optimum     {:.3}", ev.value);
    print_elements(&sol.elements);
    println!(
        "  min visibility margin {:.3} deg, {:.1} % of orbiter-epochs in view",
        ev.min_margin_rad.to_degrees(),
        100.0 * ev.visible_fraction
    );
    if let Some((el, r)) = &reference {
        println!();
        println!(
            "scenario's own orbiters{} evaluated by the same objective: {:.3}",
            if cfg.name == "orbiters-3" {
                " (seed 002 Table 6; paper reports 237.963)"
            } else {
                ""
            },
            r.value
        );
        print_elements(el);
        println!(
            "  min visibility margin {:.3} deg",
            r.min_margin_rad.to_degrees()
        );
    }
    println!();
    print_search(&sol.search, sol.elapsed_s, wall, &opts);
    let own_bound = match (&bound_problem, &reference) {
        (Some(bp), Some((el, _))) => Some(bp.final_position_bound(el)?),
        _ => None,
    };
    if let Some(b) = &bound {
        println!();
        println!(
            "pcrlb       final position PCRLB of the scenario with these orbiters (IMU, dynamics, \
             prior and ranges; run 0 of seed 1), polished from the {} optimum",
            problem.objective().name()
        );
        println!(
            "optimum     {:.3} m  (at the {} optimum {:.3} m{})",
            b.bound_m,
            problem.objective().name(),
            b.proxy_bound_m,
            own_bound.map_or(String::new(), |v| format!(
                "; scenario's own orbiters {v:.3} m"
            ))
        );
        print_elements(&b.elements);
        println!(
            "  polish: {} bound evaluations, {:.1} s (proxy search and polish)",
            b.search.evaluations, b.elapsed_s
        );
    }
    let best_elements = bound.as_ref().map_or(&sol.elements, |b| &b.elements);
    if let Some(path) = &a.export_trajectory {
        let header = [
            ("objective", problem.objective().name().to_string()),
            ("orbiters", count.to_string()),
            ("altitude_m", format!("{altitude_m:e}")),
            (
                "penalty_per_rad_s",
                format!("{:e}", problem.penalty_per_rad_s),
            ),
            ("log_det_floor", format!("{:e}", orbiters::LOG_DET_FLOOR)),
            ("our_value", format!("{:.12e}", ev.value)),
            ("our_search_elapsed_s", format!("{:.6}", sol.elapsed_s)),
        ];
        write_text(path, &traj.to_csv(&header))?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &c.write_scenario {
        let name = file_stem(path);
        let (_, text) = output::with_beacons(
            &cfg,
            output::orbiter_beacons(best_elements, altitude_m, &noise),
            &name,
            &match &bound {
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
                    ev.value
                ),
            },
        )?;
        write_text(path, &text)?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &a.plot {
        let t = traj.times.clone();
        let mut curves = vec![crate::plot::Curve {
            name: format!("optimum ({:.3})", ev.value),
            points: t
                .iter()
                .copied()
                .zip(ev.integrand.iter().copied())
                .collect(),
            dashed: false,
        }];
        if let Some((_, r)) = &reference {
            curves.push(crate::plot::Curve {
                name: format!("scenario's orbiters ({:.3})", r.value),
                points: t.iter().copied().zip(r.integrand.iter().copied()).collect(),
                dashed: true,
            });
        }
        write_text(path, "")?;
        crate::plot::line_plot(
            path,
            &format!(
                "{}: {} integrand along the entry",
                cfg.name,
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
    }
    if let Some(path) = &c.json {
        let ev_json = |e: &OrbiterEvaluation| {
            json!({
                "value": e.value,
                "min_visibility_margin_deg": e.min_margin_rad.to_degrees(),
                "visible_fraction": e.visible_fraction,
                "violation_rad_s": e.violation_rad_s,
            })
        };
        let mut v = json!({
            "problem": "orbiters",
            "scenario": cfg.name,
            "objective": problem.objective().name(),
            "objective_definition": "integral over the trajectory (trapezoid rule) of det(N3) = [n1.(n2 x n3)]^2 (3 orbiters) or ln max(det sum n n^T, 1e-9); n_j unit vector orbiter->vehicle, hidden orbiters (eq. 58-60) contribute nothing",
            "value": ev.value,
            "upper_bound": problem.upper_bound(),
            "orbiters": count,
            "altitude_km": altitude_m / 1e3,
            "elements": elements_json(&sol.elements),
            "min_visibility_margin_deg": ev.min_margin_rad.to_degrees(),
            "visible_fraction": ev.visible_fraction,
            "evaluations": sol.search.evaluations,
            "elapsed_s": sol.elapsed_s,
            "wall_s": wall.elapsed().as_secs_f64(),
            "search": search_json(&sol.search, &opts),
            "trajectory": {
                "samples": traj.len(),
                "step_s": a.step,
                "duration_s": traj.duration(),
                "rule": "trapezoid",
            },
            "reference": reference.as_ref().map(|(el, r)| {
                let mut o = ev_json(r);
                o["elements"] = elements_json(el);
                o["source"] = json!(format!("scenario {} orbiters", cfg.name));
                if cfg.name == "orbiters-3" {
                    o["paper_value"] = json!(237.963);
                }
                o
            }),
        });
        if let Some(b) = &bound {
            v["pcrlb"] = json!({
                "objective": "final position PCRLB [m] (run 0 of seed 1), minimised by a Nelder-Mead polish from the geometric optimum",
                "final_pos_m": b.bound_m,
                "at_geometric_optimum_m": b.proxy_bound_m,
                "scenario_orbiters_m": own_bound,
                "elements": elements_json(&b.elements),
                "evaluations": b.search.evaluations,
                "elapsed_s": b.elapsed_s,
            });
        }
        write_json(path, &v)?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// ground
