//! Monte Carlo of delivery at deployment (issue 28): N dispersed entries flown with each filter in
//! the guidance loop ([`super::guided_run`]), and per run the two references on the **same**
//! truth realisation — perfect navigation ([`super::guided_flight::fly_perfect_navigation`]) and
//! the unguided constant bank (the reference bank `guidance.reference_bank_deg`, the bank the
//! target was designed with) — reduced to miss statistics and the 99 % delivery ellipse.
//!
//! Reproducibility as the trade's ([`crate::sim::monte_carlo`]): run `r` draws its truth from
//! `run_seed(seed, r)` ([`crate::scenario::Scenario::draw_truth_run`]); runs execute in parallel
//! (rayon) and are reduced in run order, so any thread count gives the same report. A run that
//! fails (filter failure, no trigger before the truth stops) is counted with its reason, never
//! dropped silently; the statistics are over the runs that deployed.

use super::deployment::{Delivery, within_rate_limit};
use super::guided_flight::{GuidedFlightSettings, fly_perfect_navigation};
use super::guided_run::fly_with_filter;
use super::guided_run_error::GuidedRunError;
use crate::estimation::nav::FilterKind;
use crate::guidance::{BankActuator, Guidance, GuidanceError, NavState};
use crate::scenario::Scenario;
use crate::sim::engine::{EngineError, run_seed};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use std::sync::Arc;
use thiserror::Error;

/// χ²(2) quantile at 0.99: the 99 % ellipse of a 2-D Gaussian has semi-axes sqrt(9.2103·λ).
pub const CHI2_2_99: f64 = 9.2103;

/// Why a delivery study could not run.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DeliveryError {
    /// Run count out of range.
    #[error("runs = {0} is out of range: must be >= 1")]
    Runs(usize),
    /// The scenario cannot be flown in the loop.
    #[error(transparent)]
    Run(#[from] GuidedRunError),
    /// A filter does not fit the scenario.
    #[error(transparent)]
    Engine(#[from] EngineError),
}

/// The bank of the unguided reference: constant.
struct ConstantBank(f64);

impl Guidance for ConstantBank {
    fn command(&mut self, _: &NavState) -> Result<f64, GuidanceError> {
        Ok(self.0)
    }
    fn name(&self) -> &'static str {
        "constant"
    }
}

/// One run: the deliveries in row order ([`DeliveryReport::rows`]), or why each failed.
pub type RunDeliveries = Vec<Result<Delivery, GuidedRunError>>;

/// The 99 % delivery ellipse of the (downrange, crossrange) deployment errors.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DeliveryEllipse {
    /// Semi-major axis sqrt(9.2103·λ₁) \[m\].
    pub semi_major_m: f64,
    /// Semi-minor axis sqrt(9.2103·λ₂) \[m\].
    pub semi_minor_m: f64,
    /// Angle of the major axis from the downrange axis toward crossrange \[deg\].
    pub orientation_deg: f64,
}

/// Statistics of one row (a filter, `perfect-nav` or `unguided`) over the runs that deployed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DeliveryRow {
    /// `perfect-nav`, `unguided`, or the filter's name.
    pub name: String,
    /// Runs that deployed.
    pub deployed: usize,
    /// Runs that failed (counted, not dropped).
    pub failures: usize,
    /// The first failure (run index, reason).
    pub first_failure: Option<(usize, String)>,
    /// Mean miss distance \[m\].
    pub mean_miss_m: Option<f64>,
    /// RMS miss distance \[m\].
    pub rms_miss_m: Option<f64>,
    /// Median miss \[m\] (the middle of the sorted misses; the mean of the two middle ones
    /// for an even count).
    pub median_miss_m: Option<f64>,
    /// Largest miss \[m\].
    pub max_miss_m: Option<f64>,
    /// Mean downrange error \[m\].
    pub mean_downrange_m: Option<f64>,
    /// Mean crossrange error \[m\].
    pub mean_crossrange_m: Option<f64>,
    /// 99 % ellipse (at least two deployed runs).
    pub ellipse_99: Option<DeliveryEllipse>,
    /// Largest |bank rate| flown in any run \[deg/s\].
    pub max_bank_rate_deg_s: Option<f64>,
    /// Whether the bank rate stayed within the limit in every deployed run.
    pub rate_limit_held: bool,
    /// RMS of the position error at deployment over the runs (filters only) \[m\].
    pub rms_nav_position_error_m: Option<f64>,
    /// Mean over the deployed runs of the kinematic NEES at deployment (filters only; 6 for a
    /// consistent filter).
    pub mean_nees_kinematic: Option<f64>,
    /// The failed runs by cause (`GuidedRunError::cause`), in name order.
    pub failures_by_cause: std::collections::BTreeMap<String, usize>,
    /// Runs that deployed inside the deployment box (`guidance.deploy_box`, judged on the truth).
    pub inside_box: usize,
    /// The deployed runs outside the box, by broken limit (a run may break two), in name order.
    pub outside_box_by_limit: std::collections::BTreeMap<String, usize>,
}

/// A delivery study's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DeliveryReport {
    /// Scenario name.
    pub scenario: String,
    /// `apollo` or `fnpeg`.
    pub algorithm: String,
    /// Runs flown.
    pub runs: usize,
    /// Master seed.
    pub seed: u64,
    /// Bank rate limit \[deg/s\].
    pub bank_rate_limit_deg_s: f64,
    /// Rows: `perfect-nav`, `unguided`, then the filters in the order asked.
    pub rows: Vec<DeliveryRow>,
    /// Every run's deliveries in run order, one entry per row (for CSV; not in the JSON).
    #[serde(skip)]
    pub per_run: Vec<RunDeliveries>,
}

/// Fly run `run`: perfect navigation, unguided, then each filter, all on the truth realisation of
/// `run_seed(seed, run)`.
pub fn deliver_run(
    scenario: &Arc<Scenario>,
    filters: &[FilterKind],
    seed: u64,
    run: usize,
) -> RunDeliveries {
    let mut out = Vec::with_capacity(filters.len() + 2);
    for constant in [false, true] {
        out.push(reference_run(scenario, seed, run, constant));
    }
    for &kind in filters {
        out.push(fly_with_filter(scenario, kind, seed, run));
    }
    out
}

/// The perfect-navigation (`constant = false`) or unguided reference of run `run`.
fn reference_run(
    scenario: &Scenario,
    seed: u64,
    run: usize,
    constant: bool,
) -> Result<Delivery, GuidedRunError> {
    let name = || scenario.config.name.clone();
    let cfg = scenario
        .config
        .guidance
        .as_ref()
        .ok_or_else(|| GuidedRunError::NoGuidance(name()))?;
    let mut built = scenario
        .build_guidance()
        .ok_or_else(|| GuidedRunError::NoGuidance(name()))??;
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(seed, run as u64));
    let draw = scenario.draw_truth_run(run, &mut rng);
    let bank0 = cfg.reference_bank_deg.to_radians();
    let mut fixed = ConstantBank(bank0);
    let guidance: &mut dyn Guidance = if constant {
        &mut fixed
    } else {
        built.guidance.as_mut()
    };
    let timing = &scenario.config.timing;
    let flight = fly_perfect_navigation(
        &draw.model,
        draw.initial,
        guidance,
        BankActuator::new(built.limits, bank0),
        &built.target,
        &GuidedFlightSettings {
            truth_step_s: timing.truth_step_s,
            guidance_period_s: cfg.period_s(),
            max_time_s: timing.duration_s,
            trigger: cfg.trigger,
            deploy_box: cfg.deploy_box,
        },
    )?;
    Ok(Delivery::from_flight(&flight, &cfg.deploy_box))
}

/// Run a delivery study: `runs` runs from `seed`, perfect navigation, unguided and `filters`;
/// `progress(done)` is called as runs finish (in no particular order).
pub fn run_delivery(
    scenario: &Scenario,
    filters: &[FilterKind],
    runs: usize,
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<DeliveryReport, DeliveryError> {
    if runs == 0 {
        return Err(DeliveryError::Runs(runs));
    }
    let name = scenario.config.name.clone();
    let cfg = scenario
        .config
        .guidance
        .as_ref()
        .ok_or_else(|| GuidedRunError::NoGuidance(name.clone()))?;
    let limits = scenario
        .build_guidance()
        .ok_or_else(|| GuidedRunError::NoGuidance(name.clone()))?
        .map_err(GuidedRunError::from)?
        .limits;
    for f in filters {
        f.check_fits(&scenario.onboard)
            .map_err(|e| DeliveryError::Engine(e.into()))?;
    }
    let shared = Arc::new(scenario.clone());
    let done = std::sync::atomic::AtomicUsize::new(0);
    let per_run: Vec<RunDeliveries> = (0..runs)
        .into_par_iter()
        .map(|run| {
            let r = deliver_run(&shared, filters, seed, run);
            progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
            r
        })
        .collect();
    Ok(report_of(
        name,
        algorithm_name(cfg.algorithm),
        seed,
        &limits,
        &row_names(filters),
        per_run,
    ))
}

/// The row names of a study flying `filters`: `perfect-nav`, `unguided`, then the filters.
pub fn row_names(filters: &[FilterKind]) -> Vec<String> {
    ["perfect-nav", "unguided"]
        .into_iter()
        .map(str::to_string)
        .chain(filters.iter().map(|k| k.name().to_string()))
        .collect()
}

/// `apollo` or `fnpeg`.
pub fn algorithm_name(a: crate::guidance::GuidanceAlgorithm) -> &'static str {
    match a {
        crate::guidance::GuidanceAlgorithm::Apollo => "apollo",
        crate::guidance::GuidanceAlgorithm::Fnpeg => "fnpeg",
    }
}

/// The report of every run's deliveries `per_run` (run order, one entry per row of `names`).
pub(crate) fn report_of(
    scenario: String,
    algorithm: &str,
    seed: u64,
    limits: &crate::guidance::BankLimits,
    names: &[String],
    per_run: Vec<RunDeliveries>,
) -> DeliveryReport {
    let rows = names
        .iter()
        .enumerate()
        .map(|(i, n)| row_stats(n.clone(), per_run.iter().map(|r| &r[i]), limits))
        .collect();
    DeliveryReport {
        scenario,
        algorithm: algorithm.to_string(),
        runs: per_run.len(),
        seed,
        bank_rate_limit_deg_s: limits.rate_max.to_degrees(),
        rows,
        per_run,
    }
}

/// The statistics of one row over the runs, in run order.
fn row_stats<'a>(
    name: String,
    results: impl Iterator<Item = &'a Result<Delivery, GuidedRunError>>,
    limits: &crate::guidance::BankLimits,
) -> DeliveryRow {
    let mut ok = Vec::new();
    let mut failures = 0;
    let mut first_failure = None;
    let mut failures_by_cause = std::collections::BTreeMap::new();
    for (run, r) in results.enumerate() {
        match r {
            Ok(d) => ok.push(*d),
            Err(e) => {
                failures += 1;
                first_failure.get_or_insert_with(|| (run, e.to_string()));
                *failures_by_cause.entry(e.cause().to_string()).or_insert(0) += 1;
            }
        }
    }
    let n = ok.len();
    let mut outside_box_by_limit = std::collections::BTreeMap::new();
    for d in &ok {
        for limit in d.outside_box.names() {
            *outside_box_by_limit.entry(limit.to_string()).or_insert(0) += 1;
        }
    }
    let mean =
        |f: &dyn Fn(&Delivery) -> f64| (n > 0).then(|| ok.iter().map(f).sum::<f64>() / n as f64);
    let md = mean(&|d| d.downrange_m);
    let mc = mean(&|d| d.crossrange_m);
    let ellipse_99 = (n >= 2).then(|| {
        let (md, mc) = (md.unwrap_or(0.0), mc.unwrap_or(0.0));
        let m = (n - 1) as f64;
        let cdd = ok.iter().map(|d| (d.downrange_m - md).powi(2)).sum::<f64>() / m;
        let ccc = ok
            .iter()
            .map(|d| (d.crossrange_m - mc).powi(2))
            .sum::<f64>()
            / m;
        let cdc = ok
            .iter()
            .map(|d| (d.downrange_m - md) * (d.crossrange_m - mc))
            .sum::<f64>()
            / m;
        let half_tr = 0.5 * (cdd + ccc);
        let disc = ((0.5 * (cdd - ccc)).powi(2) + cdc * cdc).sqrt();
        DeliveryEllipse {
            semi_major_m: (CHI2_2_99 * (half_tr + disc)).sqrt(),
            semi_minor_m: (CHI2_2_99 * (half_tr - disc).max(0.0)).sqrt(),
            orientation_deg: (0.5 * (2.0 * cdc).atan2(cdd - ccc)).to_degrees(),
        }
    });
    let nav: Vec<f64> = ok
        .iter()
        .filter_map(|d| d.nav_error.map(|e| e.position_m))
        .collect();
    let nees: Vec<f64> = ok
        .iter()
        .filter_map(|d| d.nav_error.and_then(|e| e.nees_kinematic))
        .filter(|v| v.is_finite())
        .collect();
    DeliveryRow {
        name,
        deployed: n,
        failures,
        first_failure,
        mean_miss_m: mean(&|d| d.miss_m),
        rms_miss_m: mean(&|d| d.miss_m * d.miss_m).map(f64::sqrt),
        median_miss_m: median(ok.iter().map(|d| d.miss_m).collect()),
        max_miss_m: ok.iter().map(|d| d.miss_m).reduce(f64::max),
        mean_downrange_m: md,
        mean_crossrange_m: mc,
        ellipse_99,
        max_bank_rate_deg_s: ok.iter().map(|d| d.max_bank_rate_deg_s).reduce(f64::max),
        rate_limit_held: ok.iter().all(|d| within_rate_limit(d, limits)),
        rms_nav_position_error_m: (!nav.is_empty())
            .then(|| (nav.iter().map(|e| e * e).sum::<f64>() / nav.len() as f64).sqrt()),
        mean_nees_kinematic: (!nees.is_empty())
            .then(|| nees.iter().sum::<f64>() / nees.len() as f64),
        failures_by_cause,
        inside_box: ok.iter().filter(|d| !d.outside_box.any()).count(),
        outside_box_by_limit,
    }
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}
