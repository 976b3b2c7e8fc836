//! `entrynav optimize ground`: surface-beacon sites visible during the whole entry (seed 002 §4.1).

use super::*;

/// The scenario's surface beacons as sites (lat/lon/altitude or planet-fixed position).
pub(super) fn scenario_sites(cfg: &ScenarioConfig) -> Vec<Site> {
    let radius = cfg.planet.resolve().radius;
    cfg.beacons
        .iter()
        .filter_map(|b| match b {
            BeaconConfig::Surface(s) => match (s.lat_deg, s.lon_deg, s.position_km) {
                (Some(lat), Some(lon), _) => Some(Site {
                    altitude_m: s.altitude_km.unwrap_or(0.0) * 1e3,
                    ..Site::from_degrees(lat, lon)
                }),
                (_, _, Some(p)) => {
                    let p = p.map(|c| c * 1e3);
                    let (r, lon, lat) = entrynav::frames::position_to_spherical(&p);
                    Some(Site {
                        lat,
                        lon,
                        altitude_m: r - radius,
                    })
                }
                _ => None,
            },
            BeaconConfig::Orbiter(_) => None,
        })
        .collect()
}

pub(super) fn sites_json(sites: &[Site]) -> Value {
    Value::Array(
        sites
            .iter()
            .map(|s| {
                let [lat, lon] = s.degrees();
                json!({"lat_deg": lat, "lon_deg": lon})
            })
            .collect(),
    )
}

pub(super) fn print_sites(sites: &[Site], elevation: Option<&[f64]>) {
    println!(
        "  {:<6} {:>11} {:>11} {:>22}",
        "site", "lat [deg]", "lon [deg]", "min elevation [deg]"
    );
    for (k, s) in sites.iter().enumerate() {
        let [lat, lon] = s.degrees();
        let e = elevation
            .and_then(|e| e.get(k))
            .map_or(String::new(), |e| format!("{:.4}", e.to_degrees()));
        println!("  {:<6} {lat:>11.4} {lon:>11.4} {e:>22}", k + 1);
    }
}

struct DeltaStats {
    raw: DegreeSeries,
}

impl DeltaStats {
    fn min(&self, scaled: bool) -> f64 {
        self.raw.summary(scaled).map_or(0.0, |s| s.min)
    }
    fn max(&self, scaled: bool) -> f64 {
        self.raw.summary(scaled).map_or(0.0, |s| s.max)
    }
    fn json(&self) -> Value {
        let r = self.raw.summary(false);
        let s = self.raw.summary(true);
        json!({
            "method": self.raw.method.name(),
            "delta_raw_min": r.map(|m| m.min),
            "delta_raw_max": r.map(|m| m.max),
            "t_delta_raw_min_s": r.map(|m| m.t_min_s),
            "delta_scaled_min": s.map(|m| m.min),
            "delta_scaled_max": s.map(|m| m.max),
            "times_s": self.raw.times(),
            "delta_raw": self.raw.deltas(false),
            "delta_scaled": self.raw.deltas(true),
        })
    }
}

pub(super) fn run_ground(a: &GroundArgs) -> Result<()> {
    let wall = Instant::now();
    let c = &a.common;
    let (cfg, dir) = load::resolve(&c.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &c.sets)?;
    let own = scenario_sites(&cfg);
    let count = a
        .beacons
        .unwrap_or(if own.is_empty() { 3 } else { own.len() });
    let method = Method::from(a.method);
    let objective = match a.objective {
        GroundObjectiveArg::MinDelta => GroundObjective::MinDelta {
            method,
            scaled: a.scaled,
        },
        GroundObjectiveArg::Logdet => GroundObjective::LogDet,
        GroundObjectiveArg::MinEig => GroundObjective::MinEig,
        GroundObjectiveArg::Pcrlb => GroundObjective::Pcrlb,
    };
    let load = loader(&dir);
    let min_el = a.min_elevation_deg.to_radians();
    let search_problem = GroundProblem::new(&cfg, &load, count, objective, a.search_step, min_el)?;
    let report = GroundProblem::new(&cfg, &load, count, objective, a.step, min_el)?;
    let opts = c.search(ground::default_search(c.seed));
    let bar = progress_bar(c.quiet, format!("{} ground x{count}", cfg.name));
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let sol = search_problem.optimize(&opts, &progress)?;
    bar.finish_and_clear();

    // Report at the fine step: the objective and delta(t) of the optimum and of the scenario's
    // own sites (same count only).
    let ev = report.evaluate(&sol.sites)?;
    let delta = DeltaStats {
        raw: report.delta_series(&sol.sites, method)?,
    };
    let reference: Option<(GroundEvaluation, DeltaStats)> = if own.len() == count {
        let r_ev = report.evaluate(&own)?;
        let d = DeltaStats {
            raw: report.delta_series(&own, method)?,
        };
        Some((r_ev, d))
    } else {
        None
    };
    let paper = cfg.name == "ground-beacons-3";

    println!("scenario    {}", cfg.name);
    println!(
        "problem     {count} ground beacons on the reference sphere, each visible during the whole \
         entry (eq. 52, min elevation {:.3} deg)",
        a.min_elevation_deg
    );
    println!("objective   {}: {}", objective.name(), objective.units());
    println!(
        "            search on samples every {} s, reported every {} s",
        a.search_step, a.step
    );
    println!();
    let fmt_value = |v: Option<f64>| v.map_or("infeasible".to_string(), |v| format!("{v:.6e}"));
    println!("optimum     {} = {}", objective.name(), fmt_value(ev.value));
    print_sites(&sol.sites, Some(&ev.min_elevation_rad));
    println!(
        "  delta ({}) raw SI: min {:.4e}, max {:.4e};  scaled: min {:.4e}, max {:.4e}",
        method.name(),
        delta.min(false),
        delta.max(false),
        delta.min(true),
        delta.max(true)
    );
    if let Some((r, d)) = &reference {
        println!();
        println!(
            "scenario's own sites{}: {} = {}",
            if paper {
                " (hand-placed like seed 002 Fig. 4)"
            } else {
                ""
            },
            objective.name(),
            fmt_value(r.value)
        );
        print_sites(&own, Some(&r.min_elevation_rad));
        println!(
            "  delta ({}) raw SI: min {:.4e}, max {:.4e};  scaled: min {:.4e}, max {:.4e}",
            method.name(),
            d.min(false),
            d.max(false),
            d.min(true),
            d.max(true)
        );
    }
    if paper {
        println!();
        println!(
            "paper (seed 002 Sec. 5.1, its optimum): delta from 1.413e-8 to 2.945e-7 along the \
             entry (raw SI)"
        );
    }
    println!();
    println!(
        "units       raw SI delta: states r [m], lon, lat [rad], v [m/s], fpa, heading [rad], \
         outputs [m], Lie order k rows in m/s^k; scaled: {}",
        scaling_note(&report)
    );
    print_search(&sol.search, sol.elapsed_s, wall, &opts);

    if let Some(path) = &c.write_scenario {
        let name = file_stem(path);
        let (_, text) = output::with_beacons(
            &cfg,
            output::surface_beacons(&sol.sites, &report.noise()),
            &name,
            &format!(
                "Ground sites optimized by `entrynav optimize ground` ({}, seed {}): value {}.",
                objective.name(),
                opts.seed,
                fmt_value(ev.value)
            ),
        )?;
        write_text(path, &text)?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &a.plot {
        let pts = |d: &DegreeSeries| -> Vec<(f64, f64)> {
            d.times().into_iter().zip(d.deltas(false)).collect()
        };
        let mut curves = vec![crate::plot::Curve {
            name: format!("optimum (min {:.3e})", delta.min(false)),
            points: pts(&delta.raw),
            dashed: false,
        }];
        if let Some((_, d)) = &reference {
            curves.push(crate::plot::Curve {
                name: format!("scenario's sites (min {:.3e})", d.min(false)),
                points: pts(&d.raw),
                dashed: true,
            });
        }
        write_text(path, "")?;
        crate::plot::line_plot(
            path,
            &format!(
                "{}: raw SI δ = σmin/σmax ({}) along the entry",
                cfg.name,
                method.name()
            ),
            "time (s)",
            "δ (raw SI)",
            true,
            &curves,
        )?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &c.json {
        let v = json!({
            "problem": "ground",
            "scenario": cfg.name,
            "objective": objective.name(),
            "objective_units": objective.units(),
            "value": ev.value,
            "beacons": count,
            "sites": sites_json(&sol.sites),
            "min_elevation_deg": ev.min_elevation_rad.iter().map(|e| e.to_degrees()).collect::<Vec<_>>(),
            "delta": delta.json(),
            "evaluations": sol.search.evaluations,
            "elapsed_s": sol.elapsed_s,
            "wall_s": wall.elapsed().as_secs_f64(),
            "search": search_json(&sol.search, &opts),
            "search_step_s": a.search_step,
            "report_step_s": a.step,
            "delta_units": "raw SI: sigma_min/sigma_max of O with states in m, rad, m/s and outputs in m; scaled: see scaling",
            "scaling": scaling_note(&report),
            "reference": reference.as_ref().map(|(r, d)| json!({
                "source": format!("scenario {} surface beacons", cfg.name),
                "sites": sites_json(&own),
                "value": r.value,
                "min_elevation_deg": r.min_elevation_rad.iter().map(|e| e.to_degrees()).collect::<Vec<_>>(),
                "delta": d.json(),
            })),
            "paper_delta_range": paper.then(|| json!([1.413e-8, 2.945e-7])),
        });
        write_json(path, &v)?;
    }
    Ok(())
}

fn scaling_note(p: &GroundProblem) -> String {
    let s = p.scaling();
    let sizes: Vec<String> = s
        .state_names
        .iter()
        .zip(&s.state)
        .map(|(n, v)| format!("{n} {v:e}"))
        .collect();
    format!(
        "delta of W*O*D with characteristic sizes [{}], rows divided by the range noise 1-sigma, \
         Lie order k rows times ({} s)^k",
        sizes.join(", "),
        s.time_s
    )
}

// ---------------------------------------------------------------------------------------------
// select
