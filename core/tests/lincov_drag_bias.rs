//! Why CI's LinCov NEES on orbiters-3 is half the Monte Carlo's (issue 25, docs/results.md).
//!
//! orbiters-3 at its full dispersions (1 km, 0.5 m/s): each CI local filter has one orbiter's
//! range, so its error in the two directions that range does not see stays near the 1 km start
//! error. The filter predicts with its own drag, through the exponential density, at its own
//! estimate; a km-sized altitude error makes that drag biased to second order
//! (E\[e^{−δh/H}\] = e^{σ²/2H²} > 1), which LinCov, linear about the nominal, cannot carry. The
//! measurements below pin that mechanism: the Monte Carlo agrees with LinCov until the drag
//! rises, the gap is in the errors and not in the per-run onboard covariances, a mean error
//! LinCov does not predict carries a large share of it, and with the atmosphere a thousand
//! times thinner the two agree over the same epochs.

use entrynav::atmosphere::AtmosphereConfig;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::engine::record::record_run;
use entrynav::sim::lincov::{
    EntryLinCov, EntryLinCovEpoch, LinCovOptions, entry_lincov, entry_lincov_with,
};
use entrynav::sim::monte_carlo::run_record::filter_run;
use rayon::prelude::*;

/// orbiters-3 with both atmospheres' reference density times `rho`.
fn orbiters_3(rho: f64) -> Scenario {
    let mut cfg = ScenarioConfig::builtin("orbiters-3").unwrap();
    for a in [&mut cfg.truth.atmosphere, &mut cfg.filter.atmosphere] {
        match a {
            AtmosphereConfig::Exponential { rho_ref_kgm3, .. } => *rho_ref_kgm3 *= rho,
            other => panic!("orbiters-3's atmosphere is exponential, not {other:?}"),
        }
    }
    Scenario::build(cfg, &entrynav::files::no_files).unwrap()
}

/// Per LinCov epoch, over the Monte Carlo runs: the mean NEES/dof with each run's own onboard
/// covariance, the same errors' mean NEES/dof in LinCov's onboard covariance, and the NEES/dof
/// share of their mean error in that covariance.
struct Split {
    own: Vec<f64>,
    nominal: Vec<f64>,
    mean_share: Vec<f64>,
}

fn monte_carlo(s: &Scenario, l: &EntryLinCov, runs: usize) -> Split {
    let records: Vec<_> = (0..runs)
        .into_par_iter()
        .map(|r| filter_run(s, &s.onboard, &record_run(s, 1, r).unwrap(), FilterKind::Ci))
        .collect();
    let n = l.states.len();
    let k = l.epochs.len();
    let (mut own, mut nominal, mut count) = (vec![0.0; k], vec![0.0; k], vec![0usize; k]);
    let mut sum = vec![vec![0.0; n]; k];
    for rec in &records {
        assert!(rec.failure.is_none(), "{:?}", rec.failure);
        for (j, (e, lc)) in rec.epochs.iter().zip(&l.epochs).enumerate() {
            assert!((rec.times[j] - lc.t).abs() < 1e-9);
            let (nees, dof) = e.nees.unwrap();
            own[j] += nees / dof as f64;
            nominal[j] += lc.nees_of_mean(&e.err).unwrap();
            for (s, v) in sum[j].iter_mut().zip(&e.err) {
                *s += v;
            }
            count[j] += 1;
        }
    }
    let per =
        |v: &[f64]| -> Vec<f64> { v.iter().zip(&count).map(|(x, c)| x / *c as f64).collect() };
    let mean_share = (0..k)
        .map(|j| {
            let m: Vec<f64> = sum[j].iter().map(|v| v / count[j] as f64).collect();
            l.epochs[j].nees_of_mean(&m).unwrap_or(f64::NAN)
        })
        .collect();
    Split {
        own: per(&own),
        nominal: per(&nominal),
        mean_share,
    }
}

/// `f` at every epoch of `l`.
fn series(l: &EntryLinCov, f: impl Fn(&EntryLinCovEpoch) -> f64) -> Vec<f64> {
    l.epochs.iter().map(f).collect()
}

/// LinCov's own mean error's share of NEES/dof at an epoch.
fn own_mean_share(e: &EntryLinCovEpoch) -> f64 {
    e.nees_of_mean(&e.mean_error).unwrap()
}

/// Average of `v` over the epochs of `l` with `lo ≤ t ≤ hi`.
fn over(l: &EntryLinCov, v: &[f64], lo: f64, hi: f64) -> f64 {
    let sel: Vec<f64> = l
        .epochs
        .iter()
        .zip(v)
        .filter(|(e, _)| e.t >= lo && e.t <= hi)
        .map(|(_, x)| *x)
        .collect();
    assert!(sel.len() > 10, "{lo}..{hi}: {} epochs", sel.len());
    assert!(sel.iter().all(|x| x.is_finite()), "{lo}..{hi}: {sel:?}");
    sel.iter().sum::<f64>() / sel.len() as f64
}

#[test]
fn ci_nees_gap_on_orbiters_3_is_a_second_order_drag_bias() {
    const RUNS: usize = 1000;
    let s = orbiters_3(1.0);
    let l = entry_lincov(&s, FilterKind::Ci).unwrap();
    let predicted = series(&l, EntryLinCovEpoch::nees_per_dof);
    let lc_share = series(&l, own_mean_share);
    let mc = monte_carlo(&s, &l, RUNS);
    // Up to t = 40 s the aerodynamic acceleration stays below 1.5 m/s² (85 → 70 km): agreement.
    let (lc, own) = (
        over(&l, &predicted, 0.0, 40.0),
        over(&l, &mc.own, 0.0, 40.0),
    );
    eprintln!("to 40 s: LinCov {lc:.4}, MC {own:.4}");
    assert!(
        (lc / own - 1.0).abs() < 0.1,
        "before the drag: LinCov {lc} vs MC {own}"
    );
    // From t = 70 s (drag 50–130 m/s²) the Monte Carlo's NEES is about twice LinCov's (measured
    // with 500 runs of seed 1: 1.02 against 0.50 over the whole entry).
    let (lc, own) = (
        over(&l, &predicted, 70.0, 240.0),
        over(&l, &mc.own, 70.0, 240.0),
    );
    assert!(own > 1.8 * lc, "in the drag: LinCov {lc} vs MC {own}");
    // The gap is in the errors, not in the runs' own covariances: the same errors scored with
    // LinCov's onboard covariance give the same NEES.
    let nominal = over(&l, &mc.nominal, 70.0, 240.0);
    assert!(
        (nominal / own - 1.0).abs() < 0.05,
        "own P {own} vs LinCov's P {nominal}"
    );
    // A mean error LinCov does not predict carries a large share of it (measured 0.38–0.46 of
    // NEES/dof from 70 s; LinCov's own mean error is zero, the filter's models being the truth's).
    let (mc_share, lc_mean) = (
        over(&l, &mc.mean_share, 70.0, 240.0),
        over(&l, &lc_share, 70.0, 240.0),
    );
    eprintln!(
        "from 70 s: LinCov {lc:.4}, MC {own:.4} (in LinCov's P {nominal:.4}); mean-error share MC \
         {mc_share:.4}, LinCov {lc_mean:.2e}"
    );
    assert!(lc_mean < 1e-3, "LinCov's mean-error share {lc_mean}");
    assert!(
        mc_share > 0.25 && mc_share > 0.3 * (own - lc),
        "MC mean-error share {mc_share} of a gap {}",
        own - lc
    );

    // LinCov with the second-order mean (the locals' time update and measurements) predicts that
    // mean error and most of the gap (2000 runs of seed 1 over the whole entry: mean-error share
    // 0.328 vs 0.315, NEES/dof 0.828 vs 1.072, velocity RMSE −6 % instead of −15 %).
    let so = entry_lincov_with(
        &s,
        FilterKind::Ci,
        LinCovOptions {
            second_order_mean: true,
        },
    )
    .unwrap();
    let predicted = series(&so, EntryLinCovEpoch::nees_per_dof);
    let so_share = series(&so, own_mean_share);
    let (so_nees, so_mean) = (
        over(&so, &predicted, 70.0, 240.0),
        over(&so, &so_share, 70.0, 240.0),
    );
    eprintln!("second order, from 70 s: LinCov {so_nees:.4} (mean-error share {so_mean:.4})");
    assert!(
        (so_mean / mc_share - 1.0).abs() < 0.3,
        "second-order mean-error share {so_mean} vs MC {mc_share}"
    );
    // It closes more than half of the NEES gap (measured: 57 %, 0.883 against 1.205 and the first
    // order's 0.453), the rest being the extra spread (fourth moments) it does not carry.
    let closed = (so_nees - lc) / (own - lc);
    assert!(
        closed > 0.5 && so_nees < 1.1 * own,
        "second-order NEES/dof {so_nees} vs MC {own} (first order {lc}): {closed} of the gap"
    );

    // With the atmosphere a thousand times thinner (the same entry state; the drag reaches
    // 2 m/s² only at t ≈ 89 s) the same epochs agree: the nonlinearity is the drag's.
    let thin = orbiters_3(1e-3);
    let l = entry_lincov(&thin, FilterKind::Ci).unwrap();
    let predicted = series(&l, EntryLinCovEpoch::nees_per_dof);
    let mc = monte_carlo(&thin, &l, RUNS);
    let (lc, own) = (
        over(&l, &predicted, 0.0, 80.0),
        over(&l, &mc.own, 0.0, 80.0),
    );
    eprintln!("thin atmosphere, to 80 s: LinCov {lc:.4}, MC {own:.4}");
    assert!(
        (lc / own - 1.0).abs() < 0.1,
        "thin atmosphere: LinCov {lc} vs MC {own}"
    );
}
