//! The bank-angle command as a filter input (`NavFilter::set_bank_angle`): a filter told the bank
//! the vehicle flies tracks it, one left at the scenario's bank does not; telling a filter its
//! scenario's bank changes nothing; and telling it another bank is the same as building it on a
//! scenario with that bank. For every filter kind.

use entrynav::estimation::nav::{FilterKind, FilterStart, NavFilter, StepInfo, build_filter};
use entrynav::scenario::{Scenario, ScenarioConfig, TruthDraw};
use entrynav::sim::engine::judge::estimate_spherical;
use entrynav::sim::engine::start::initial_estimate;
use entrynav::sim::{TruthRun, run_seed, simulate_truth};
use entrynav::state_dim::{DimVisitor, with_state_dim};
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// Bank angle the vehicle flies in these tests [deg] (the built-in scenarios fly 0°).
const FLOWN_BANK_DEG: f64 = 60.0;

fn scenario(name: &str, bank_deg: f64) -> Arc<Scenario> {
    let mut cfg = ScenarioConfig::builtin(name).unwrap();
    cfg.truth.bank_deg = bank_deg;
    Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap())
}

const CASES: [(&str, &[FilterKind]); 3] = [
    (
        "four-beacon-fusion",
        &[
            FilterKind::Ekf,
            FilterKind::Ukf,
            FilterKind::Ci,
            FilterKind::Dcifaif,
        ],
    ),
    (
        "msl-pressure",
        &[FilterKind::Ekf, FilterKind::Mmae, FilterKind::MmaeMoe],
    ),
    (
        "msl-airdata",
        &[FilterKind::UkfCm, FilterKind::UkfAc, FilterKind::UskfNn],
    ),
];

/// A filter's state after one epoch, with the true spherical state at that epoch.
#[derive(Clone)]
struct NavStep<const N: usize> {
    t: f64,
    x: SVector<f64, N>,
    p: SMatrix<f64, N, N>,
    info: StepInfo,
    truth_spherical: [f64; 6],
}

/// A dispersed truth realisation of `truth_sc` (its bank) and the filter start of run 0.
fn truth<const N: usize>(
    truth_sc: &Scenario,
    filter_sc: &Scenario,
) -> (TruthDraw, TruthRun, FilterStart<N>) {
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(7, 0));
    let draw = truth_sc.draw_truth(&mut rng);
    let run = simulate_truth(truth_sc, &draw, &mut rng).unwrap();
    let x0 = initial_estimate(filter_sc, &draw, &run.samples[0], &mut rng);
    (
        draw,
        run,
        FilterStart::with_estimate(&filter_sc.onboard, &x0),
    )
}

/// Run `kind` on `filter_sc` over `run`, after `setup`; every step (the filter API directly:
/// predict to each epoch, update).
fn steps<const N: usize, const L: usize>(
    kind: FilterKind,
    filter_sc: &Arc<Scenario>,
    run: &TruthRun,
    start: &FilterStart<N>,
    setup: impl FnOnce(&mut dyn NavFilter<N>),
) -> Vec<NavStep<N>> {
    let mut f = build_filter::<N, L>(kind, &filter_sc.onboard, start).unwrap();
    setup(f.as_mut());
    let mut out = Vec::new();
    for (epoch, sample) in run.epochs_with_truth() {
        f.predict(epoch.t).unwrap();
        let info = f
            .update(epoch, &filter_sc.onboard.beacon_states(epoch.t))
            .unwrap();
        let (x, p) = f.estimate();
        out.push(NavStep {
            t: epoch.t,
            x,
            p,
            info,
            truth_spherical: sample.spherical,
        });
    }
    out
}

/// Position error [m] of a step's estimate (spherical, small-angle).
fn position_error<const N: usize>(sc: &Scenario, s: &NavStep<N>) -> f64 {
    let e = estimate_spherical(sc, &s.x, s.t);
    let tr = s.truth_spherical;
    let dr = e[0] - tr[0];
    let dn = tr[0] * (e[2] - tr[2]);
    let de = tr[0] * tr[2].cos() * (e[1] - tr[1]);
    (dr * dr + dn * dn + de * de).sqrt()
}

/// RMS over the run and final position error [m].
fn errors<const N: usize>(sc: &Scenario, steps: &[NavStep<N>]) -> (f64, f64) {
    assert!(steps.len() > 10);
    let rms = (steps
        .iter()
        .map(|s| position_error(sc, s).powi(2))
        .sum::<f64>()
        / steps.len() as f64)
        .sqrt();
    (rms, position_error(sc, steps.last().unwrap()))
}

fn assert_same<const N: usize>(a: &[NavStep<N>], b: &[NavStep<N>], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(x.t.to_bits(), y.t.to_bits(), "{what}: step {k}");
        assert!(
            x.x.iter()
                .zip(&y.x)
                .all(|(u, v)| u.to_bits() == v.to_bits()),
            "{what}: estimate differs at step {k}"
        );
        assert!(
            x.p.iter()
                .zip(&y.p)
                .all(|(u, v)| u.to_bits() == v.to_bits()),
            "{what}: covariance differs at step {k}"
        );
        assert_eq!(x.info, y.info, "{what}: step {k}");
    }
}

/// Position-error RMS and final error [m] of `kind` told the flown bank and left at 0°.
fn improvement<const N: usize, const L: usize>(
    name: &str,
    kind: FilterKind,
) -> ((f64, f64), (f64, f64)) {
    let bank = FLOWN_BANK_DEG.to_radians();
    // The filter's scenario says 0°; the vehicle flies FLOWN_BANK_DEG.
    let nominal = scenario(name, 0.0);
    let flown = scenario(name, FLOWN_BANK_DEG);
    let (_, run, start) = truth::<N>(&flown, &nominal);
    let wrong = steps::<N, L>(kind, &nominal, &run, &start, |_| {});
    let told = steps::<N, L>(kind, &nominal, &run, &start, |f| {
        assert_eq!(f.bank_angle(), 0.0);
        f.set_bank_angle(bank);
        assert_eq!(f.bank_angle(), bank);
    });
    (errors(&nominal, &told), errors(&nominal, &wrong))
}

struct Improvement<'a> {
    name: &'a str,
    kind: FilterKind,
}

impl DimVisitor for Improvement<'_> {
    type Output = ((f64, f64), (f64, f64));
    fn visit<const N: usize, const L: usize>(self) -> Self::Output {
        improvement::<N, L>(self.name, self.kind)
    }
}

struct Equivalence<'a> {
    name: &'a str,
    kind: FilterKind,
}

impl DimVisitor for Equivalence<'_> {
    type Output = ();
    fn visit<const N: usize, const L: usize>(self) {
        bank_equivalence::<N, L>(self.name, self.kind)
    }
}

#[test]
fn filter_told_the_flown_bank_tracks_the_truth() {
    for (name, kinds) in CASES {
        for &kind in kinds {
            let n = scenario(name, 0.0).filter_model().state_dim();
            let ((rms_t, fin_t), (rms_w, fin_w)) =
                with_state_dim(n, Improvement { name, kind }).unwrap();
            println!(
                "{name} {}: position error RMS {rms_t:.1} m (told {FLOWN_BANK_DEG}°) vs {rms_w:.1} m (left at 0°), final {fin_t:.1} vs {fin_w:.1} m",
                kind.name()
            );
            if name == "four-beacon-fusion" {
                // Two-way ranges to four beacons fix the position whatever the dynamics model:
                // the bank changes little here (RMS within a few metres of 30-60 m).
                assert!(
                    rms_t < 1.5 * rms_w,
                    "{name} {}: {rms_t} vs {rms_w} m",
                    kind.name()
                );
            } else {
                // Dead reckoning on IMU and air data: the wrong bank is kilometres off.
                assert!(
                    rms_t * 3.0 < rms_w && fin_t * 5.0 < fin_w,
                    "{name} {}: told {rms_t} / {fin_t} m, wrong bank {rms_w} / {fin_w} m",
                    kind.name()
                );
            }
        }
    }
}

/// `kind` on the flown scenario by default and told its own bank, and on the 0° scenario told
/// the flown bank: all three bitwise identical.
fn bank_equivalence<const N: usize, const L: usize>(name: &str, kind: FilterKind) {
    let nominal = scenario(name, 0.0);
    let flown = scenario(name, FLOWN_BANK_DEG);
    let (_, run, start) = truth::<N>(&flown, &nominal);
    let what = format!("{name} {}", kind.name());
    let default = steps::<N, L>(kind, &flown, &run, &start, |_| {});
    let same = steps::<N, L>(kind, &flown, &run, &start, |f| {
        assert_eq!(f.bank_angle(), flown.truth_bank);
        f.set_bank_angle(flown.truth_bank);
    });
    assert_same(&default, &same, &what);
    let told = steps::<N, L>(kind, &nominal, &run, &start, |f| {
        f.set_bank_angle(flown.truth_bank)
    });
    assert_same(&default, &told, &what);
}

#[test]
fn setting_the_scenario_bank_changes_nothing_and_another_bank_equals_that_scenario() {
    for (name, kinds) in CASES {
        for &kind in kinds {
            let n = scenario(name, 0.0).filter_model().state_dim();
            with_state_dim(n, Equivalence { name, kind }).unwrap();
        }
    }
}
