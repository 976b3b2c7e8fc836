//! The altitude safeguard (`[guidance] min_deploy_altitude_m`, `guidance::safeguard`): altitude
//! has priority over range. On the nominal MSL entry a range law that banks lift-down after peak
//! drag reaches the ground; wrapped in the safeguard it deploys at the floor. On dispersed entries with
//! perfect navigation, the safeguarded guidance fails (reaches the ground above the trigger speed)
//! no more often than the unguided reference bank and less often than without it.

#[path = "support/seed001_guided.rs"]
mod seed001_guided;

use entrynav::guidance::safeguard::AltitudeSafeguard;
use entrynav::guidance::{BankActuator, Guidance, GuidanceError, NavState};
use entrynav::scenario::Scenario;
use entrynav::sim::guided::delivery::{DeliveryRow, run_delivery};
use entrynav::sim::guided::guided_flight::{
    GuidedFlight, GuidedFlightError, GuidedFlightSettings, fly_perfect_navigation,
};

/// `msl-guided` on seed 001's dispersions (the safeguard's measurements were made on them).
fn msl(floor_m: Option<f64>) -> Scenario {
    let mut cfg = seed001_guided::seed001_guided_config();
    cfg.guidance.as_mut().unwrap().min_deploy_altitude_m = floor_m;
    Scenario::build(cfg, &entrynav::files::no_files).unwrap()
}

/// A range law that flies the 60° reference bank down to `0` m/s, then banks fully lift-down.
struct LiftDown(f64);

impl Guidance for LiftDown {
    fn command(&mut self, nav: &NavState) -> Result<f64, GuidanceError> {
        Ok(if nav.speed() > self.0 {
            60f64.to_radians()
        } else {
            std::f64::consts::PI
        })
    }
    fn name(&self) -> &'static str {
        "lift-down"
    }
}

/// Fly the nominal truth of `s` with perfect navigation and `guidance`.
fn fly_nominal(
    s: &Scenario,
    guidance: &mut dyn Guidance,
) -> Result<GuidedFlight, GuidedFlightError> {
    let cfg = s.config.guidance.as_ref().unwrap();
    let built = s.build_guidance().unwrap().unwrap();
    let truth = s.nominal_truth();
    let bank0 = cfg.reference_bank_deg.to_radians();
    fly_perfect_navigation(
        &truth.model,
        truth.initial,
        guidance,
        BankActuator::new(built.limits, bank0),
        &built.target,
        &GuidedFlightSettings {
            truth_step_s: s.config.timing.truth_step_s,
            guidance_period_s: cfg.period_s(),
            max_time_s: 1500.0,
            trigger: cfg.trigger,
            deploy_box: cfg.deploy_box,
        },
    )
}

#[test]
fn the_safeguard_keeps_a_lift_down_law_above_the_floor() {
    let s = msl(None);
    let built = s.build_guidance().unwrap().unwrap();
    // From the reference's peak drag on (where the safeguard starts to act), lift-down.
    let switch = built.reference.peak_drag_speed();
    // Unprotected, that reaches the ground above 450 m/s.
    let err = fly_nominal(&s, &mut LiftDown(switch)).unwrap_err();
    assert!(matches!(err, GuidedFlightError::NoTrigger { .. }), "{err}");
    let cfg = s.config.guidance.as_ref().unwrap();
    for floor_m in [2000.0, 5000.0] {
        let mut safe = AltitudeSafeguard {
            inner: Box::new(LiftDown(switch)),
            model: s.guidance_model().unwrap(),
            trigger: cfg.trigger,
            floor_m,
            limits: built.limits,
            density_scale: 1.0,
            max_time_s: 1500.0,
            active_below_mps: built.reference.peak_drag_speed(),
            period_s: cfg.period_s(),
            activations: 0,
            predictions: 0,
        };
        let f = fly_nominal(&s, &mut safe).unwrap_or_else(|e| panic!("floor {floor_m} m: {e}"));
        println!(
            "floor {floor_m} m: deployed at {:.0} m, t = {:.1} s, {} capped cycles, {} predictions",
            f.deploy_altitude_m, f.t_deploy, safe.activations, safe.predictions
        );
        assert!(safe.activations > 0);
        // Nominal truth = onboard model: the prediction is right to the predictor's step, the
        // bisection and the actuator's lag, so the deployment is at the floor, not far above it.
        assert!(
            f.deploy_altitude_m >= floor_m - 100.0 && f.deploy_altitude_m <= floor_m + 500.0,
            "floor {floor_m} m: deployed at {} m",
            f.deploy_altitude_m
        );
    }
}

fn row<'a>(rows: &'a [DeliveryRow], name: &str) -> &'a DeliveryRow {
    rows.iter().find(|r| r.name == name).unwrap()
}

#[test]
fn on_dispersed_entries_the_safeguard_fails_less_than_unguided_and_unprotected_guidance() {
    let (runs, floor_m) = (80, 800.0);
    let plain = run_delivery(&msl(None), &[], runs, 1, &|_| ()).unwrap();
    let safe = run_delivery(&msl(Some(floor_m)), &[], runs, 1, &|_| ()).unwrap();
    // Perfect-navigation runs that failed or deployed below the floor.
    let low = |r: &entrynav::sim::guided::delivery::DeliveryReport| {
        r.per_run
            .iter()
            .filter(|d| d[0].as_ref().map_or(true, |d| d.altitude_m < floor_m))
            .count()
    };
    let (p, s, u) = (
        row(&plain.rows, "perfect-nav"),
        row(&safe.rows, "perfect-nav"),
        row(&safe.rows, "unguided"),
    );
    println!(
        "{runs} runs: failures unprotected {}, safeguarded {}, unguided {}; failed or below \
         {floor_m} m {} -> {}; 99 % ellipse {:?} -> {:?}",
        p.failures,
        s.failures,
        u.failures,
        low(&plain),
        low(&safe),
        p.ellipse_99,
        s.ellipse_99
    );
    assert!(
        p.failures > 0,
        "the sample must contain unprotected failures"
    );
    assert!(s.failures < p.failures);
    assert!(s.failures <= u.failures);
    assert!(low(&safe) < low(&plain));
    assert!(s.rate_limit_held);
}
