//! Branch and bound of the site selection against brute force: the same optimum on every
//! instance small enough to enumerate (ground-beacon grids and random blocks, k = 2..4, D- and
//! E-optimal, with and without side constraints), the issue-17 case (ground-beacons-3, 1° grid,
//! k = 3: −0.645375, which the heuristic misses), the same report on 1 and 2 threads, and the
//! proof status and errors.

use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::select::{
    AtMost, BranchBoundOptions, BranchBoundReport, ProofStatus, separation_constraints,
    site_information,
};
use entrynav_optimizer::{
    GroundObjective, GroundProblem, OptimizerError, SelectionCriterion, SelectionProblem, Site,
};
use nalgebra::{Matrix3, Vector3};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use std::time::Duration;

fn no_files(p: &str) -> Result<String, entrynav::files::FileError> {
    Err(entrynav::files::FileError::new(p, "no files here"))
}

fn ground(step_s: f64) -> GroundProblem {
    let cfg = ScenarioConfig::builtin("ground-beacons-3").unwrap();
    GroundProblem::new(&cfg, &no_files, 3, GroundObjective::LogDet, step_s, 0.0).unwrap()
}

fn exact(p: &SelectionProblem) -> BranchBoundReport {
    p.branch_and_bound(&BranchBoundOptions::default(), None, &|_| {})
        .unwrap()
}

/// The branch and bound proves the brute-force optimum (within the proof gap) and its bound
/// covers it.
fn agrees(p: &SelectionProblem, what: &str) -> BranchBoundReport {
    let brute = p.brute_force(2_000_000).expect("small instance");
    let r = exact(p);
    let tol = 1e-9 * brute.value.abs().max(1.0);
    assert_eq!(r.status, ProofStatus::Optimal, "{what}: {r:?}");
    assert!(r.gap <= r.proof_tolerance, "{what}: gap {}", r.gap);
    assert_eq!(r.proof_tolerance, p.tolerance(1e-6, r.best.value));
    assert!(
        r.best.value >= brute.value - r.proof_tolerance && r.best.value <= brute.value + tol,
        "{what}: branch and bound {} vs brute force {}",
        r.best.value,
        brute.value
    );
    assert!(r.bound + tol >= brute.value, "{what}: bound {}", r.bound);
    assert_eq!(r.best.indices.len(), p.k());
    assert!(p.admissible(&r.best.indices), "{what}");
    assert_eq!(r.best.value, p.value(&r.best.indices), "{what}");
    r
}

#[test]
fn equals_brute_force_on_ground_grids() {
    let g = ground(2.0);
    for grid in [3.0, 2.0, 1.5] {
        let sites = g.visible_grid(grid).unwrap();
        for (criterion, epochs) in [
            (SelectionCriterion::LogDet, None),
            (SelectionCriterion::MinEig, None),
            (SelectionCriterion::MinEig, Some(30.0)),
        ] {
            if epochs.is_some() && grid < 2.0 {
                continue;
            }
            let blocks = site_information(&g, &sites, epochs).unwrap();
            for k in 2..=4 {
                let p = SelectionProblem::new(blocks.clone(), k, criterion).unwrap();
                agrees(
                    &p,
                    &format!("grid {grid} {} {epochs:?} k {k}", criterion.name()),
                );
            }
        }
    }
}

#[test]
fn proves_the_issue_17_optimum_the_heuristic_misses() {
    // `optimize select --scenario ground-beacons-3 --k 3 --grid-deg 1`: 118 grid sites plus the
    // three hand-placed ones, D-optimal, 1 s samples.
    let g = ground(1.0);
    let mut sites = g.visible_grid(1.0).unwrap();
    assert_eq!(sites.len(), 118);
    sites.extend([
        Site::from_degrees(-23.5, -81.95),
        Site::from_degrees(-29.5, -81.35),
        Site::from_degrees(-25.6, -73.8),
    ]);
    let blocks = site_information(&g, &sites, None).unwrap();
    let p = SelectionProblem::new(blocks, 3, SelectionCriterion::LogDet).unwrap();
    let heuristic = p.solve().unwrap();
    assert!((heuristic.improved.value - -0.647923).abs() < 5e-7);
    let r = p
        .branch_and_bound(
            &BranchBoundOptions::default(),
            Some(&heuristic.improved),
            &|_| {},
        )
        .unwrap();
    let brute = p.brute_force(300_000).unwrap();
    assert_eq!(r.status, ProofStatus::Optimal);
    assert_eq!(r.best.indices, brute.indices);
    assert_eq!(r.best.value, brute.value);
    assert!((r.best.value - -0.645375).abs() < 5e-7, "{}", r.best.value);
    assert!(r.best.value > heuristic.improved.value + 2e-3);
}

fn random_blocks(seed: u64, m: usize, epochs: usize) -> Vec<Vec<Matrix3<f64>>> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut uniform = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
    (0..m)
        .map(|_| {
            (0..epochs)
                .map(|_| {
                    let v = Vector3::new(uniform(), uniform(), uniform());
                    let w = Vector3::new(uniform(), uniform(), uniform());
                    v * v.transpose() + w * w.transpose() * 0.3
                })
                .collect()
        })
        .collect()
}

#[test]
fn equals_brute_force_on_random_instances() {
    for trial in 0..4 {
        let blocks = random_blocks(17 + trial, 14, 3);
        for criterion in [SelectionCriterion::LogDet, SelectionCriterion::MinEig] {
            for k in 2..=4 {
                let p = SelectionProblem::new(blocks.clone(), k, criterion).unwrap();
                agrees(&p, &format!("random {trial} {} k {k}", criterion.name()));
            }
        }
    }
}

#[test]
fn side_constraints_equal_constrained_brute_force() {
    let g = ground(2.0);
    let sites = g.visible_grid(2.0).unwrap();
    let spacing = separation_constraints(&sites, 4.5f64.to_radians()).unwrap();
    assert!(spacing.len() > 10, "{} close pairs", spacing.len());
    for criterion in [SelectionCriterion::LogDet, SelectionCriterion::MinEig] {
        let blocks = site_information(&g, &sites, None).unwrap();
        for k in 2..=4 {
            let free = SelectionProblem::new(blocks.clone(), k, criterion).unwrap();
            let p = free.clone().with_constraints(spacing.clone()).unwrap();
            let r = agrees(&p, &format!("spacing {} k {k}", criterion.name()));
            // The spacing binds: the unconstrained optimum is not admissible.
            let best_free = free.brute_force(1_000_000).unwrap();
            assert!(!p.admissible(&best_free.indices) || r.best.value == best_free.value);
        }
    }
    // A group cap: at most one of the first half of random candidates.
    let blocks = random_blocks(5, 12, 2);
    let cap = vec![AtMost {
        sites: (0..6).collect(),
        max: 1,
    }];
    for criterion in [SelectionCriterion::LogDet, SelectionCriterion::MinEig] {
        let p = SelectionProblem::new(blocks.clone(), 4, criterion)
            .unwrap()
            .with_constraints(cap.clone())
            .unwrap();
        let r = agrees(&p, &format!("cap {}", criterion.name()));
        assert!(r.best.indices.iter().filter(|&&i| i < 6).count() <= 1);
    }
}

#[test]
fn same_report_on_one_and_two_threads() {
    // E-optimal k = 5 on the 1° grid: the incumbent improves during the search, so the order in
    // which nodes are evaluated matters (the node count depends on the batch size) — the case
    // where a thread-dependent fold would show.
    let g = ground(2.0);
    let sites = g.visible_grid(1.0).unwrap();
    let blocks = site_information(&g, &sites, None).unwrap();
    let p = SelectionProblem::new(blocks, 5, SelectionCriterion::MinEig).unwrap();
    let run = |threads: usize, batch: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let opts = BranchBoundOptions {
            batch,
            ..BranchBoundOptions::default()
        };
        let mut r = pool
            .install(|| p.branch_and_bound(&opts, None, &|_| {}))
            .unwrap();
        r.elapsed_s = 0.0;
        r
    };
    let one = run(1, 8);
    let two = run(2, 8);
    assert_eq!(one, two);
    assert!(one.incumbent_updates >= 2, "{one:?}");
    assert_ne!(one.nodes, run(1, 2).nodes, "order-insensitive instance");
}

#[test]
fn limits_report_a_certified_gap() {
    let g = ground(2.0);
    let sites = g.visible_grid(1.0).unwrap();
    let blocks = site_information(&g, &sites, Some(30.0)).unwrap();
    let p = SelectionProblem::new(blocks, 3, SelectionCriterion::MinEig).unwrap();
    let full = exact(&p);
    let opts = BranchBoundOptions {
        node_limit: Some(full.nodes / 3),
        ..BranchBoundOptions::default()
    };
    let r = p.branch_and_bound(&opts, None, &|_| {}).unwrap();
    assert_eq!(r.status, ProofStatus::NodeLimit);
    assert!(r.open > 0 && r.nodes <= full.nodes);
    assert!(r.bound >= full.best.value - 1e-12 && r.gap >= 0.0);
    assert!(r.best.value <= full.best.value + 1e-12);
    // A zero time limit still evaluates the first batch, so the bound is finite.
    let opts = BranchBoundOptions {
        time_limit: Some(Duration::ZERO),
        ..BranchBoundOptions::default()
    };
    let r = p.branch_and_bound(&opts, None, &|_| {}).unwrap();
    assert_eq!(r.status, ProofStatus::TimeLimit);
    assert!(r.bound.is_finite() && r.bound >= full.best.value - 1e-12);
    // A loose requested gap (E-optimal: relative to λ_min) stops early and keeps its promise.
    let opts = BranchBoundOptions {
        gap: 0.3 * (full.root_bound - full.best.value) / full.best.value,
        ..BranchBoundOptions::default()
    };
    let r = p.branch_and_bound(&opts, None, &|_| {}).unwrap();
    let promised = p.tolerance(opts.gap, r.best.value);
    assert!(matches!(r.status, ProofStatus::Gap | ProofStatus::Optimal));
    assert!(r.gap <= promised && r.best.value >= full.best.value - promised);
    assert!(r.nodes < full.nodes, "{} vs {} nodes", r.nodes, full.nodes);
}

#[test]
fn bad_requests_are_errors() {
    let blocks = random_blocks(3, 6, 1);
    let p = SelectionProblem::new(blocks.clone(), 3, SelectionCriterion::LogDet).unwrap();
    let wrong = entrynav_optimizer::Selection {
        indices: vec![0, 1],
        value: 0.0,
    };
    let e = p
        .branch_and_bound(&BranchBoundOptions::default(), Some(&wrong), &|_| {})
        .unwrap_err();
    assert!(matches!(e, OptimizerError::InvalidInput(_)), "{e}");
    let bad_gap = BranchBoundOptions {
        gap: f64::NAN,
        ..BranchBoundOptions::default()
    };
    assert!(p.branch_and_bound(&bad_gap, None, &|_| {}).is_err());
    // Pairwise exclusive candidates: no 3 of 6 can be chosen.
    let pairs = (0..6)
        .flat_map(|i| {
            (i + 1..6).map(move |j| AtMost {
                sites: vec![i, j],
                max: 1,
            })
        })
        .collect();
    let p = p.with_constraints(pairs).unwrap();
    let e = p
        .branch_and_bound(&BranchBoundOptions::default(), None, &|_| {})
        .unwrap_err();
    assert!(matches!(e, OptimizerError::Infeasible(_)), "{e}");
    assert!(p.brute_force(100).is_none());
    let e = SelectionProblem::new(blocks, 2, SelectionCriterion::LogDet)
        .unwrap()
        .with_constraints(vec![AtMost {
            sites: vec![9],
            max: 0,
        }])
        .unwrap_err();
    assert!(matches!(e, OptimizerError::InvalidInput(_)), "{e}");
}
