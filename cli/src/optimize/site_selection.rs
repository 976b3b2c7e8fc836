//! `entrynav optimize select`: certified choice of k candidate sites (Joshi & Boyd relaxation
//! bound with clarabel, then local search).

use super::ground_sites::{scenario_sites, sites_json};
use super::*;

fn selection_json(s: &Selection, sites: &[Site], r: &SelectionReport) -> Value {
    let chosen: Vec<Site> = s.indices.iter().map(|&i| sites[i]).collect();
    json!({
        "indices": s.indices,
        "sites": sites_json(&chosen),
        "value": s.value,
        "gap": r.gap(s),
    })
}

pub(super) fn run_select(a: &SelectArgs) -> Result<()> {
    let wall = Instant::now();
    let (cfg, dir) = load::scenario_config(&a.scenario)?;
    let cfg = load::apply_overrides(cfg, &a.sets)?;
    let load = loader(&dir);
    let criterion = SelectionCriterion::from(a.criterion);
    if a.eig_epochs.is_some() && criterion != SelectionCriterion::MinEig {
        bail!("--eig-epochs applies to --criterion min-eig only");
    }
    let ground = GroundProblem::new(
        &cfg,
        &load,
        a.k.max(1),
        GroundObjective::LogDet,
        a.step,
        a.min_elevation_deg.to_radians(),
    )?;
    let mut sites = ground.visible_grid(a.grid_deg)?;
    let grid_count = sites.len();
    // Heuristic answers to certify: the scenario's own surface sites (if k of them, all
    // feasible) and the sites of a ground-optimizer JSON file.
    let mut extra: Vec<(String, Vec<usize>)> = Vec::new();
    let mut add = |label: String, list: Vec<Site>, sites: &mut Vec<Site>| {
        if list.len() == a.k && list.iter().all(|s| ground.is_feasible(s)) {
            let start = sites.len();
            sites.extend(list);
            extra.push((label, (start..sites.len()).collect()));
        } else {
            println!(
                "note: {label} not certified (needs exactly k = {} sites, each visible during the \
                 whole entry)",
                a.k
            );
        }
    };
    let own = scenario_sites(&cfg);
    if !own.is_empty() {
        add(format!("scenario {} sites", cfg.name), own, &mut sites);
    }
    if let Some(path) = &a.compare {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let v: Value = serde_json::from_str(&text)
            .with_context(|| format!("{} is not JSON", path.display()))?;
        let list = v["sites"]
            .as_array()
            .with_context(|| format!("{} has no \"sites\" array", path.display()))?
            .iter()
            .map(|s| {
                Some(Site::from_degrees(
                    s["lat_deg"].as_f64()?,
                    s["lon_deg"].as_f64()?,
                ))
            })
            .collect::<Option<Vec<Site>>>()
            .with_context(|| format!("{}: sites need lat_deg and lon_deg", path.display()))?;
        add(format!("sites of {}", path.display()), list, &mut sites);
    }
    let blocks = site_information(&ground, &sites, a.eig_epochs)?;
    let problem =
        SelectionProblem::new(blocks, a.k, criterion)?.with_solver_verbose(a.solver_verbose);
    let report = problem.solve()?;
    let brute = problem.brute_force(a.brute_force_limit);
    let r = &report.relaxation;

    println!("scenario    {}", cfg.name);
    println!(
        "candidates  {grid_count} grid sites every {} deg visible during the whole entry \
         (min elevation {} deg){}",
        a.grid_deg,
        a.min_elevation_deg,
        if sites.len() > grid_count {
            format!(" + {} sites to certify", sites.len() - grid_count)
        } else {
            String::new()
        }
    );
    println!(
        "criterion   {} over k = {} of m = {} ({})",
        criterion.name(),
        a.k,
        sites.len(),
        match (criterion, a.eig_epochs) {
            (SelectionCriterion::LogDet, _) =>
                "ln det of the time-averaged unit-sigma range FIM sum_i A_i, A_i = (1/T) integral n_i n_i^T dt (planet-fixed frame)".to_string(),
            (SelectionCriterion::MinEig, None) =>
                "lambda_min of the time-averaged unit-sigma range FIM".to_string(),
            (SelectionCriterion::MinEig, Some(s)) => format!(
                "min over epochs every {s} s of lambda_min of the instantaneous unit-sigma FIM sum n n^T"
            ),
        }
    );
    println!(
        "relaxation  bound {:.6} (primal {:.6}, dual {:.6}; clarabel {}, {} iterations, {:.3} s)",
        r.bound, r.primal, r.dual, r.status, r.iterations, r.solve_time_s
    );
    let show = |label: &str, s: &Selection| {
        let chosen: Vec<String> = s
            .indices
            .iter()
            .map(|&i| {
                let [lat, lon] = sites[i].degrees();
                format!("({lat:.2}, {lon:.2})")
            })
            .collect();
        println!(
            "{label:<30} value {:>11.6}  gap {:>10.3e}  sites {}",
            s.value,
            report.gap(s),
            chosen.join(" ")
        );
    };
    if let Some(s) = &report.rounded {
        show("rounded (top-k of z)", s);
    }
    show("swap-improved (answer)", &report.improved);
    if let Some(s) = &report.greedy {
        show("greedy", s);
    }
    if let Some(b) = &brute {
        show("brute force (exact optimum)", b);
    }
    let extra_sel: Vec<(String, Selection)> = extra
        .iter()
        .map(|(label, idx)| {
            (
                label.clone(),
                Selection {
                    indices: idx.clone(),
                    value: problem.value(idx),
                },
            )
        })
        .collect();
    for (label, s) in &extra_sel {
        show(label, s);
    }
    println!(
        "            {} criterion evaluations, {:.3} s wall",
        report.evaluations,
        wall.elapsed().as_secs_f64()
    );

    if let Some(path) = &a.write_scenario {
        let noise = template_noise(&cfg, false)?;
        let chosen: Vec<Site> = report.improved.indices.iter().map(|&i| sites[i]).collect();
        let (_, text) = output::with_beacons(
            &cfg,
            output::surface_beacons(&chosen, &noise),
            &file_stem(path),
            &format!(
                "Sites chosen by `entrynav optimize select` ({}, k = {}, grid {} deg): value {:.6}, certified gap {:.3e}.",
                criterion.name(),
                a.k,
                a.grid_deg,
                report.improved.value,
                report.gap(&report.improved)
            ),
        )?;
        write_text(path, &text)?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &a.json {
        let improved = &report.improved;
        let chosen: Vec<Site> = improved.indices.iter().map(|&i| sites[i]).collect();
        let support: Vec<Value> =
            r.z.iter()
                .enumerate()
                .filter(|(_, z)| **z > 1e-4)
                .map(|(i, z)| {
                    let [lat, lon] = sites[i].degrees();
                    json!({"index": i, "z": z, "lat_deg": lat, "lon_deg": lon})
                })
                .collect();
        let v = json!({
            "problem": "select",
            "scenario": cfg.name,
            "objective": criterion.name(),
            "eig_epochs_s": a.eig_epochs,
            "value": improved.value,
            "sites": sites_json(&chosen),
            "bound": r.bound,
            "gap": report.gap(improved),
            "k": a.k,
            "candidates": sites.len(),
            "grid_candidates": grid_count,
            "grid_deg": a.grid_deg,
            "evaluations": report.evaluations,
            "elapsed_s": report.elapsed_s,
            "wall_s": wall.elapsed().as_secs_f64(),
            "relaxation": {
                "status": r.status,
                "iterations": r.iterations,
                "primal": r.primal,
                "dual": r.dual,
                "solve_time_s": r.solve_time_s,
                "support": support,
            },
            "rounded": report.rounded.as_ref().map(|s| selection_json(s, &sites, &report)),
            "greedy": report.greedy.as_ref().map(|s| selection_json(s, &sites, &report)),
            "brute_force": brute.as_ref().map(|b| selection_json(b, &sites, &report)),
            "certified": extra_sel.iter().map(|(label, s)| {
                let mut o = selection_json(s, &sites, &report);
                o["label"] = json!(label);
                o
            }).collect::<Vec<_>>(),
        });
        write_json(path, &v)?;
    }
    Ok(())
}
