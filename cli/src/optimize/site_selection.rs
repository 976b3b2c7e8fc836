//! `entrynav optimize select`: certified choice of k candidate sites (Joshi & Boyd relaxation
//! bound with clarabel, then local search; `--exact`: branch and bound, in
//! [`exact_selection`](super::exact_selection)).

use super::exact_selection::{exact_json, finish_exact_only, print_proof, run_exact};
use super::ground_sites::{scenario_sites, sites_json};
use super::*;

/// `value` and `gap = bound − value` of a selection (`bound`: the best bound known).
pub(super) fn selection_json(s: &Selection, sites: &[Site], bound: f64) -> Value {
    let chosen: Vec<Site> = s.indices.iter().map(|&i| sites[i]).collect();
    json!({
        "indices": s.indices,
        "sites": sites_json(&chosen),
        "value": s.value,
        "gap": (bound - s.value).max(0.0),
    })
}

/// `--region LAT_MIN,LAT_MAX,LON_MIN,LON_MAX` as a predicate on sites.
fn region_filter(region: &Option<Vec<f64>>) -> Result<impl Fn(&Site) -> bool + use<>> {
    let b = match region.as_deref() {
        None => None,
        Some(&[lat0, lat1, lon0, lon1]) if lat0 <= lat1 && lon0 <= lon1 => {
            Some([lat0, lat1, lon0, lon1])
        }
        Some(v) => {
            bail!("--region needs LAT_MIN,LAT_MAX,LON_MIN,LON_MAX with min <= max (deg), got {v:?}")
        }
    };
    Ok(move |s: &Site| {
        b.is_none_or(|[lat0, lat1, lon0, lon1]| {
            let [lat, lon] = s.degrees();
            (lat0..=lat1).contains(&lat) && (lon0..=lon1).contains(&lon)
        })
    })
}

pub(super) fn run_select(a: &SelectArgs) -> Result<()> {
    let wall = Instant::now();
    let (cfg, dir) = load::resolve(&a.scenario, load::Base::CurrentDir)?.into_parts();
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
    let inside = region_filter(&a.region)?;
    let mut sites = ground.visible_grid(a.grid_deg)?;
    sites.retain(&inside);
    if sites.is_empty() {
        bail!("no visible grid site lies inside --region {:?}", a.region);
    }
    let grid_count = sites.len();
    // Heuristic answers to certify: the scenario's own surface sites (if k of them, all
    // feasible) and the sites of a ground-optimizer JSON file.
    let mut extra: Vec<(String, Vec<usize>)> = Vec::new();
    let mut add = |label: String, list: Vec<Site>, sites: &mut Vec<Site>| {
        if list.len() == a.k && list.iter().all(|s| ground.is_feasible(s) && inside(s)) {
            let start = sites.len();
            sites.extend(list);
            extra.push((label, (start..sites.len()).collect()));
        } else {
            println!(
                "note: {label} not certified (needs exactly k = {} sites, each visible during the \
                 whole entry and inside --region)",
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
    let spacing = match a.min_separation_deg {
        Some(d) => separation_constraints(&sites, d.to_radians())?,
        None => Vec::new(),
    };
    let pairs = spacing.len();
    let problem = SelectionProblem::new(blocks, a.k, criterion)?
        .with_solver_verbose(a.solver_verbose)
        .with_constraints(spacing)?;
    // The heuristic; with --exact the branch and bound can go on without it.
    let report = match problem.solve() {
        Ok(r) => r,
        Err(e) if a.exact => {
            println!("note: the heuristic failed ({e}); branch and bound starts without it");
            return finish_exact_only(a, &cfg, &problem, &sites, grid_count, wall);
        }
        Err(e) => return Err(e.into()),
    };
    let brute = problem.brute_force(a.brute_force_limit);
    let exact = if a.exact {
        Some(run_exact(a, &problem, Some(&report.improved))?)
    } else {
        None
    };
    let r = &report.relaxation;
    // Gaps are measured from the best bound known: the proof's, else the relaxation's.
    let bound = exact.as_ref().map_or(r.bound, |e| e.bound);
    let answer = exact.as_ref().map_or(&report.improved, |e| &e.best);

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
    if a.min_separation_deg.is_some() || a.region.is_some() {
        println!(
            "constraints {}{}",
            a.min_separation_deg.map_or(String::new(), |d| format!(
                "sites at least {d} deg apart ({pairs} closer pairs, z_i + z_j <= 1); "
            )),
            a.region.as_ref().map_or(String::new(), |b| format!(
                "candidates inside lat [{}, {}], lon [{}, {}] deg",
                b[0], b[1], b[2], b[3]
            ))
        );
    }
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
            "{label:<30} value {:>11.6}  gap {:>10.3e}  sites {}{}",
            s.value,
            (bound - s.value).max(0.0),
            chosen.join(" "),
            if problem.admissible(&s.indices) {
                ""
            } else {
                "  (breaks the side constraints)"
            }
        );
    };
    if let Some(s) = &report.rounded {
        show("rounded (top-k of z)", s);
    }
    show(
        if exact.is_some() {
            "swap-improved (heuristic)"
        } else {
            "swap-improved (answer)"
        },
        &report.improved,
    );
    if let Some(s) = &report.greedy {
        show("greedy", s);
    }
    if let Some(b) = &brute {
        show("brute force (exact optimum)", b);
    }
    if let Some(e) = &exact {
        show("branch and bound (answer)", &e.best);
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
    if let Some(e) = &exact {
        print_proof(a, e);
    }

    write_selected(a, &cfg, &sites, criterion, answer, bound, exact.as_ref())?;
    if let Some(path) = &a.json {
        let chosen: Vec<Site> = answer.indices.iter().map(|&i| sites[i]).collect();
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
            "answer": if exact.is_some() { "exact" } else { "heuristic" },
            "value": answer.value,
            "sites": sites_json(&chosen),
            "bound": bound,
            "gap": (bound - answer.value).max(0.0),
            "k": a.k,
            "candidates": sites.len(),
            "grid_candidates": grid_count,
            "grid_deg": a.grid_deg,
            "evaluations": report.evaluations,
            "elapsed_s": report.elapsed_s,
            "wall_s": wall.elapsed().as_secs_f64(),
            "relaxation": {
                "status": r.status.to_string(),
                "iterations": r.iterations,
                "primal": r.primal,
                "dual": r.dual,
                "solve_time_s": r.solve_time_s,
                "support": support,
            },
            "rounded": report.rounded.as_ref().map(|s| selection_json(s, &sites, bound)),
            "greedy": report.greedy.as_ref().map(|s| selection_json(s, &sites, bound)),
            "heuristic": selection_json(&report.improved, &sites, bound),
            "brute_force": brute.as_ref().map(|b| selection_json(b, &sites, bound)),
            "certified": extra_sel.iter().map(|(label, s)| {
                let mut o = selection_json(s, &sites, bound);
                o["label"] = json!(label);
                o["admissible"] = json!(problem.admissible(&s.indices));
                o
            }).collect::<Vec<_>>(),
            "constraints": constraints_json(a, pairs),
            "exact": exact.as_ref().map(|e| exact_json(a, e, &sites)),
        });
        write_json(path, &v)?;
    }
    Ok(())
}

pub(super) fn constraints_json(a: &SelectArgs, pairs: usize) -> Value {
    json!({
        "min_separation_deg": a.min_separation_deg,
        "close_pairs": pairs,
        "region_deg": a.region,
    })
}

/// `--write-scenario`: the answer's sites as the scenario's beacons.
pub(super) fn write_selected(
    a: &SelectArgs,
    cfg: &ScenarioConfig,
    sites: &[Site],
    criterion: SelectionCriterion,
    answer: &Selection,
    bound: f64,
    exact: Option<&BranchBoundReport>,
) -> Result<()> {
    let Some(path) = &a.write_scenario else {
        return Ok(());
    };
    let noise = template_noise(cfg, false)?;
    let chosen: Vec<Site> = answer.indices.iter().map(|&i| sites[i]).collect();
    let (_, text) = output::with_beacons(
        cfg,
        output::surface_beacons(&chosen, &noise),
        &file_stem(path),
        &format!(
            "Sites chosen by `entrynav optimize select` ({}, k = {}, grid {} deg{}): value {:.6}, certified gap {:.3e}.",
            criterion.name(),
            a.k,
            a.grid_deg,
            exact.map_or(String::new(), |e| format!(
                ", branch and bound: {}",
                e.status.name()
            )),
            answer.value,
            (bound - answer.value).max(0.0)
        ),
    )?;
    write_text(path, &text)?;
    println!("wrote {}", path.display());
    Ok(())
}
