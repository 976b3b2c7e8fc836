//! The EKF linearisation's shortcuts against the plain evaluation: kinematics differentiated on
//! the six kinematic states and lifted to N, and the accelerometer triad shared by the axes.

use entrynav::math::{dual_gradient, seed_duals};
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sensors::channels::{kinematics, kinematics_ad};
use entrynav::sim::record_run;
use nalgebra::SVector;

/// Along the four-beacon-fusion entry (11 states), `kinematics_ad` gives the values and
/// gradients of `kinematics` on N-variable duals, and every channel evaluated with a shared triad
/// gives the value and gradient of its own evaluation, to the bit (`==`: zeros of either sign).
#[test]
fn lifted_kinematics_and_shared_triad_equal_the_plain_evaluation() {
    let cfg = ScenarioConfig::builtin("four-beacon-fusion").unwrap();
    let s = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    let model = s.filter_model();
    let rec = record_run(&s, 1, 0).unwrap();
    let mut x = SVector::<f64, 11>::from_column_slice(&rec.x0);
    let mut checked = 0;
    for k in 0..120 {
        let t = k as f64;
        let xd = seed_duals(&x);
        let (plain, lifted) = (kinematics(model, &xd, t), kinematics_ad(model, &x, &xd, t));
        for (a, b) in plain
            .pos
            .iter()
            .chain(&plain.vel)
            .zip(lifted.pos.iter().chain(&lifted.vel))
        {
            assert_eq!(a.re, b.re, "t = {t}");
            assert_eq!(dual_gradient(a), dual_gradient(b), "t = {t}");
        }
        assert_eq!(plain.density.re, lifted.density.re);
        assert_eq!(
            dual_gradient(&plain.density),
            dual_gradient(&lifted.density)
        );
        let beacons = s.beacon_states(t);
        let mut triad = None;
        for spec in &s.channels {
            let own = s
                .measurement
                .evaluate_with(model, &xd, &plain, 0.3, &beacons, spec.channel);
            let shared = s.measurement.evaluate_sharing_triad(
                model,
                &xd,
                &plain,
                0.3,
                &beacons,
                spec.channel,
                &mut triad,
            );
            assert_eq!(own.re, shared.re, "{:?}", spec.channel);
            assert_eq!(
                dual_gradient(&own),
                dual_gradient(&shared),
                "{:?}",
                spec.channel
            );
            checked += 1;
        }
        assert!(
            triad.is_some(),
            "the accelerometer channels filled the triad"
        );
        x = model.step(&x, 0.3, 1.0);
    }
    assert_eq!(checked, 120 * s.channels.len());
}
