//! Position errors in metres in the local frame at the truth (downrange along the true heading,
//! crossrange, up): three orthogonal components of the position error, so their squares add up
//! to the total, per epoch and at the end, for spherical and Cartesian filter states.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::{McOptions, run_trade};

fn check(name: &str) {
    let s = Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap();
    let mut opts = McOptions::new(30, 2);
    opts.pcrlb = false;
    let r = run_trade(&s, &[FilterKind::Ekf], &opts, &|_| {}).unwrap();
    let f = &r.filters[0];
    let get = |k: &str| f.rmse_final[k].unwrap();
    let (pos, dr, cr, up) = (
        get("pos_m"),
        get("downrange_m"),
        get("crossrange_m"),
        get("up_m"),
    );
    let sum = dr * dr + cr * cr + up * up;
    assert!(
        (sum - pos * pos).abs() <= 1e-6 * pos * pos,
        "{name}: final {dr}² + {cr}² + {up}² = {sum} vs pos² {}",
        pos * pos
    );
    assert!(
        dr > 0.0 && cr > 0.0 && up > 0.0,
        "{name}: every component is measured"
    );
    let series = &f.series.local_rmse_m;
    assert_eq!(series.len(), 3);
    for (k, p) in f.series.pos_rmse_m.iter().enumerate() {
        let (Some(p), Some(a), Some(b), Some(c)) = (*p, series[0][k], series[1][k], series[2][k])
        else {
            continue;
        };
        let s2 = a * a + b * b + c * c;
        // Spherical states: the local frame is tangent at the truth, so the split is exact to
        // first order in the error (metres against a 3400 km radius).
        assert!(
            (s2 - p * p).abs() <= 1e-4 * p * p + 1e-9,
            "{name}: epoch {k}: {s2} vs {}",
            p * p
        );
    }
    for k in ["downrange_m", "crossrange_m", "up_m"] {
        assert!(
            f.rmse_time_avg[k].unwrap() > 0.0,
            "{name}: {k} time average"
        );
    }
}

#[test]
fn local_errors_add_up_to_the_position_error_spherical_states() {
    check("four-beacon-fusion");
}

#[test]
fn local_errors_add_up_to_the_position_error_cartesian_states() {
    check("orbiters-3");
}
