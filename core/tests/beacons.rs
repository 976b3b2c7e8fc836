//! Integration tests of the beacons module: two-body propagation, constructions from the papers'
//! numbers (seeds 000, 002, 003), surface-beacon rotation, visibility tests and configuration.
//!
//! Measured numbers are printed; run with `--nocapture` to see them.

use entrynav::Planet;
use entrynav::beacons::{
    Beacon, BeaconConfig, BeaconError, BeaconMotion, CircularOrbit, KeplerElements, Orbiter,
    SurfaceBeacon, ground_visible, orbiter_visibility_margin, orbiter_visible,
};
use entrynav::frames::spherical_to_position;
use entrynav::math::{cross, dot, norm, sub};
use proptest::prelude::*;

const MARS: Planet = Planet::MARS;

fn energy(mu: f64, r: &[f64; 3], v: &[f64; 3]) -> f64 {
    0.5 * dot(v, v) - mu / norm(r)
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    norm(&sub(a, b))
}

fn angle_deg(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    norm(&cross(a, b)).atan2(dot(a, b)).to_degrees()
}

/// Seed 000 Table 2 orbiter 1 (km, m/s), inertial at t = 0.
fn seed000_orbiter1() -> Orbiter {
    Orbiter::from_state(
        &MARS,
        [7855.7e3, -461.8e3, 749.82e3],
        [66.2, 2206.4, -413.0],
    )
    .unwrap()
}

/// Largest relative drift of energy and angular momentum over `n` samples up to `t_end`.
fn invariant_drift(orb: &Orbiter, t_end: f64, n: usize) -> (f64, f64) {
    let mu = orb.mu();
    let (r0, v0) = orb.initial_state();
    let e0 = energy(mu, &r0, &v0);
    let h0 = cross(&r0, &v0);
    let (mut de, mut dh) = (0.0f64, 0.0f64);
    for k in 1..=n {
        let t = t_end * k as f64 / n as f64;
        let (r, v) = orb.state_at(t);
        de = de.max(((energy(mu, &r, &v) - e0) / e0).abs());
        dh = dh.max(dist(&cross(&r, &v), &h0) / norm(&h0));
    }
    (de, dh)
}

#[test]
fn elliptic_propagation_conserves_energy_and_angular_momentum() {
    let orb = seed000_orbiter1();
    let period = orb.period().expect("seed 000 orbiter 1 is bound");
    let (de, dh) = invariant_drift(&orb, 5.0 * period, 2000);
    println!(
        "elliptic (seed 000 orbiter 1, e = {:.3}, T = {period:.1} s) over 5 T: max rel energy drift {de:.2e}, max rel |h| drift {dh:.2e}",
        orb.eccentricity()
    );
    assert!(de < 1e-12 && dh < 1e-12, "energy {de:e}, h {dh:e}");

    // A more eccentric orbit, sampled without being commensurate with the period.
    let el = KeplerElements {
        a: 12_000e3,
        e: 0.7,
        inc: 0.8,
        raan: 2.0,
        argp: -1.0,
        true_anomaly: 0.3,
    };
    let orb = Orbiter::from_elements(&MARS, &el).unwrap();
    let (de, dh) = invariant_drift(&orb, 7.3 * orb.period().unwrap(), 3001);
    println!("elliptic e = 0.7 over 7.3 T: energy {de:.2e}, |h| {dh:.2e}");
    assert!(de < 1e-12 && dh < 1e-12, "energy {de:e}, h {dh:e}");
}

/// Classical RK4 of seed 003 eq. 8.
fn rk4_two_body(mu: f64, r0: [f64; 3], v0: [f64; 3], dt: f64, steps: usize) -> Vec<[f64; 6]> {
    let deriv = |x: &[f64; 6]| -> [f64; 6] {
        let r = [x[0], x[1], x[2]];
        let rn = norm(&r);
        let k = -mu / (rn * rn * rn);
        [x[3], x[4], x[5], k * x[0], k * x[1], k * x[2]]
    };
    let axpy = |x: &[f64; 6], a: f64, d: &[f64; 6]| -> [f64; 6] {
        std::array::from_fn(|i| x[i] + a * d[i])
    };
    let mut x = [r0[0], r0[1], r0[2], v0[0], v0[1], v0[2]];
    let mut out = vec![x];
    for _ in 0..steps {
        let k1 = deriv(&x);
        let k2 = deriv(&axpy(&x, 0.5 * dt, &k1));
        let k3 = deriv(&axpy(&x, 0.5 * dt, &k2));
        let k4 = deriv(&axpy(&x, dt, &k3));
        x = std::array::from_fn(|i| x[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        out.push(x);
    }
    out
}

fn max_rk4_deviation(orb: &Orbiter) -> (f64, f64) {
    let (r0, v0) = orb.initial_state();
    let dt = 0.1;
    let traj = rk4_two_body(orb.mu(), r0, v0, dt, 20_000);
    let (mut dr, mut dv) = (0.0f64, 0.0f64);
    for (k, x) in traj.iter().enumerate().step_by(10) {
        let (r, v) = orb.state_at(k as f64 * dt);
        dr = dr.max(dist(&r, &[x[0], x[1], x[2]]));
        dv = dv.max(dist(&v, &[x[3], x[4], x[5]]));
    }
    (dr, dv)
}

#[test]
fn agrees_with_rk4_integration() {
    // Seed 000 orbiters 1 and 2, seed 003's orbit, and seed 002's circular orbit at 725 km.
    let cases = [
        ("seed000 orbiter 1", seed000_orbiter1()),
        (
            "seed000 orbiter 2",
            Orbiter::from_state(
                &MARS,
                [3492.7e3, 3659.2e3, 215.11e3],
                [-605.1, 97.0, 3232.8],
            )
            .unwrap(),
        ),
        (
            "seed003 orbit",
            Orbiter::from_elements(&MARS, &seed003_elements()).unwrap(),
        ),
        (
            "seed002 circular 725 km",
            Orbiter::from_circular(
                &MARS,
                &CircularOrbit {
                    altitude: 725e3,
                    raan: 49.329f64.to_radians(),
                    inc: 24.209f64.to_radians(),
                    true_anomaly: 240.219f64.to_radians(),
                },
            )
            .unwrap(),
        ),
    ];
    for (name, orb) in &cases {
        let (dr, dv) = max_rk4_deviation(orb);
        println!(
            "{name}: max |Δr| vs RK4 (dt 0.1 s, 2000 s) = {dr:.3e} m, max |Δv| = {dv:.3e} m/s"
        );
        assert!(dr < 1e-6, "{name}: {dr} m");
        assert!(dv < 1e-9, "{name}: {dv} m/s");
    }
}

#[test]
fn returns_to_start_after_one_period() {
    let el = KeplerElements {
        a: 9_000e3,
        e: 0.45,
        inc: 1.1,
        raan: 0.4,
        argp: 2.5,
        true_anomaly: -2.0,
    };
    let orb = Orbiter::from_elements(&MARS, &el).unwrap();
    let t = orb.period().unwrap();
    let (r0, v0) = orb.initial_state();
    for n in [1.0, 2.0, -1.0, 10.0] {
        let (r, v) = orb.state_at(n * t);
        assert!(dist(&r, &r0) < 1e-6 && dist(&v, &v0) < 1e-9, "n = {n}");
    }
    // Half a period twice (no period reduction involved) also closes the orbit.
    let (rh, vh) = orb.state_at(0.5 * t);
    let half = Orbiter::from_state(&MARS, rh, vh).unwrap();
    let (r, v) = half.state_at(0.5 * t);
    let err = dist(&r, &r0);
    println!("two half-period legs close the orbit to {err:.3e} m");
    assert!(err < 1e-5 && dist(&v, &v0) < 1e-8);
    // Just before the period the state is close to the start (continuity of the reduction).
    let (r, _) = orb.state_at(t - 1e-3);
    assert!(dist(&r, &r0) < norm(&v0) * 1e-3 * 1.01);
}

#[test]
fn hyperbolic_and_parabolic_states_propagate() {
    let r0 = [4_000e3, 500e3, -200e3];
    let rn = norm(&r0);
    let vesc = (2.0 * MARS.mu / rn).sqrt();
    let dir = [0.3, 0.9, 0.2];
    let unit = dir.map(|x| x / norm(&dir));

    let hyp = Orbiter::from_state(&MARS, r0, unit.map(|x| 1.5 * vesc * x)).unwrap();
    assert!(hyp.period().is_none() && hyp.eccentricity() > 1.0 && hyp.specific_energy() > 0.0);
    let (de, dh) = invariant_drift(&hyp, 2.0e5, 2000);
    println!(
        "hyperbolic (e = {:.3}) over 2e5 s: energy {de:.2e}, |h| {dh:.2e}",
        hyp.eccentricity()
    );
    assert!(de < 1e-12 && dh < 1e-12);
    // Backwards in time as well, and against RK4.
    let (de, _) = invariant_drift(&hyp, -2.0e5, 500);
    assert!(de < 1e-12);
    let (dr, _) = max_rk4_deviation(&hyp);
    println!("hyperbolic: max |Δr| vs RK4 = {dr:.3e} m");
    assert!(dr < 1e-6);

    // Far out, a hyperbola is a straight line at v∞ = √(v² − v_esc²): |r| ≈ v∞ t (up to a
    // logarithmic term). Guards against the Newton iteration crawling on the exponential flank.
    for fac in [1.5, 5.0] {
        let orb = Orbiter::from_state(&MARS, r0, unit.map(|x| fac * vesc * x)).unwrap();
        let v_inf = vesc * (fac * fac - 1.0f64).sqrt();
        for t in [1e9, 1e12, -1e12] {
            let (r, v) = orb.state_at(t);
            let ratio = norm(&r) / (v_inf * t.abs());
            assert!(
                (ratio - 1.0).abs() < 1e-3,
                "fac {fac} t {t}: |r|/(v∞ t) = {ratio}"
            );
            assert!((norm(&v) / v_inf - 1.0).abs() < 1e-3);
        }
    }

    // Parabolic: energy 0 to rounding; compare |v|² − 2μ/r relative to 2μ/r.
    let par = Orbiter::from_state(&MARS, r0, unit.map(|x| vesc * x)).unwrap();
    for t in [-5e4, 10.0, 3.0e3, 1.0e5, 1.0e7] {
        let (r, v) = par.state_at(t);
        let scale = MARS.mu / norm(&r);
        let e = energy(MARS.mu, &r, &v);
        assert!(
            (e - par.specific_energy()).abs() < 1e-12 * scale,
            "t {t}: {e}"
        );
        assert!(
            dist(&cross(&r, &v), &par.angular_momentum()) < 1e-12 * norm(&par.angular_momentum())
        );
    }
    let (dr, _) = max_rk4_deviation(&par);
    assert!(dr < 1e-6, "parabolic vs RK4 {dr}");
}

#[test]
fn circular_construction_follows_seed002_eq55() {
    let alt = 725e3;
    let r_expect = MARS.radius + alt;
    for &(raan, inc, f) in &[
        (0.0, 0.0, 0.0),
        (49.329, 24.209, 240.219),
        (300.0, 170.0, -35.0),
    ] {
        let c = CircularOrbit {
            altitude: alt,
            raan: f64::to_radians(raan),
            inc: f64::to_radians(inc),
            true_anomaly: f64::to_radians(f),
        };
        let orb = Orbiter::from_circular(&MARS, &c).unwrap();
        let (r, v) = orb.initial_state();
        assert!((norm(&r) - r_expect).abs() < 1e-6);
        assert!((norm(&v) - (MARS.mu / r_expect).sqrt()).abs() < 1e-9);
        assert!(dot(&r, &v).abs() < 1e-6 * norm(&r) * norm(&v));
        assert!(orb.eccentricity() < 1e-12);
        // Orbit normal P × Q = [sin Ω sin i, −cos Ω sin i, cos i].
        let h = orb.angular_momentum();
        let hn = h.map(|x| x / norm(&h));
        let expect = [
            c.raan.sin() * c.inc.sin(),
            -c.raan.cos() * c.inc.sin(),
            c.inc.cos(),
        ];
        assert!(dist(&hn, &expect) < 1e-12);
        // Stays circular.
        let (r1, v1) = orb.state_at(1234.5);
        assert!((norm(&r1) - r_expect).abs() < 1e-6 && dot(&r1, &v1).abs() < 1e-3);
    }
    let orb = Orbiter::from_circular(
        &MARS,
        &CircularOrbit {
            altitude: alt,
            raan: 0.0,
            inc: 0.0,
            true_anomaly: 0.0,
        },
    )
    .unwrap();
    let (r, v) = orb.initial_state();
    assert!((r[0] - r_expect).abs() < 1e-6 && r[1] == 0.0 && r[2] == 0.0);
    assert!(v[0].abs() < 1e-12 && v[1] > 0.0 && v[2] == 0.0);
}

fn seed003_elements() -> KeplerElements {
    KeplerElements {
        a: 3700e3,
        e: 0.0,
        inc: 90f64.to_radians(),
        raan: 127.3f64.to_radians(),
        argp: 0.0,
        true_anomaly: 355f64.to_radians(),
    }
}

#[test]
fn seed003_table3_orbit() {
    let orb = Orbiter::from_elements(&MARS, &seed003_elements()).unwrap();
    let (r, v) = orb.initial_state();
    assert!((norm(&r) - 3700e3).abs() < 1e-6);
    assert!((norm(&v) - (MARS.mu / 3700e3).sqrt()).abs() < 1e-9);
    // Polar orbit: the normal lies in the equatorial plane, perpendicular to the node line.
    let h = orb.angular_momentum();
    assert!(h[2].abs() < 1e-9 * norm(&h));
    let node = [
        127.3f64.to_radians().cos(),
        127.3f64.to_radians().sin(),
        0.0,
    ];
    assert!(dot(&h, &node).abs() < 1e-9 * norm(&h));
    // f = 355°: 5° before the ascending node, so slightly south and moving north.
    assert!(r[2] < 0.0 && v[2] > 0.0);
    assert!((angle_deg(&r, &node) - 5.0).abs() < 1e-9);
    let period = orb.period().unwrap();
    assert!((period - std::f64::consts::TAU * (3700e3f64.powi(3) / MARS.mu).sqrt()).abs() < 1e-9);
}

#[test]
fn surface_beacon_turns_with_the_planet() {
    let b = SurfaceBeacon::from_fixed_position([3300e3, 420e3, 1350e3], &MARS).unwrap();
    let r0 = b.position_fixed();
    let quarter = std::f64::consts::FRAC_PI_2 / MARS.rotation_rate;
    for t in [0.0, 100.0, 5000.0, quarter, 1.0e5] {
        let (r, v) = b.state_at(t);
        assert!((norm(&r) - norm(&r0)).abs() < 1e-6);
        assert!((r[2] - r0[2]).abs() < 1e-9);
        let w = cross(&[0.0, 0.0, MARS.rotation_rate], &r);
        assert!(dist(&v, &w) < 1e-12);
    }
    let (r, _) = b.state_at(quarter);
    // A +90° rotation about +z maps (x, y) to (−y, x).
    assert!(dist(&r, &[-r0[1], r0[0], r0[2]]) < 1e-6, "{r:?}");
    // Latitude / longitude constructor agrees with the frames helper.
    let s = SurfaceBeacon::from_lat_lon_alt(0.3, -1.2, 2e3, &MARS).unwrap();
    let p = spherical_to_position(MARS.radius + 2e3, -1.2, 0.3);
    assert!(dist(&s.position_fixed(), &p) < 1e-9);
}

#[test]
fn ground_visibility_below_and_opposite() {
    let b =
        SurfaceBeacon::from_lat_lon_alt(-20.0f64.to_radians(), 40.0f64.to_radians(), 0.0, &MARS)
            .unwrap();
    let beacon = Beacon::Surface(b);
    let t = 150.0;
    let below = b.position_at(t);
    let up = below.map(|x| x / norm(&below));
    let vehicle = up.map(|x| x * (MARS.radius + 80e3));
    assert!(beacon.visible_from(vehicle, t, MARS.radius));
    let m = beacon.visibility_margin(vehicle, t, MARS.radius);
    assert!((m - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    let opposite = vehicle.map(|x| -x);
    assert!(!beacon.visible_from(opposite, t, MARS.radius));
    assert!(beacon.visibility_margin(opposite, t, MARS.radius) < 0.0);
    // Rotation matters: at t = 0 the beacon is elsewhere, 150 s later it has moved ≈ 0.6°.
    assert!(beacon.visibility_margin(vehicle, 0.0, MARS.radius) < m);
}

#[test]
fn orbiter_visibility_at_the_horizon() {
    let r_v = MARS.radius + 100e3;
    let r_b = MARS.radius + 725e3;
    let limit = (MARS.radius / r_v).acos() + (MARS.radius / r_b).acos();
    let vehicle = [r_v, 0.0, 0.0];
    for (delta, visible) in [(-1e-4, true), (1e-4, false)] {
        let a = limit + delta;
        let orb = [r_b * a.cos(), r_b * a.sin(), 0.0];
        assert_eq!(
            orbiter_visible(&orb, &vehicle, MARS.radius),
            visible,
            "delta {delta}"
        );
        assert!((orbiter_visibility_margin(&orb, &vehicle, MARS.radius) + delta).abs() < 1e-12);
    }
    // Below the surface the horizon angle clamps to zero instead of NaN.
    let buried = [MARS.radius - 10e3, 0.0, 0.0];
    let m = orbiter_visibility_margin(&[r_b, 0.0, 0.0], &buried, MARS.radius);
    assert!(m.is_finite() && (m - (MARS.radius / r_b).acos()).abs() < 1e-12);
}

proptest! {
    /// For two points outside the sphere, eq. 60 is exactly "the segment between them misses the sphere".
    #[test]
    fn orbiter_test_equals_segment_misses_sphere(
        a in prop::array::uniform3(-1.0f64..1.0), b in prop::array::uniform3(-1.0f64..1.0),
        ha in 1.0f64..3000e3, hb in 1.0f64..20000e3,
    ) {
        prop_assume!(norm(&a) > 1e-3 && norm(&b) > 1e-3);
        let pa = a.map(|x| x / norm(&a) * (MARS.radius + ha));
        let pb = b.map(|x| x / norm(&b) * (MARS.radius + hb));
        let d = sub(&pb, &pa);
        let s = (-dot(&pa, &d) / dot(&d, &d)).clamp(0.0, 1.0);
        let closest = [pa[0] + s * d[0], pa[1] + s * d[1], pa[2] + s * d[2]];
        let clearance = norm(&closest) - MARS.radius;
        prop_assume!(clearance.abs() > 10.0);
        prop_assert_eq!(orbiter_visible(&pb, &pa, MARS.radius), clearance > 0.0);
    }

    /// Propagating t1 then t2 equals propagating t1 + t2 (elliptic and hyperbolic).
    #[test]
    fn propagation_composes(
        dir in prop::array::uniform3(-1.0f64..1.0), vdir in prop::array::uniform3(-1.0f64..1.0),
        alt in 100e3f64..20000e3, vfac in 0.5f64..1.8, t1 in -3e4f64..3e4, t2 in -3e4f64..3e4,
    ) {
        prop_assume!(norm(&dir) > 1e-2 && norm(&vdir) > 1e-2);
        let r0 = dir.map(|x| x / norm(&dir) * (MARS.radius + alt));
        let vc = (MARS.mu / norm(&r0)).sqrt();
        let v0 = vdir.map(|x| x / norm(&vdir) * vfac * vc);
        prop_assume!(norm(&cross(&r0, &v0)) > 1e-3 * norm(&r0) * norm(&v0));
        let orb = Orbiter::from_state(&MARS, r0, v0).unwrap();
        let (r1, v1) = orb.state_at(t1);
        let mid = Orbiter::from_state(&MARS, r1, v1);
        prop_assume!(mid.is_ok()); // the conic may dip below the surface
        let (ra, va) = mid.unwrap().state_at(t2);
        let (rb, vb) = orb.state_at(t1 + t2);
        let scale = norm(&rb).max(norm(&r0));
        prop_assert!(dist(&ra, &rb) < 1e-8 * scale, "{} m", dist(&ra, &rb));
        prop_assert!(dist(&va, &vb) < 1e-8 * norm(&vb).max(vc));
    }
}

#[test]
fn seed000_beacons_are_all_hidden_from_the_vehicle() {
    // Seed 000 Table 1 truth start; at t = 0 planet-fixed = inertial.
    let vehicle = spherical_to_position(
        3518.2e3,
        (-89.872f64).to_radians(),
        (-28.02f64).to_radians(),
    );
    let beacons = [
        (
            "surface 1",
            Beacon::Surface(
                SurfaceBeacon::from_fixed_position([3300e3, 420e3, 1350e3], &MARS).unwrap(),
            ),
        ),
        (
            "surface 2",
            Beacon::Surface(
                SurfaceBeacon::from_fixed_position([3290e3, 570e3, 755e3], &MARS).unwrap(),
            ),
        ),
        ("orbiter 1", Beacon::Orbiter(seed000_orbiter1())),
        (
            "orbiter 2",
            Beacon::Orbiter(
                Orbiter::from_state(
                    &MARS,
                    [3492.7e3, 3659.2e3, 215.11e3],
                    [-605.1, 97.0, 3232.8],
                )
                .unwrap(),
            ),
        ),
    ];
    for (name, b) in &beacons {
        let (pos, _) = b.state_at(0.0);
        let angle = angle_deg(&vehicle, &pos);
        let margin = b.visibility_margin(vehicle, 0.0, MARS.radius);
        println!(
            "seed 000 {name}: {angle:.2}° from the vehicle, visibility margin {:.2}°",
            margin.to_degrees()
        );
        // As docs/references.md says: surface 1, surface 2 and orbiter 2 are at 106.2°, 104.4°
        // and 131.0° from the vehicle, orbiter 1 at 89.5° (hidden all the same: its eq. 60
        // margin is about −9.8°).
        let expected = if *name == "orbiter 1" {
            85.0..=95.0
        } else {
            100.0..=135.0
        };
        assert!(expected.contains(&angle), "{name}: {angle}°");
        assert!(!b.visible_from(vehicle, 0.0, MARS.radius), "{name}");
        if let Beacon::Surface(s) = b {
            assert!(!ground_visible(&s.position_fixed(), &vehicle));
        }
    }
}

// ---------------------------------------------------------------- configuration

#[derive(serde::Deserialize)]
struct File {
    beacons: Vec<BeaconConfig>,
}

fn parse(text: &str) -> Result<Vec<BeaconConfig>, String> {
    toml::from_str::<File>(text)
        .map(|f| f.beacons)
        .map_err(|e| e.to_string())
}

const GOOD: &str = r#"
[[beacons]]
name = "surface-1"
kind = "surface"
position_km = [3300.0, 420.0, 1350.0]
range_sigma_m = 4.4721
outages = [[200.0, 300.0]]

[[beacons]]
name = "ground-geo"
kind = "surface"
lat_deg = -25.0
lon_deg = -80.0
altitude_km = -1.5
range_sigma_m = 100.0

[[beacons]]
name = "orbiter-1"
kind = "orbiter"
position_km = [7855.7, -461.8, 749.82]
velocity_mps = [66.2, 2206.4, -413.0]
range_sigma_m = 6.3246
outages = [[200.0, inf]]

[[beacons]]
name = "orbiter-c"
kind = "orbiter"
circular = { altitude_km = 725.0, raan_deg = 49.329, inc_deg = 24.209, true_anomaly_deg = 240.219 }

[[beacons]]
name = "orbiter-e"
kind = "orbiter"
elements = { a_km = 3700, e = 0.0, inc_deg = 90, raan_deg = 127.3, argp_deg = 0, true_anomaly_deg = 355 }
range_sigma_m = 100.0
range_rate_sigma_mps = 0.1
"#;

#[test]
fn config_parses_validates_and_builds() {
    let cfgs = parse(GOOD).unwrap();
    assert_eq!(cfgs.len(), 5);
    for (i, c) in cfgs.iter().enumerate() {
        c.validate(&format!("beacons[{i}]")).unwrap();
    }
    let built: Vec<Beacon> = cfgs.iter().map(|c| c.build(&MARS).unwrap()).collect();
    assert_eq!(cfgs[0].name(), "surface-1");
    assert_eq!(cfgs[0].range_sigma_m(), Some(4.4721));
    assert_eq!(cfgs[0].range_rate_sigma_mps(), None);
    assert_eq!(cfgs[4].range_rate_sigma_mps(), Some(0.1));
    assert!(cfgs[0].in_outage(250.0) && !cfgs[0].in_outage(300.0) && !cfgs[0].in_outage(199.0));
    assert!(cfgs[2].in_outage(200.0) && cfgs[2].in_outage(1e6) && !cfgs[2].in_outage(199.9));

    let Beacon::Surface(s) = &built[0] else {
        panic!("surface expected")
    };
    assert_eq!(s.position_fixed(), [3300e3, 420e3, 1350e3]);
    let Beacon::Surface(g) = &built[1] else {
        panic!("surface expected")
    };
    assert!((norm(&g.position_fixed()) - (MARS.radius - 1.5e3)).abs() < 1e-6);
    assert!(built[2].is_orbiter() && built[3].is_orbiter());
    let (r, _) = built[3].state_at(0.0);
    assert!((norm(&r) - (MARS.radius + 725e3)).abs() < 1e-6);
    let (r, _) = built[4].state_at(0.0);
    assert!((norm(&r) - 3700e3).abs() < 1e-6);

    // Serialisation round trip.
    #[derive(serde::Serialize)]
    struct Out<'a> {
        beacons: &'a [BeaconConfig],
    }
    let text = toml::to_string(&Out { beacons: &cfgs }).unwrap();
    assert_eq!(parse(&text).unwrap(), cfgs);
}

#[test]
fn config_rejects_unknown_fields() {
    let e = parse(
        "[[beacons]]\nname = \"s\"\nkind = \"surface\"\nposition_km = [3300.0, 0.0, 0.0]\nrange_sigma = 3.0\n",
    )
    .unwrap_err();
    assert!(e.contains("range_sigma"), "{e}");
    let e = parse(
        "[[beacons]]\nname = \"o\"\nkind = \"orbiter\"\ncircular = { altitude_km = 725.0, raan_deg = 0.0, inc_deg = 0.0, true_anomaly_deg = 0.0, ecc = 0.1 }\n",
    )
    .unwrap_err();
    assert!(e.contains("ecc"), "{e}");
    assert!(parse("[[beacons]]\nname = \"x\"\nkind = \"satellite\"\n").is_err());
}

fn one(text: &str) -> BeaconConfig {
    parse(text).unwrap().remove(0)
}

fn field_error(c: &BeaconConfig, prefix: &str) -> String {
    c.validate(prefix).unwrap_err().to_string()
}

#[test]
fn config_rejects_two_alternatives() {
    let c = one(
        "[[beacons]]\nname = \"o\"\nkind = \"orbiter\"\nposition_km = [7855.7, -461.8, 749.82]\nvelocity_mps = [66.2, 2206.4, -413.0]\ncircular = { altitude_km = 725.0, raan_deg = 0.0, inc_deg = 0.0, true_anomaly_deg = 0.0 }\n",
    );
    let e = field_error(&c, "beacons[3]");
    assert!(
        e.contains("beacons[3]") && e.contains("exactly one") && e.contains("circular"),
        "{e}"
    );
    assert!(matches!(c.build(&MARS), Err(BeaconError::Choice { .. })));

    let c = one(
        "[[beacons]]\nname = \"s\"\nkind = \"surface\"\nposition_km = [3300.0, 0.0, 0.0]\nlat_deg = 1.0\nlon_deg = 2.0\naltitude_km = 0.0\n",
    );
    let e = field_error(&c, "beacons[0]");
    assert!(e.contains("not both"), "{e}");

    let c = one(
        "[[beacons]]\nname = \"o\"\nkind = \"orbiter\"\nposition_km = [7855.7, -461.8, 749.82]\n",
    );
    let e = field_error(&c, "beacons[1]");
    assert!(e.contains("velocity_mps"), "{e}");
    let c = one("[[beacons]]\nname = \"o\"\nkind = \"orbiter\"\n");
    assert!(field_error(&c, "beacons[1]").contains("found none"));
}

#[test]
fn config_range_errors_name_the_field() {
    let c = one(
        "[[beacons]]\nname = \"o\"\nkind = \"orbiter\"\ncircular = { altitude_km = -5.0, raan_deg = 0.0, inc_deg = 0.0, true_anomaly_deg = 0.0 }\n",
    );
    let e = field_error(&c, "beacons[2]");
    assert!(
        e.contains("beacons[2].circular.altitude_km") && e.contains("-5") && e.contains("> 0"),
        "{e}"
    );

    let c = one(
        "[[beacons]]\nname = \"s\"\nkind = \"surface\"\nposition_km = [3300.0, 0.0, 0.0]\nrange_sigma_m = 0.0\n",
    );
    let e = field_error(&c, "beacons[0]");
    assert!(
        e.contains("beacons[0].range_sigma_m") && e.contains("> 0"),
        "{e}"
    );
    let c = one(
        "[[beacons]]\nname = \"s\"\nkind = \"surface\"\nposition_km = [3300.0, 0.0, 0.0]\nrange_rate_sigma_mps = -0.1\n",
    );
    assert!(field_error(&c, "b").contains("b.range_rate_sigma_mps"));

    let c = one(
        "[[beacons]]\nname = \"s\"\nkind = \"surface\"\nposition_km = [3300.0, 0.0, 0.0]\noutages = [[10.0, 20.0], [300.0, 200.0]]\n",
    );
    let e = field_error(&c, "beacons[0]");
    assert!(
        e.contains("beacons[0].outages[1][1]") && e.contains("200"),
        "{e}"
    );
    let c = one(
        "[[beacons]]\nname = \"s\"\nkind = \"surface\"\nposition_km = [3300.0, 0.0, 0.0]\noutages = [[-1.0, 20.0]]\n",
    );
    assert!(field_error(&c, "beacons[0]").contains("beacons[0].outages[0][0]"));

    let c = one(
        "[[beacons]]\nname = \"o\"\nkind = \"orbiter\"\nelements = { a_km = 3700, e = 1.2, inc_deg = 90, raan_deg = 127.3, argp_deg = 0, true_anomaly_deg = 355 }\n",
    );
    let e = field_error(&c, "beacons[4]");
    assert!(
        e.contains("beacons[4].elements.e") && e.contains("[0, 1)"),
        "{e}"
    );
    let c = one(
        "[[beacons]]\nname = \"o\"\nkind = \"orbiter\"\nelements = { a_km = 3700, e = 0.0, inc_deg = 190, raan_deg = 127.3, argp_deg = 0, true_anomaly_deg = 355 }\n",
    );
    assert!(field_error(&c, "beacons[4]").contains("beacons[4].elements.inc_deg"));
    let c = one(
        "[[beacons]]\nname = \"s\"\nkind = \"surface\"\nlat_deg = 95.0\nlon_deg = 0.0\naltitude_km = 0.0\n",
    );
    assert!(field_error(&c, "beacons[0]").contains("beacons[0].lat_deg"));

    // Planet-dependent check happens at build: an orbiter inside the planet.
    let c = one(
        "[[beacons]]\nname = \"low\"\nkind = \"orbiter\"\nposition_km = [3000.0, 0.0, 0.0]\nvelocity_mps = [0.0, 3000.0, 0.0]\n",
    );
    c.validate("beacons[0]").unwrap();
    let e = c
        .build_with_prefix(&MARS, "beacons[0]")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("beacons[0].position_km") && e.contains("planet radius"),
        "{e}"
    );
    let e = c.build(&MARS).unwrap_err().to_string();
    assert!(e.contains("\"low\""), "{e}");
}
