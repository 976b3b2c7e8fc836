//! `entrynav optimize orbiters`: orbiter elements (Ω, i, f) on circular orbits (seed 002 §4.2).

use super::design_check::{check_configs, print_check, verdict};
use super::lincov_polish::{self, LinCovStage};
use super::orbit_files::{export_trajectory, orbiter_scenario, plot_orbiters, write_orbiter_json};
use super::*;
use entrynav_optimizer::OrbiterNavProblem;
use entrynav_optimizer::OrbiterNavSolution;
use entrynav_optimizer::output::BeaconNoise;
use entrynav_optimizer::{OrbiterBoundSolution, OrbiterSolution};

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

pub(super) fn print_elements(el: &[OrbitElements]) {
    println!(
        "  {:<10} {:>10} {:>10} {:>10}",
        "orbiter", "RAAN [deg]", "i [deg]", "f [deg]"
    );
    for (k, e) in el.iter().enumerate() {
        let [raan, inc, f] = e.degrees();
        println!("  {:<10} {raan:>10.3} {inc:>10.3} {f:>10.3}", k + 1);
    }
}

/// What `optimize orbiters` starts from: the scenario, its own circular orbiters and the size
/// of the constellation to search.
pub(super) struct OrbiterInputs {
    pub(super) cfg: ScenarioConfig,
    pub(super) dir: PathBuf,
    /// The scenario's own orbiters on circular orbits: (altitude [m], elements).
    pub(super) own: Vec<(f64, OrbitElements)>,
    pub(super) count: usize,
    pub(super) altitude_m: f64,
}

/// The search on the nominal position bound.
pub(super) struct NavAnswer {
    /// Objective name (`nav`, `pcrlb-avg`, `pcrlb-final`).
    pub(super) objective: &'static str,
    pub(super) solution: OrbiterNavSolution,
    /// lincov-*: the polish of the bound's optimum on LinCov.
    pub(super) lincov: Option<LinCovStage>,
    /// The (time-averaged, final) bound of the scenario's own orbiters, when comparable.
    pub(super) own: Option<(f64, f64)>,
}

/// What the search found, and the scenario's own orbiters evaluated the same way.
pub(super) struct OrbiterAnswer {
    pub(super) problem: OrbiterProblem,
    pub(super) opts: SearchOptions,
    pub(super) noise: BeaconNoise,
    /// The geometric optimum (with `--objective pcrlb`, the proxy the polish started from).
    pub(super) sol: OrbiterSolution,
    /// `--objective pcrlb`: the polish on the final position PCRLB.
    pub(super) bound: Option<OrbiterBoundSolution>,
    /// `--objective pcrlb`: the bound of the scenario's own orbiters, when comparable.
    pub(super) own_bound: Option<f64>,
    /// The scenario's own orbiters (the paper's Table 6 for orbiters-3), when comparable.
    pub(super) reference: Option<(Vec<OrbitElements>, OrbiterEvaluation)>,
    /// `--objective nav|pcrlb-avg|pcrlb-final`: the search on the nominal bound, and the
    /// (time-averaged, final) bound of the scenario's own orbiters.
    pub(super) nav: Option<NavAnswer>,
}

impl OrbiterAnswer {
    /// The elements written to the scenario file: the PCRLB polish's, else the optimum's.
    pub(super) fn best_elements(&self) -> &[OrbitElements] {
        self.bound
            .as_ref()
            .map_or(&self.sol.elements, |b| &b.elements)
    }
}

pub(super) fn run_orbiters(a: &OrbitersArgs) -> Result<()> {
    let wall = Instant::now();
    let inputs = load_orbiter_inputs(a)?;
    let answer = solve_orbiters(a, &inputs)?;
    let written = orbiter_scenario(a, &inputs, &answer)?;
    let objective = match (&answer.bound, &answer.nav) {
        (Some(_), _) => "pcrlb",
        (None, Some(n)) => n.lincov.as_ref().map_or(n.objective, LinCovStage::name),
        (None, None) => answer.problem.objective().name(),
    };
    let check = check_configs(&inputs.cfg, &written.0, &inputs.dir, objective, &a.check)?;
    print_orbiters(&inputs, &answer, wall);
    print_check(check.as_ref());
    export_trajectory(a, &inputs, &answer)?;
    if let Some(path) = &a.common.write_scenario {
        write_text(path, &written.1)?;
        println!("wrote {}", path.display());
    }
    plot_orbiters(a, &inputs, &answer)?;
    write_orbiter_json(a, &inputs, &answer, check.as_ref(), wall)?;
    verdict(check.as_ref())
}

/// The scenario with its overrides, the orbiter count (default: the scenario's, at least 3) and
/// the altitude (default: the scenario's first circular orbiter).
fn load_orbiter_inputs(a: &OrbitersArgs) -> Result<OrbiterInputs> {
    let c = &a.common;
    let (cfg, dir) = load::resolve(&c.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &c.sets)?;
    crate::exit::warn_implausible(&cfg);
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
    Ok(OrbiterInputs {
        cfg,
        dir,
        own,
        count,
        altitude_m,
    })
}

/// The global search on the geometric objective, the PCRLB polish (`--objective pcrlb`) and the
/// evaluation of the scenario's own orbiters.
fn solve_orbiters(a: &OrbitersArgs, inputs: &OrbiterInputs) -> Result<OrbiterAnswer> {
    let c = &a.common;
    let cfg = &inputs.cfg;
    let on_bound = a.objective == Some(OrbiterObjectiveArg::Pcrlb);
    let objective = a.objective.and_then(OrbiterObjectiveArg::geometric);
    let scenario = load::build(cfg.clone(), &inputs.dir)?;
    let trajectory = Trajectory::from_scenario(&scenario, a.step)?;
    let problem = OrbiterProblem::new(trajectory, inputs.count, inputs.altitude_m, objective)?;
    let opts = c.search(orbiters::default_search(c.seed));
    let bar = progress_bar(c.quiet, format!("{} orbiters", cfg.name));
    bar.set_length(opts.budget(3 * inputs.count) as u64);
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let noise = template_noise(cfg, true)?;
    let bound_problem =
        on_bound.then(|| OrbiterBoundProblem::new(problem.clone(), cfg.clone(), noise));
    let bound = bound_problem
        .as_ref()
        .map(|b| {
            let polish = orbiters_bound::default_bound_polish(c.seed);
            b.optimize(&opts, &polish, &progress)
        })
        .transpose()?;
    let comparable = inputs.own.len() == inputs.count
        && inputs
            .own
            .iter()
            .all(|(alt, _)| (alt - inputs.altitude_m).abs() < 1e-6);
    let own_elements: Vec<OrbitElements> = inputs.own.iter().map(|(_, e)| *e).collect();
    // Default: `nav` against the scenario's own orbiters, or `pcrlb-avg` without comparable ones.
    let chosen = a.objective.unwrap_or(if comparable {
        OrbiterObjectiveArg::Nav
    } else {
        OrbiterObjectiveArg::PcrlbAvg
    });
    let nav = match chosen.bound_figure() {
        Some(figure) => {
            // The working scenario: the base with `count` orbiters at the altitude (their
            // places do not matter: the bound's set-up reads only the truth and the epochs).
            let mut working = cfg.clone();
            let placeholder: Vec<OrbitElements> = (0..inputs.count)
                .map(|k| OrbitElements::from_degrees(120.0 * k as f64, 45.0, 0.0))
                .collect();
            working.beacons = output::orbiter_beacons(&placeholder, inputs.altitude_m, &noise);
            let working = load::build(working, &inputs.dir)?;
            let p = OrbiterNavProblem::new(problem.clone(), &working, noise.range_sigma_m, figure)?;
            let p = if comparable || figure == entrynav_optimizer::BoundFigure::Navigation {
                if !comparable {
                    bail!(
                        "--objective nav is relative to the scenario's own {} orbiters at {} km, \
                         which '{}' does not have; use pcrlb-avg or pcrlb-final",
                        inputs.count,
                        inputs.altitude_m / 1e3,
                        cfg.name
                    );
                }
                p.with_reference(&own_elements)?
            } else {
                p
            };
            let mut s = p.optimize(&opts, &progress)?;
            let lincov = chosen
                .lincov_figure()
                .map(|figure| {
                    lincov_polish::polish_orbiters(
                        &p,
                        &working,
                        &mut s,
                        figure,
                        &a.lincov_filter,
                        comparable.then_some(own_elements.as_slice()),
                        &noise,
                        c.seed,
                        c.quiet,
                    )
                })
                .transpose()?;
            let own = comparable
                .then(|| {
                    p.series(&own_elements)
                        .map(|b| (b.time_avg(), b.final_value()))
                })
                .transpose()?;
            Some(NavAnswer {
                objective: figure.name(),
                solution: s,
                lincov,
                own,
            })
        }
        None => None,
    };
    let sol = match (&bound, &nav) {
        (Some(b), _) => b.proxy.clone(),
        (None, Some(n)) => OrbiterSolution {
            elements: n.solution.elements.clone(),
            evaluation: problem.evaluate(&n.solution.elements)?,
            search: n.solution.search.clone(),
            elapsed_s: n.solution.elapsed_s,
        },
        (None, None) => problem.optimize(&opts, &progress)?,
    };
    bar.finish_and_clear();
    let reference = comparable
        .then(|| {
            let el: Vec<OrbitElements> = inputs.own.iter().map(|(_, e)| *e).collect();
            problem.evaluate(&el).map(|ev| (el, ev))
        })
        .transpose()?;
    let own_bound = match (&bound_problem, &reference) {
        (Some(bp), Some((el, _))) => Some(bp.final_position_bound(el)?),
        _ => None,
    };
    Ok(OrbiterAnswer {
        problem,
        opts,
        noise,
        sol,
        bound,
        own_bound,
        reference,
        nav,
    })
}

/// The problem, the optimum, the scenario's own orbiters, the search and the PCRLB polish.
fn print_orbiters(inputs: &OrbiterInputs, answer: &OrbiterAnswer, wall: Instant) {
    let (cfg, problem, sol) = (&inputs.cfg, &answer.problem, &answer.sol);
    let traj = problem.trajectory();
    let ev = &sol.evaluation;
    println!("scenario    {}", cfg.name);
    println!(
        "problem     {} orbiters on circular orbits at {:.1} km (seed 002 eq. 55-56), \
         line of sight by eq. 58-60",
        inputs.count,
        inputs.altitude_m / 1e3
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
    if let Some((el, r)) = &answer.reference {
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
    print_search(&sol.search, sol.elapsed_s, wall, &answer.opts);
    if let Some(b) = &answer.bound {
        print_bound_polish(problem, b, answer.own_bound);
    }
    if let Some(n) = &answer.nav {
        println!();
        println!(
            "bound       objective {} on the nominal position PCRLB (full global search); the \
             geometric value above is reported for comparison",
            n.objective
        );
        println!(
            "optimum     {:.2} m time-averaged, {:.2} m final{}",
            n.solution.series.time_avg(),
            n.solution.series.final_value(),
            n.own.map_or(String::new(), |(a, f)| format!(
                "  (scenario's own orbiters: {a:.2} m, {f:.2} m)"
            ))
        );
        if let Some(l) = &n.lincov {
            l.print();
        }
    }
}

/// The `pcrlb` lines: the polished bound against the geometric optimum's and the scenario's.
fn print_bound_polish(problem: &OrbiterProblem, b: &OrbiterBoundSolution, own_bound: Option<f64>) {
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
