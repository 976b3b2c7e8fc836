//! Orbiter geometry (seed 002 §5.2): the search reaches the documented optimum (239.845, above
//! the paper's Table 6 value 237.963) and the documented values of Table 6's elements, it is
//! reproducible from its seed, the closed-form circular motion is the core's two-body motion, and
//! impossible requests are errors.

use entrynav::beacons::BeaconMotion;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav_optimizer::orbiters::default_search;
use entrynav_optimizer::{
    OptimizerError, OrbitElements, OrbiterObjective, OrbiterProblem, SearchOptions, Trajectory,
    no_progress,
};

fn trajectory() -> Trajectory {
    let cfg = ScenarioConfig::builtin("orbiters-3").unwrap();
    let s = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    Trajectory::from_scenario(&s, 1.0).unwrap()
}

fn table6() -> Vec<OrbitElements> {
    vec![
        OrbitElements::from_degrees(49.329, 24.209, 240.219),
        OrbitElements::from_degrees(16.136, 35.889, 256.141),
        OrbitElements::from_degrees(36.562, 18.901, 229.294),
    ]
}

#[test]
fn orbiters_3_reaches_the_documented_239_845_above_the_papers_237_963() {
    let tr = trajectory();
    assert_eq!(tr.len(), 241);
    assert!((tr.duration() - 240.0).abs() < 1e-9);
    let p = OrbiterProblem::new(tr, 3, 725e3, None).unwrap();
    assert_eq!(p.objective(), OrbiterObjective::DetN3);
    assert!((p.upper_bound() - 240.0).abs() < 1e-9);
    let sol = p.optimize(&default_search(2), &no_progress).unwrap();
    let ev = &sol.evaluation;
    // docs/optimizer.md: 239.845 for seed 2 with the default search (upper bound 240), above
    // the paper's 237.963; the search is reproducible from its seed.
    assert!(
        (ev.value - 239.845).abs() < 5e-4,
        "objective {} is not the documented 239.845",
        ev.value
    );
    assert!(ev.value <= 240.0 + 1e-9);
    assert!(
        (ev.min_margin_rad.to_degrees() - 17.3).abs() < 0.05,
        "min visibility margin {} deg, documented 17.3",
        ev.min_margin_rad.to_degrees()
    );
    assert!(ev.min_margin_rad > 0.0 && ev.violation_rad_s == 0.0);
    assert!(sol.search.evaluations > 0);
    // The paper's Table 6 elements, evaluated by our objective on our trajectory.
    let paper = p.evaluate(&table6()).unwrap();
    assert!(
        (paper.value - 236.455).abs() < 5e-4 && paper.value < ev.value,
        "Table 6: {}, documented 236.455",
        paper.value
    );
    assert!(
        (paper.min_margin_rad.to_degrees() - 24.3).abs() < 0.05,
        "Table 6 margin {} deg, documented 24.3",
        paper.min_margin_rad.to_degrees()
    );
    for e in &sol.elements {
        assert!((0.0..=std::f64::consts::PI).contains(&e.inc));
    }
}

#[test]
fn the_same_seed_gives_the_same_constellation() {
    let p = OrbiterProblem::new(trajectory(), 3, 725e3, None).unwrap();
    let opts = SearchOptions {
        seed: 5,
        starts: 2,
        particles: 16,
        iterations: 20,
        polish_iterations: 50,
        polish_step: 0.02,
    };
    let a = p.optimize(&opts, &no_progress).unwrap();
    let b = p.optimize(&opts, &no_progress).unwrap();
    assert_eq!(a.elements, b.elements);
    assert_eq!(a.evaluation.value, b.evaluation.value);
    assert_eq!(a.search.evaluations, b.search.evaluations);
    // One thread or many: the same answer.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let c = pool.install(|| p.optimize(&opts, &no_progress).unwrap());
    assert_eq!(a.elements, c.elements);
    let d = p
        .optimize(&SearchOptions { seed: 6, ..opts }, &no_progress)
        .unwrap();
    assert_ne!(a.elements, d.elements);
}

#[test]
fn closed_form_circular_motion_is_the_core_two_body_motion() {
    let tr = trajectory();
    let planet = tr.planet;
    let p = OrbiterProblem::new(tr, 3, 725e3, None).unwrap();
    for el in table6() {
        let orbiter = el.orbiter(&planet, 725e3).unwrap();
        for k in [0, 60, 240] {
            let t = p.trajectory().times[k];
            let (core, _) = orbiter.state_at(t);
            let ours = p.orbiter_position(&el, k);
            for c in 0..3 {
                assert!(
                    (core[c] - ours[c]).abs() < 1e-3,
                    "t = {t}: {core:?} vs {ours:?}"
                );
            }
        }
    }
}

#[test]
fn impossible_requests_are_clear_errors() {
    let e = OrbiterProblem::new(trajectory(), 3, -10e3, None).unwrap_err();
    assert!(matches!(e, OptimizerError::Infeasible(_)), "{e}");
    assert!(e.to_string().contains("below the surface"), "{e}");
    let e = OrbiterProblem::new(trajectory(), 2, 725e3, None).unwrap_err();
    assert!(matches!(e, OptimizerError::Infeasible(_)), "{e}");
    let e = OrbiterProblem::new(trajectory(), 4, 725e3, Some(OrbiterObjective::DetN3)).unwrap_err();
    assert!(matches!(e, OptimizerError::InvalidInput(_)), "{e}");
    let p = OrbiterProblem::new(trajectory(), 3, 725e3, None).unwrap();
    assert!(p.evaluate(&table6()[..2]).is_err());
}

#[test]
fn four_orbiters_use_the_integrated_log_det() {
    let p = OrbiterProblem::new(trajectory(), 4, 725e3, None).unwrap();
    assert_eq!(p.objective(), OrbiterObjective::LogDet);
    let opts = SearchOptions {
        seed: 1,
        starts: 1,
        particles: 20,
        iterations: 30,
        polish_iterations: 100,
        polish_step: 0.02,
    };
    let sol = p.optimize(&opts, &no_progress).unwrap();
    assert!(sol.evaluation.value.is_finite());
    assert!(sol.evaluation.value <= p.upper_bound() + 1e-9);
    // Better than a constellation with everything on one orbit plane.
    let flat: Vec<OrbitElements> = (0..4)
        .map(|j| OrbitElements::from_degrees(0.0, 0.0, 90.0 * j as f64))
        .collect();
    assert!(sol.evaluation.value > p.evaluate(&flat).unwrap().value);
}

#[test]
fn pcrlb_objective_lowers_the_final_position_bound_below_the_geometric_optimum() {
    use entrynav_optimizer::OrbiterBoundProblem;
    use entrynav_optimizer::output::template_noise;
    let cfg = ScenarioConfig::builtin("orbiters-3").unwrap();
    let noise = template_noise(&cfg, true).unwrap();
    let proxy = OrbiterProblem::new(trajectory(), 3, 725e3, None).unwrap();
    let p = OrbiterBoundProblem::new(proxy, cfg.clone(), noise);
    // The objective is the bound a trade reports on the scenario as shipped (Table 6 orbiters).
    let own = p.final_position_bound(&table6()).unwrap();
    let s = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    let trade_bound = entrynav::sim::pcrlb_study(&s, 1, 1).unwrap().final_["pos_m"].unwrap();
    assert!(
        (own - trade_bound).abs() <= 1e-6 * trade_bound,
        "objective {own} m vs trade bound {trade_bound} m"
    );
    assert!(
        (own - 7.779).abs() < 5e-4,
        "Table 6 final position PCRLB {own} m, documented 7.779 m"
    );
    let proxy_opts = SearchOptions {
        seed: 2,
        starts: 2,
        particles: 20,
        iterations: 40,
        polish_iterations: 200,
        polish_step: 0.02,
    };
    let polish = SearchOptions {
        polish_iterations: 30,
        ..entrynav_optimizer::orbiters_bound::default_bound_polish(2)
    };
    let sol = p.optimize(&proxy_opts, &polish, &no_progress).unwrap();
    assert!(
        sol.bound_m <= sol.proxy_bound_m,
        "the polish never ends above its start: {} vs {} m",
        sol.bound_m,
        sol.proxy_bound_m
    );
    assert!(
        sol.bound_m < 0.95 * own,
        "bound-optimal orbiters {} m not below Table 6's {own} m",
        sol.bound_m
    );
    let again = p.final_position_bound(&sol.elements).unwrap();
    assert_eq!(
        again, sol.bound_m,
        "reported bound is the bound of the reported elements"
    );
}

#[test]
fn the_nominal_bound_objective_equals_the_core_bound_and_improves_on_table_6() {
    use entrynav_optimizer::{BoundFigure, OrbiterNavProblem};
    let s = Scenario::build(
        ScenarioConfig::builtin("orbiters-3").unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap();
    let geometry = OrbiterProblem::new(trajectory(), 3, 725e3, None).unwrap();
    let p = OrbiterNavProblem::new(geometry, &s, 50.0, BoundFigure::Navigation)
        .unwrap()
        .with_reference(&table6())
        .unwrap();
    // The input is the unit of the objective, and the problem's circular orbits reproduce the
    // scenario's own orbiters in the core's bound.
    assert!((p.value(&table6()).unwrap() - 1.0).abs() < 1e-12);
    let bound = entrynav::sim::bounds::nominal_bound::NominalBound::new(&s).unwrap();
    let times = bound.epoch_times();
    let positions: Vec<Vec<[f64; 3]>> = s
        .beacons
        .iter()
        .map(|b| times.iter().map(|t| b.position_at(*t)).collect())
        .collect();
    let core = bound.moving_sites(&[50.0; 3], &positions).unwrap();
    let mine = p.series(&table6()).unwrap();
    for (a, b) in mine.pos_m.iter().zip(&core.pos_m) {
        assert!((a - b).abs() <= 1e-6 * b, "{a} vs {b}");
    }
    let opts = SearchOptions {
        seed: 1,
        starts: 2,
        particles: 16,
        iterations: 20,
        polish_iterations: 100,
        polish_step: 0.02,
    };
    let sol = p.optimize(&opts, &|_, _| {}).unwrap();
    assert!(
        sol.value < 0.97,
        "nav {} not below the input's 1",
        sol.value
    );
}
