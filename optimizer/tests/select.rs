//! Candidate-site selection (Joshi & Boyd relaxation by clarabel): on small instances the
//! relaxation bound is at least the brute-force optimum and every heuristic answer lies within
//! its reported gap; impossible requests are errors.

use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::select::site_information;
use entrynav_optimizer::{
    GroundObjective, GroundProblem, OptimizerError, SelectionCriterion, SelectionProblem,
};
use nalgebra::{Matrix3, Vector3};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};

fn no_files(p: &str) -> Result<String, entrynav::files::FileError> {
    Err(entrynav::files::FileError::new(p, "no files in tests"))
}

fn check(problem: &SelectionProblem, what: &str) {
    let report = problem.solve().unwrap();
    let brute = problem.brute_force(1_000_000).expect("small instance");
    let bound = report.relaxation.bound;
    let tol = 1e-6 * bound.abs().max(1.0);
    assert!(
        bound + tol >= brute.value,
        "{what}: bound {bound} below the brute-force optimum {}",
        brute.value
    );
    let rounded = report
        .rounded
        .as_ref()
        .expect("no side constraints: rounding succeeds");
    let greedy = report
        .greedy
        .as_ref()
        .expect("no side constraints: greedy succeeds");
    for (name, s) in [
        ("rounded", rounded),
        ("improved", &report.improved),
        ("greedy", greedy),
    ] {
        assert_eq!(s.indices.len(), problem.k());
        assert!(s.value <= brute.value + 1e-12, "{what} {name}");
        // The certified gap: the best k-subset is at most `gap` better.
        assert!(
            brute.value - s.value <= report.gap(s) + tol,
            "{what} {name}: optimum {} − value {} exceeds the gap {}",
            brute.value,
            s.value,
            report.gap(s)
        );
    }
    assert!(report.improved.value >= rounded.value);
    let z_sum: f64 = report.relaxation.z.iter().sum();
    assert!((z_sum - problem.k() as f64).abs() < 1e-5, "sum z = {z_sum}");
}

#[test]
fn bound_covers_brute_force_on_ground_beacon_candidates() {
    let cfg = ScenarioConfig::builtin("ground-beacons-3").unwrap();
    let ground = GroundProblem::new(&cfg, &no_files, 3, GroundObjective::LogDet, 2.0, 0.0).unwrap();
    let sites = ground.visible_grid(2.0).unwrap();
    assert!(
        sites.len() >= 10 && sites.len() <= 60,
        "{} candidates",
        sites.len()
    );
    for (criterion, epochs) in [
        (SelectionCriterion::LogDet, None),
        (SelectionCriterion::MinEig, None),
        (SelectionCriterion::MinEig, Some(30.0)),
    ] {
        let blocks = site_information(&ground, &sites, epochs).unwrap();
        let p = SelectionProblem::new(blocks, 3, criterion).unwrap();
        check(&p, &format!("ground {} {epochs:?}", criterion.name()));
    }
}

#[test]
fn bound_covers_brute_force_on_random_instances() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(2009);
    let mut uniform = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
    for trial in 0..4 {
        let m = 10;
        let blocks: Vec<Vec<Matrix3<f64>>> = (0..m)
            .map(|_| {
                (0..3)
                    .map(|_| {
                        let v = Vector3::new(uniform(), uniform(), uniform());
                        let w = Vector3::new(uniform(), uniform(), uniform());
                        v * v.transpose() + w * w.transpose() * 0.3
                    })
                    .collect()
            })
            .collect();
        for criterion in [SelectionCriterion::LogDet, SelectionCriterion::MinEig] {
            let p = SelectionProblem::new(blocks.clone(), 4, criterion).unwrap();
            check(&p, &format!("random {trial} {}", criterion.name()));
        }
    }
}

#[test]
fn impossible_selections_are_errors() {
    let blocks = vec![vec![Matrix3::identity()]; 5];
    let e = SelectionProblem::new(blocks.clone(), 6, SelectionCriterion::LogDet).unwrap_err();
    assert!(matches!(e, OptimizerError::Infeasible(_)), "{e}");
    assert!(e.to_string().contains("only 5 candidate"), "{e}");
    assert!(SelectionProblem::new(blocks, 0, SelectionCriterion::LogDet).is_err());
    let e = SelectionProblem::new(vec![], 1, SelectionCriterion::MinEig).unwrap_err();
    assert!(matches!(e, OptimizerError::Infeasible(_)), "{e}");
}
