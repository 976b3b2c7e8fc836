//! `entrynav optimize select --objective nav|pcrlb-avg|pcrlb-final`: k of the candidate sites
//! chosen on the nominal position bound (greedy + exchanges, no certificate: the bound is not
//! concave in the selection), checked against the input design like every optimum.
//!
//! Order: search, check, write files, print; exit code 1 when the check finds the answer worse.

use super::design_check::{DesignCheck, check_configs, print_check, verdict};
use super::ground_sites::{print_sites, scenario_sites, sites_json};
use super::names::SelectObjectiveArg;
use super::site_candidates::load_candidates;
use super::*;
use entrynav_optimizer::{LinCovFigures, LinCovScore};

pub(super) fn run_select_on_bound(a: &SelectArgs, objective: SelectObjectiveArg) -> Result<()> {
    let wall = Instant::now();
    if a.exact {
        bail!(
            "--exact certifies the convex criteria (logdet, min-eig) only; --objective {} has no \
             relaxation bound",
            objective.name()
        );
    }
    let (cfg, dir) = load::resolve(&a.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &a.sets)?;
    crate::exit::warn_implausible(&cfg);
    let own = scenario_sites(&cfg);
    let own_mask = cfg
        .beacons
        .iter()
        .find_map(|b| match b {
            BeaconConfig::Surface(c) => Some(c.elevation_mask_deg.unwrap_or(0.0)),
            BeaconConfig::Orbiter(_) => None,
        })
        .unwrap_or(0.0);
    let ground = GroundProblem::new(
        &cfg,
        &loader(&dir),
        a.k.max(1),
        objective.ground(),
        a.step,
        a.min_elevation_deg.to_radians(),
    )?
    .with_min_separation(a.min_separation_deg.to_radians())?
    .with_reference(&own, own_mask.to_radians())?;
    let candidates = load_candidates(a, &cfg, &ground)?;
    let mut sel = ground.select_on_bound(&candidates.sites)?;
    let lincov = match objective.lincov() {
        Some(figure) => {
            let filter = entrynav::estimation::nav::FilterKind::parse(&a.lincov_filter)?;
            let score = LinCovScore::new(ground.scenario(), filter, figure)?
                .with_reference(ground.beacons_masked(&own, own_mask.to_radians()))?;
            let l = ground.exchange_on_lincov(&candidates.sites, &sel.indices, &score)?;
            sel.indices = l.indices.clone();
            sel.value = l.value;
            Some((filter, score.reference(), l))
        }
        None => None,
    };
    let chosen: Vec<Site> = sel.indices.iter().map(|&i| candidates.sites[i]).collect();
    let noise = template_noise(&cfg, false)?;
    let stem = a
        .write_scenario
        .as_deref()
        .map_or_else(|| "selected".to_string(), file_stem);
    let (chosen_cfg, text) = output::with_beacons(
        &cfg,
        output::surface_beacons(&chosen, &noise),
        &stem,
        &format!(
            "Sites chosen by `entrynav optimize select --objective {}` (k = {}, grid {} deg, at \
             least {} deg apart; greedy + exchanges, no certificate): value {:.6}.",
            objective.name(),
            a.k,
            a.grid_deg,
            a.min_separation_deg,
            sel.value
        ),
    )?;
    let check = check_configs(&cfg, &chosen_cfg, &dir, objective.name(), &a.check)?;
    let series = ground.bound_series(&chosen)?;
    let input = ground.bound_series_masked(&own, own_mask.to_radians())?;
    let bounds = [
        (series.time_avg(), series.final_value()),
        (input.time_avg(), input.final_value()),
    ];
    // Files first, then the tables.
    if let Some(path) = &a.write_scenario {
        write_text(path, &text)?;
    }
    if let Some(path) = &a.json {
        let v = json!({
            "problem": "select",
            "scenario": cfg.name,
            "objective": objective.name(),
            "answer": "local search on the nominal bound (no certificate)",
            "value": sel.value,
            "sites": sites_json(&chosen),
            "k": a.k,
            "candidates": candidates.sites.len(),
            "grid_candidates": candidates.grid_count,
            "grid_deg": a.grid_deg,
            "evaluations": sel.evaluations,
            "exchanges": sel.exchanges,
            "wall_s": wall.elapsed().as_secs_f64(),
            "constraints": super::site_selection::constraints_json(a, 0),
            "nominal_bound": {
                "optimum": {"time_avg_pos_m": bounds[0].0, "final_pos_m": bounds[0].1},
                "input": {"time_avg_pos_m": bounds[1].0, "final_pos_m": bounds[1].1},
            },
            "check": check.as_ref().map(DesignCheck::json),
            "lincov": lincov.as_ref().map(|(f, input, l)| {
                let fig = |x: &LinCovFigures| json!({
                    "time_avg_pos_m": x.avg_m, "final_pos_m": x.final_m, "nees_dof": x.nees_ratio,
                });
                json!({
                    "objective": objective.name(),
                    "filter": f.name(),
                    "value": l.value,
                    "input": input.as_ref().map(fig),
                    "bound_selection": fig(&l.start_figures),
                    "optimum": fig(&l.figures),
                    "evaluations": l.evaluations,
                    "exchanges": l.exchanges,
                })
            }),
        });
        write_text(path, &(serde_json::to_string_pretty(&v)? + "\n"))?;
    }
    println!("scenario    {}", cfg.name);
    println!(
        "candidates  {} grid sites every {} deg visible during the whole entry, k = {}, at least \
         {} deg apart",
        candidates.grid_count, a.grid_deg, a.k, a.min_separation_deg
    );
    let units = match &lincov {
        Some((f, _, _)) => objective.lincov().map_or_else(String::new, |l| l.units(*f)),
        None => objective.ground().units(),
    };
    println!("objective   {}: {units}", objective.name());
    println!(
        "search      greedy + exchanges: {} bound evaluations, {} improving exchanges, {:.2} s; a \
         local optimum, no certificate (the bound is not concave in the selection)",
        sel.evaluations,
        sel.exchanges,
        wall.elapsed().as_secs_f64()
    );
    println!();
    println!("answer      {} = {:.6}", objective.name(), sel.value);
    print_sites(&chosen, None);
    for (label, (avg, last)) in [("answer", bounds[0]), ("input ", bounds[1])] {
        println!("  nominal position PCRLB, {label}: {avg:.2} m time-averaged, {last:.2} m final");
    }
    if let Some((f, input, l)) = &lincov {
        let fig = |x: &LinCovFigures| {
            format!(
                "{:.2} m time-averaged, {:.2} m final, NEES/dof {:.2}",
                x.avg_m, x.final_m, x.nees_ratio
            )
        };
        println!(
            "lincov      {} exchanges on LinCov of {} ({} evaluations): {}",
            l.exchanges,
            f.name(),
            l.evaluations,
            objective.name()
        );
        if let Some(i) = input {
            println!(
                "  predicted {} position RMSE, input:           {}",
                f.name(),
                fig(i)
            );
        }
        println!(
            "  predicted {} position RMSE, bound selection: {}",
            f.name(),
            fig(&l.start_figures)
        );
        println!(
            "  predicted {} position RMSE, answer:          {}",
            f.name(),
            fig(&l.figures)
        );
    }
    print_check(check.as_ref());
    for path in [&a.write_scenario, &a.json].into_iter().flatten() {
        println!("wrote {}", path.display());
    }
    verdict(check.as_ref())
}
