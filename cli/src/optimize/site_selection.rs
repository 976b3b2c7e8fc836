//! `entrynav optimize select`: certified choice of k candidate sites (Joshi & Boyd relaxation
//! bound with clarabel, then local search; `--exact`: branch and bound, in
//! [`exact_selection`](super::exact_selection)).

use super::design_check::{DesignCheck, check_configs, print_check, verdict};
use super::exact_selection::{exact_json, finish_exact_only, print_proof, run_exact};
use super::ground_sites::sites_json;
use super::site_candidates::{Candidates, load_candidates};
use super::*;
use entrynav_optimizer::SelectionReport;

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

/// What the selection found: the heuristic report, the enumeration, the proof and the answers
/// certified.
struct Selected {
    report: SelectionReport,
    /// The exact optimum by enumeration, when there are few enough k-subsets.
    brute: Option<Selection>,
    /// `--exact`: the branch and bound.
    exact: Option<BranchBoundReport>,
    /// Each answer to certify, labelled.
    certified: Vec<(String, Selection)>,
    /// The answer's check against the input design (`None`: not run).
    check: Option<DesignCheck>,
}

impl Selected {
    /// The best bound known: the proof's, else the relaxation's. Gaps are measured from it.
    fn bound(&self) -> f64 {
        self.exact
            .as_ref()
            .map_or(self.report.relaxation.bound, |e| e.bound)
    }

    /// The answer: the proof's, else the swap-improved heuristic.
    fn answer(&self) -> &Selection {
        self.exact
            .as_ref()
            .map_or(&self.report.improved, |e| &e.best)
    }
}

pub(super) fn run_select(a: &SelectArgs) -> Result<()> {
    let wall = Instant::now();
    let (cfg, dir) = load::resolve(&a.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &a.sets)?;
    crate::exit::warn_implausible(&cfg);
    let criterion = SelectionCriterion::from(a.criterion);
    if a.eig_epochs.is_some() && criterion != SelectionCriterion::MinEig {
        bail!("--eig-epochs applies to --criterion min-eig only");
    }
    let ground = GroundProblem::new(
        &cfg,
        &loader(&dir),
        a.k.max(1),
        GroundObjective::LogDet,
        a.step,
        a.min_elevation_deg.to_radians(),
    )?;
    let candidates = load_candidates(a, &cfg, &ground)?;
    let (problem, pairs) = selection_problem(a, criterion, &ground, &candidates.sites)?;
    // The heuristic; with --exact the branch and bound can go on without it.
    let report = match problem.solve() {
        Ok(r) => r,
        Err(e) if a.exact => {
            // With its sources (a solver failure names clarabel's reason).
            let e = anyhow::Error::from(e);
            println!("note: the heuristic failed ({e:#}); branch and bound starts without it");
            return finish_exact_only(
                a,
                &cfg,
                &problem,
                &candidates.sites,
                candidates.grid_count,
                wall,
            );
        }
        Err(e) => return Err(e.into()),
    };
    let mut selected = certify(a, &problem, &candidates, report)?;
    let answer = selected.answer();
    let (chosen_cfg, text) = selected_scenario(
        a,
        &cfg,
        &candidates.sites,
        criterion,
        answer,
        selected.bound(),
        selected.exact.as_ref(),
    )?;
    selected.check = check_configs(&cfg, &chosen_cfg, &dir, criterion.name(), &a.check)?;
    print_select(a, &cfg, &problem, &candidates, pairs, &selected, wall);
    print_check(selected.check.as_ref());
    if let Some(path) = &a.write_scenario {
        write_text(path, &text)?;
        println!("wrote {}", path.display());
    }
    write_select_json(a, &cfg, &problem, &candidates, pairs, &selected, wall)?;
    verdict(selected.check.as_ref())
}

/// The information blocks of the candidates and the spacing constraints (with the number of
/// close pairs).
fn selection_problem(
    a: &SelectArgs,
    criterion: SelectionCriterion,
    ground: &GroundProblem,
    sites: &[Site],
) -> Result<(SelectionProblem, usize)> {
    let blocks = site_information(ground, sites, a.eig_epochs)?;
    let spacing = if a.min_separation_deg > 0.0 {
        separation_constraints(sites, a.min_separation_deg.to_radians())?
    } else {
        Vec::new()
    };
    let pairs = spacing.len();
    let problem = SelectionProblem::new(blocks, a.k, criterion)?
        .with_solver_verbose(a.solver_verbose)
        .with_constraints(spacing)?;
    Ok((problem, pairs))
}

/// Enumeration (within `--brute-force-limit`), the proof (`--exact`, from the heuristic
/// answer) and the values of the answers to certify.
fn certify(
    a: &SelectArgs,
    problem: &SelectionProblem,
    candidates: &Candidates,
    report: SelectionReport,
) -> Result<Selected> {
    let brute = problem.brute_force(a.brute_force_limit);
    let exact = if a.exact {
        Some(run_exact(a, problem, Some(&report.improved))?)
    } else {
        None
    };
    let certified = candidates
        .extra
        .iter()
        .map(|(label, idx)| {
            let s = Selection {
                indices: idx.clone(),
                value: problem.value(idx),
            };
            (label.clone(), s)
        })
        .collect();
    Ok(Selected {
        report,
        brute,
        exact,
        certified,
        check: None,
    })
}

/// One line per selection: value, gap from `bound` and sites (and whether it breaks the side
/// constraints).
pub(super) fn print_selection(
    label: &str,
    s: &Selection,
    sites: &[Site],
    bound: f64,
    problem: &SelectionProblem,
) {
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
}

/// The candidates, constraints, criterion and relaxation, then every selection and the proof.
fn print_select(
    a: &SelectArgs,
    cfg: &ScenarioConfig,
    problem: &SelectionProblem,
    candidates: &Candidates,
    pairs: usize,
    selected: &Selected,
    wall: Instant,
) {
    let (sites, grid_count) = (&candidates.sites, candidates.grid_count);
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
    if a.min_separation_deg > 0.0 || a.region.is_some() {
        let d = a.min_separation_deg;
        println!(
            "constraints {}{}",
            if d > 0.0 {
                format!("sites at least {d} deg apart ({pairs} closer pairs, z_i + z_j <= 1); ")
            } else {
                String::new()
            },
            a.region.as_ref().map_or(String::new(), |b| format!(
                "candidates inside lat [{}, {}], lon [{}, {}] deg",
                b[0], b[1], b[2], b[3]
            ))
        );
    }
    println!(
        "criterion   {} over k = {} of m = {} ({})",
        problem.criterion().name(),
        a.k,
        sites.len(),
        criterion_definition(problem.criterion(), a.eig_epochs)
    );
    let (report, r) = (&selected.report, &selected.report.relaxation);
    println!(
        "relaxation  bound {:.6} (primal {:.6}, dual {:.6}; clarabel {}, {} iterations, {:.3} s)",
        r.bound, r.primal, r.dual, r.status, r.iterations, r.solve_time_s
    );
    let bound = selected.bound();
    let show = |label: &str, s: &Selection| print_selection(label, s, sites, bound, problem);
    if let Some(s) = &report.rounded {
        show("rounded (top-k of z)", s);
    }
    show(
        if selected.exact.is_some() {
            "swap-improved (heuristic)"
        } else {
            "swap-improved (answer)"
        },
        &report.improved,
    );
    if let Some(s) = &report.greedy {
        show("greedy", s);
    }
    if let Some(b) = &selected.brute {
        show("brute force (exact optimum)", b);
    }
    if let Some(e) = &selected.exact {
        show("branch and bound (answer)", &e.best);
    }
    for (label, s) in &selected.certified {
        show(label, s);
    }
    println!(
        "            {} criterion evaluations, {:.3} s wall",
        report.evaluations,
        wall.elapsed().as_secs_f64()
    );
    if let Some(e) = &selected.exact {
        print_proof(a, e);
    }
}

/// What the criterion's value is, in words.
fn criterion_definition(criterion: SelectionCriterion, eig_epochs: Option<f64>) -> String {
    match (criterion, eig_epochs) {
        (SelectionCriterion::LogDet, _) =>
            "ln det of the time-averaged unit-sigma range FIM sum_i A_i, A_i = (1/T) integral n_i n_i^T dt (planet-fixed frame)".to_string(),
        (SelectionCriterion::MinEig, None) =>
            "lambda_min of the time-averaged unit-sigma range FIM".to_string(),
        (SelectionCriterion::MinEig, Some(s)) => format!(
            "min over epochs every {s} s of lambda_min of the instantaneous unit-sigma FIM sum n n^T"
        ),
    }
}

/// `--json`: the answer, the relaxation and its support, every selection and the proof.
fn write_select_json(
    a: &SelectArgs,
    cfg: &ScenarioConfig,
    problem: &SelectionProblem,
    candidates: &Candidates,
    pairs: usize,
    selected: &Selected,
    wall: Instant,
) -> Result<()> {
    let Some(path) = &a.json else {
        return Ok(());
    };
    let sites = &candidates.sites;
    let (report, r) = (&selected.report, &selected.report.relaxation);
    let (answer, bound, exact) = (selected.answer(), selected.bound(), &selected.exact);
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
        "objective": problem.criterion().name(),
        "eig_epochs_s": a.eig_epochs,
        "answer": if exact.is_some() { "exact" } else { "heuristic" },
        "value": answer.value,
        "sites": sites_json(&chosen),
        "bound": bound,
        "gap": (bound - answer.value).max(0.0),
        "k": a.k,
        "candidates": sites.len(),
        "grid_candidates": candidates.grid_count,
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
        "rounded": report.rounded.as_ref().map(|s| selection_json(s, sites, bound)),
        "greedy": report.greedy.as_ref().map(|s| selection_json(s, sites, bound)),
        "heuristic": selection_json(&report.improved, sites, bound),
        "brute_force": selected.brute.as_ref().map(|b| selection_json(b, sites, bound)),
        "certified": selected.certified.iter().map(|(label, s)| {
            let mut o = selection_json(s, sites, bound);
            o["label"] = json!(label);
            o["admissible"] = json!(problem.admissible(&s.indices));
            o
        }).collect::<Vec<_>>(),
        "constraints": constraints_json(a, pairs),
        "exact": exact.as_ref().map(|e| exact_json(a, e, sites)),
        "check": selected.check.as_ref().map(DesignCheck::json),
    });
    write_json(path, &v)
}

pub(super) fn constraints_json(a: &SelectArgs, pairs: usize) -> Value {
    json!({
        "min_separation_deg": (a.min_separation_deg > 0.0).then_some(a.min_separation_deg),
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
    let (_, text) = selected_scenario(a, cfg, sites, criterion, answer, bound, exact)?;
    write_text(path, &text)?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The scenario with the answer's sites as its beacons (configuration and file text).
fn selected_scenario(
    a: &SelectArgs,
    cfg: &ScenarioConfig,
    sites: &[Site],
    criterion: SelectionCriterion,
    answer: &Selection,
    bound: f64,
    exact: Option<&BranchBoundReport>,
) -> Result<(ScenarioConfig, String)> {
    let noise = template_noise(cfg, false)?;
    let chosen: Vec<Site> = answer.indices.iter().map(|&i| sites[i]).collect();
    let stem = a
        .write_scenario
        .as_deref()
        .map_or_else(|| "selected".to_string(), file_stem);
    Ok(output::with_beacons(
        cfg,
        output::surface_beacons(&chosen, &noise),
        &stem,
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
    )?)
}
