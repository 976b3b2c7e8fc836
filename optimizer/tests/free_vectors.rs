//! N free unit vectors without visibility: the search recovers seed 002's (N/3)³ (eq. 40,
//! Table 1) for N = 3..8.

use entrynav_optimizer::free_vectors::free_unit_vectors;
use entrynav_optimizer::{OptimizerError, SearchOptions, no_progress};

#[test]
fn recovers_n_over_3_cubed_for_3_to_8_vectors() {
    for n in 3..=8 {
        let opts = SearchOptions {
            seed: 11,
            starts: 2,
            particles: 30,
            iterations: 150,
            polish_iterations: 800,
            polish_step: 0.05,
        };
        let r = free_unit_vectors(n, &opts, &no_progress).unwrap();
        let bound = (n as f64 / 3.0).powi(3);
        assert_eq!(r.bound, bound);
        assert!(
            r.det <= bound * (1.0 + 1e-12),
            "N = {n}: det {} above the bound",
            r.det
        );
        assert!(
            r.det >= bound * (1.0 - 1e-6),
            "N = {n}: det {} vs (N/3)^3 = {bound} (rel. {:.2e})",
            r.det,
            1.0 - r.det / bound
        );
        for d in &r.directions {
            assert!(((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() - 1.0).abs() < 1e-12);
        }
    }
}

#[test]
fn fewer_than_three_vectors_is_infeasible() {
    let e = free_unit_vectors(2, &SearchOptions::default(), &no_progress).unwrap_err();
    assert!(matches!(e, OptimizerError::Infeasible(_)), "{e}");
}
