//! Dynamics acceptance tests: exact Jacobians vs finite differences, two-body conservation with
//! the atmosphere off, and agreement between the spherical and Cartesian formulations.

use entrynav::atmosphere::{Atmosphere, AtmosphereModel, Exponential};
use entrynav::dynamics::{AugmentedParam, DynamicsKind, EntryModel, Vehicle};
use entrynav::frames::{inertial_to_spherical, spherical_to_inertial};
use entrynav::math::fd_jacobian;
use entrynav::planet::Planet;
use nalgebra::{SMatrix, SVector};
use proptest::prelude::*;

const R0_KM: f64 = 3437.2;

fn exp_atmosphere(planet: &Planet) -> AtmosphereModel {
    AtmosphereModel::Exponential(
        Exponential::from_reference_radius(2e-4, R0_KM * 1e3, 7500.0, planet.radius)
            .expect("valid exponential"),
    )
}

fn model(kind: DynamicsKind, augmented: Vec<AugmentedParam>) -> EntryModel<AtmosphereModel> {
    let planet = Planet::MARS;
    EntryModel {
        kind,
        planet,
        atmosphere: exp_atmosphere(&planet),
        vehicle: Vehicle {
            cd_s_over_m: 0.016,
            lift_to_drag: 0.156,
        },
        augmented,
        rho0_model: 2e-4,
        density_factor: 1.0,
        bias_tau_s: None,
    }
}

/// Compare AD and central-difference Jacobians after scaling column j by the state's
/// characteristic size s_j: |J_ad − J_fd|_ij · s_j ≤ tol · (max_k |J_ik s_k| + floor).
fn assert_jacobians_agree<const N: usize>(
    ad: &SMatrix<f64, N, N>,
    fd: &SMatrix<f64, N, N>,
    scale: &SVector<f64, N>,
    tol: f64,
    what: &str,
) {
    for i in 0..N {
        let row_max = (0..N)
            .map(|k| (ad[(i, k)] * scale[k]).abs())
            .fold(0.0, f64::max);
        for j in 0..N {
            let err = ((ad[(i, j)] - fd[(i, j)]) * scale[j]).abs();
            assert!(
                err <= tol * (row_max + 1e-12),
                "{what}: d f{i}/d x{j}: AD {} vs FD {} (scaled err {err:e}, row scale {row_max:e})",
                ad[(i, j)],
                fd[(i, j)]
            );
        }
    }
}

fn spherical_state(alt_km: f64, lon: f64, lat: f64, v: f64, fpa: f64, psi: f64) -> [f64; 6] {
    [Planet::MARS.radius + alt_km * 1e3, lon, lat, v, fpa, psi]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn spherical_jacobians_match_finite_differences(
        alt in 10.0f64..130.0, lon in -3.1f64..3.1, lat in -1.2f64..1.2, v in 500.0f64..7000.0,
        fpa in -0.45f64..0.1, psi in -3.1f64..3.1, rho0 in 1e-4f64..4e-4, ld in 0.0f64..0.4,
        b in 0.004f64..0.03, bank in -1.0f64..1.0, rotating in any::<bool>(),
    ) {
        let kind = if rotating { DynamicsKind::SphericalRotating } else { DynamicsKind::Spherical };
        let m = model(kind, vec![AugmentedParam::Rho0, AugmentedParam::LiftToDrag, AugmentedParam::CdSOverM]);
        let s = spherical_state(alt, lon, lat, v, fpa, psi);
        let x = SVector::<f64, 9>::from([s[0], s[1], s[2], s[3], s[4], s[5], rho0, ld, b]);
        let (f, j) = m.jacobian(&x, bank);
        prop_assert!(f.iter().all(|v| v.is_finite()));
        let scale = SVector::<f64, 9>::from([1e3, 1e-3, 1e-3, 10.0, 1e-3, 1e-3, 1e-5, 1e-2, 1e-3]);
        let steps = scale * 1e-4;
        let fd = fd_jacobian(|y| m.rhs(y, bank), &x, &steps);
        assert_jacobians_agree(&j, &fd, &scale, 1e-6, "spherical");
    }

    #[test]
    fn cartesian_jacobians_match_finite_differences(
        alt in 10.0f64..130.0, lon in -3.1f64..3.1, lat in -1.2f64..1.2, v in 500.0f64..7000.0,
        fpa in -0.45f64..0.1, psi in -3.1f64..3.1, ld in 0.0f64..0.4, bank in -1.0f64..1.0, t in 0.0f64..300.0,
    ) {
        let m = model(DynamicsKind::Cartesian, vec![AugmentedParam::LiftToDrag]);
        let s = spherical_state(alt, lon, lat, v, fpa, psi);
        let (p, vel) = spherical_to_inertial(&s, t, m.planet.rotation_rate);
        let x = SVector::<f64, 7>::from([p[0], p[1], p[2], vel[0], vel[1], vel[2], ld]);
        let (_, j) = m.jacobian(&x, bank);
        let scale = SVector::<f64, 7>::from([1e3, 1e3, 1e3, 10.0, 10.0, 10.0, 1e-2]);
        let fd = fd_jacobian(|y| m.rhs(y, bank), &x, &(scale * 1e-4));
        assert_jacobians_agree(&j, &fd, &scale, 1e-6, "cartesian");
    }
}

/// Inertial specific energy and angular momentum of a model state at time t.
fn invariants(m: &EntryModel<AtmosphereModel>, x: &SVector<f64, 6>, t: f64) -> (f64, [f64; 3]) {
    let (p, v) = if m.kind.is_cartesian() {
        ([x[0], x[1], x[2]], [x[3], x[4], x[5]])
    } else {
        spherical_to_inertial(&[x[0], x[1], x[2], x[3], x[4], x[5]], t, m.omega())
    };
    let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let e = 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - m.planet.mu / r;
    let h = [
        p[1] * v[2] - p[2] * v[1],
        p[2] * v[0] - p[0] * v[2],
        p[0] * v[1] - p[1] * v[0],
    ];
    (e, h)
}

fn entry_start() -> [f64; 6] {
    // Seed 000 Table 1 truth.
    [
        3_518_200.0,
        (-89.872f64).to_radians(),
        (-28.02f64).to_radians(),
        5515.0,
        (-11.8f64).to_radians(),
        5.156f64.to_radians(),
    ]
}

fn initial_for(m: &EntryModel<AtmosphereModel>) -> SVector<f64, 6> {
    let s = entry_start();
    if m.kind.is_cartesian() {
        let (p, v) = spherical_to_inertial(&s, 0.0, m.omega());
        SVector::from([p[0], p[1], p[2], v[0], v[1], v[2]])
    } else {
        SVector::from(s)
    }
}

#[test]
fn atmosphere_off_conserves_energy_and_angular_momentum() {
    for kind in [
        DynamicsKind::Spherical,
        DynamicsKind::SphericalRotating,
        DynamicsKind::Cartesian,
    ] {
        let mut m = model(kind, vec![]);
        m.density_factor = 0.0; // atmosphere off
        let mut x = initial_for(&m);
        let (e0, h0) = invariants(&m, &x, 0.0);
        let h0n = (h0[0] * h0[0] + h0[1] * h0[1] + h0[2] * h0[2]).sqrt();
        let mut worst: (f64, f64) = (0.0, 0.0);
        for k in 1..=2400 {
            x = m.step(&x, 0.0, 0.1);
            let (e, h) = invariants(&m, &x, k as f64 * 0.1);
            let dh =
                ((h[0] - h0[0]).powi(2) + (h[1] - h0[1]).powi(2) + (h[2] - h0[2]).powi(2)).sqrt();
            worst.0 = worst.0.max(((e - e0) / e0).abs());
            worst.1 = worst.1.max(dh / h0n);
        }
        assert!(worst.0 < 1e-9, "{kind:?}: energy drift {:e}", worst.0);
        assert!(
            worst.1 < 1e-9,
            "{kind:?}: angular-momentum drift {:e}",
            worst.1
        );
    }
}

/// Propagate the same entry (atmosphere on) in the spherical and Cartesian formulations and
/// compare positions along the way.
fn max_position_difference(spherical_kind: DynamicsKind, omega: f64) -> f64 {
    let mut ms = model(spherical_kind, vec![]);
    let mut mc = model(DynamicsKind::Cartesian, vec![]);
    ms.planet.rotation_rate = omega;
    mc.planet.rotation_rate = omega;
    let mut xs = initial_for(&ms);
    let mut xc = initial_for(&mc);
    let mut worst: f64 = 0.0;
    for k in 1..=2400 {
        xs = ms.step(&xs, 0.3, 0.1);
        xc = mc.step(&xc, 0.3, 0.1);
        let t = k as f64 * 0.1;
        let (ps, _) = spherical_to_inertial(&[xs[0], xs[1], xs[2], xs[3], xs[4], xs[5]], t, omega);
        let d =
            ((ps[0] - xc[0]).powi(2) + (ps[1] - xc[1]).powi(2) + (ps[2] - xc[2]).powi(2)).sqrt();
        worst = worst.max(d);
    }
    // Sanity: the entry really decelerated (the atmosphere was on).
    let sc = inertial_to_spherical(&[xc[0], xc[1], xc[2]], &[xc[3], xc[4], xc[5]], 240.0, omega);
    assert!(
        sc[3] < 2500.0,
        "the vehicle should have slowed down, v = {}",
        sc[3]
    );
    worst
}

#[test]
fn spherical_and_cartesian_agree_to_a_metre() {
    let d_rot =
        max_position_difference(DynamicsKind::SphericalRotating, Planet::MARS.rotation_rate);
    let d_fix = max_position_difference(DynamicsKind::Spherical, 0.0);
    eprintln!(
        "max position difference over 240 s: rotating {d_rot:.3e} m, non-rotating {d_fix:.3e} m"
    );
    assert!(d_rot < 1.0, "rotating: {d_rot} m");
    assert!(d_fix < 1.0, "non-rotating: {d_fix} m");
}

#[test]
fn augmented_rho0_scales_density_and_states_are_constant() {
    let m = model(
        DynamicsKind::Spherical,
        vec![AugmentedParam::Rho0, AugmentedParam::LiftToDrag],
    );
    let s = entry_start();
    let x = SVector::<f64, 8>::from([s[0], s[1], s[2], s[3], s[4], s[5], 4e-4, 0.156]);
    let f = m.rhs(&x, 0.0);
    assert_eq!(f[6], 0.0);
    assert_eq!(f[7], 0.0);
    let rho = m.density(&x);
    let expect = 2.0 * m.atmosphere.density(s[0] - m.planet.radius);
    assert!((rho - expect).abs() < 1e-15 * expect.max(1e-30));
}

/// Largest scaled entry |ΔΦ_ij|·s_j / s_i of the difference of two transition matrices.
fn scaled_stm_difference<const N: usize>(
    a: &SMatrix<f64, N, N>,
    b: &SMatrix<f64, N, N>,
    scale: &SVector<f64, N>,
) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..N {
        for j in 0..N {
            worst = worst.max(((a[(i, j)] - b[(i, j)]) * scale[j] / scale[i]).abs());
        }
    }
    worst
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// The EKF's linearised transition matrix (Taylor polynomial of e^{hA}) against the exact
    /// Jacobian of the RK4 step (AD through the step): same mean, Φ within 1.5 % (scaled) at the
    /// filters' 1 s step, and converging faster than h² (A is taken at the step's midpoint).
    #[test]
    fn linearised_stm_matches_the_exact_rk4_jacobian(
        alt in 15.0f64..130.0, lat in -1.2f64..1.2, v in 1000.0f64..7000.0,
        fpa in -0.3f64..0.0, psi in -3.1f64..3.1, ld in 0.0f64..0.3, bank in -1.0f64..1.0,
        rotating in any::<bool>(),
    ) {
        let kind = if rotating { DynamicsKind::SphericalRotating } else { DynamicsKind::Spherical };
        let m = model(kind, vec![AugmentedParam::Rho0, AugmentedParam::LiftToDrag]);
        let s = spherical_state(alt, 0.3, lat, v, fpa, psi);
        let x = SVector::<f64, 8>::from([s[0], s[1], s[2], s[3], s[4], s[5], 2e-4, ld]);
        // Entry states a vehicle flies: deceleration below 15 g (the printed trajectories peak near 10 g).
        prop_assume!(m.rhs(&x, bank)[3].abs() < 150.0);
        let scale = SVector::<f64, 8>::from([1e3, 1e-3, 1e-3, 10.0, 1e-3, 1e-3, 1e-5, 1e-2]);
        let mut diffs = Vec::new();
        for h in [1.0, 0.1] {
            let (x_lin, phi_lin) = m.step_with_linear_stm(&x, bank, h);
            let (x_exact, phi_exact) = m.step_with_stm(&x, bank, h);
            let x_plain = m.step(&x, bank, h);
            for i in 0..8 {
                prop_assert!((x_lin[i] - x_plain[i]).abs() <= 1e-12 * x_plain[i].abs().max(scale[i]));
                prop_assert!((x_lin[i] - x_exact[i]).abs() <= 1e-12 * x_exact[i].abs().max(scale[i]));
            }
            diffs.push(scaled_stm_difference(&phi_lin, &phi_exact, &scale));
        }
        prop_assert!(diffs[0] < 1.5e-2, "h = 1 s: scaled |ΔΦ| = {:e}", diffs[0]);
        prop_assert!(diffs[1] < diffs[0] / 50.0 + 1e-12, "no convergence in h: {diffs:?}");
    }
}

/// What the range trigger reads the onboard dynamic pressure with: the filter's C_D S/m where it
/// estimates one (whatever its place among the augmented states), the vehicle's constant where
/// it does not or the estimate is not a usable coefficient.
#[test]
fn the_estimated_cd_s_over_m_is_the_augmented_state_else_the_vehicle_constant() {
    let x = [3.4e6, 0.1, 0.2, 5000.0, -0.2, 1.0, 0.25, 7.3e-3];
    let constant = model(DynamicsKind::Spherical, vec![]).vehicle.cd_s_over_m;
    let with = |augmented| model(DynamicsKind::Spherical, augmented);
    use AugmentedParam::{CdSOverM, LiftToDrag, Rho0};
    assert_eq!(with(vec![LiftToDrag, CdSOverM]).cd_s_over_m_of(&x), 7.3e-3);
    assert_eq!(with(vec![CdSOverM, LiftToDrag]).cd_s_over_m_of(&x), 0.25);
    assert_eq!(with(vec![LiftToDrag, Rho0]).cd_s_over_m_of(&x), constant);
    // Not carried by this estimate, non-positive or not finite: the constant.
    assert_eq!(
        with(vec![LiftToDrag, CdSOverM]).cd_s_over_m_of(&x[..7]),
        constant
    );
    for bad in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let mut y = x;
        y[7] = bad;
        assert_eq!(
            with(vec![LiftToDrag, CdSOverM]).cd_s_over_m_of(&y),
            constant
        );
    }
    assert_ne!(constant, 7.3e-3);
}
