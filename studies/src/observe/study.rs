//! `entrynav observe` as a study: the degree of observability δ(t) along a scenario's nominal
//! trajectory (seed 000 §2.4, seed 002 §3), of the centralised system and of each IMU +
//! one-beacon subsystem, the range Fisher information of its beacons (seed 002 §3.2, eq. 54) and
//! the posterior Cramér–Rao lower bound from its truth runs alone (`entrynav::sim::pcrlb`).

use crate::error::{StudyError, StudyResult};
use crate::observe::document::to_json;
use crate::observe::options::ObserveOptions;
use entrynav::observability::fisher::max_det_bound;
use entrynav::observability::{
    AnalysisPoint, ChannelSet, DegreeSeries, FimEpoch, ObservabilityError, Scaling,
    analysis_points, degree_series, max_det_directions, range_fim_series,
};
use entrynav::scenario::Scenario;
use entrynav::sim::monte_carlo::state_names;
use entrynav::sim::{PcrlbReport, pcrlb_study};
use serde_json::{Value, json};
use std::time::Instant;

/// The PCRLB over the truth runs, without a filter.
#[derive(Debug, Clone)]
pub struct PcrlbBound {
    /// The bound per state and for `pos_m`/`vel_mps`.
    pub report: PcrlbReport,
    /// Truth runs it averages over.
    pub runs: usize,
    /// Their master seed.
    pub seed: u64,
    /// Seconds it took.
    pub elapsed_s: f64,
    /// The rows of its table: the scenario's state names, then `pos_m` and `vel_mps`.
    pub names: Vec<String>,
}

/// The best geometry of `n` free beacons (seed 002 Table 1), beside the FIM of the scenario's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeBeacons {
    /// Number of beacons (`beacons`, else the most in view).
    pub n: usize,
    /// max det(Σ n nᵀ) found by projected gradient ascent.
    pub det: f64,
    /// Its analytic value (N/3)³.
    pub bound: f64,
}

/// What an observability study found.
#[derive(Debug, Clone)]
pub struct Observation {
    /// The options it ran with.
    pub options: ObserveOptions,
    /// The analysis points along the nominal truth trajectory.
    pub points: Vec<AnalysisPoint>,
    /// The characteristic sizes of the scaled δ.
    pub scaling: Scaling,
    /// δ(t) of the centralised system, and the seconds it took.
    pub central: (DegreeSeries, f64),
    /// δ(t) of each subsystem (with `subsystems`), and the seconds each took.
    pub subsystems: Vec<(DegreeSeries, f64)>,
    /// The range FIM per epoch (with `fim`).
    pub fim: Option<Vec<FimEpoch>>,
    /// The best free geometry of as many beacons (with `fim`, from three beacons).
    pub free_beacons: Option<FreeBeacons>,
    /// The PCRLB (with `pcrlb`).
    pub pcrlb: Option<PcrlbBound>,
}

impl Observation {
    /// The JSON document (`entrynav observe --json`) of the study on `scenario`.
    pub fn to_json(&self, scenario: &Scenario) -> Value {
        let (central, central_s) = &self.central;
        let fim = self.fim.as_deref();
        let mut v = to_json(
            scenario,
            &self.scaling,
            central,
            *central_s,
            &self.subsystems,
            fim,
        );
        if let Some(b) = &self.pcrlb {
            v["pcrlb"] = serde_json::to_value(&b.report).unwrap_or(Value::Null);
            v["pcrlb_runs"] = json!(b.runs);
            v["pcrlb_seed"] = json!(b.seed);
        }
        v
    }
}

/// An observability failure, refused (exit code 2) as the command always did.
fn refused(e: ObservabilityError) -> StudyError {
    StudyError::Refused(e.to_string())
}

/// The study of `scenario` with `options`.
pub fn run_observe(scenario: &Scenario, options: &ObserveOptions) -> StudyResult<Observation> {
    options.validate()?;
    let method = options.method;
    let sets = if options.subsystems {
        let sets = ChannelSet::subsystems(scenario);
        if sets.is_empty() {
            return Err(StudyError::Refused(format!(
                "scenario '{}' has no beacon channels: --subsystems needs range or range-rate \
                 beacons (each subsystem is the IMU plus one beacon)",
                scenario.config.name
            )));
        }
        sets
    } else {
        Vec::new()
    };
    let subset = match (options.fim, options.beacons) {
        (true, Some(n)) => Some(first_range_beacons(scenario, n)?),
        _ => None,
    };
    let points = analysis_points(scenario, options.step).map_err(refused)?;
    let scaling = Scaling::characteristic(scenario.filter_model());
    let timed = |set: &ChannelSet| {
        let started = Instant::now();
        let series = degree_series(scenario, &points, set, method, &scaling).map_err(refused)?;
        Ok::<_, StudyError>((series, started.elapsed().as_secs_f64()))
    };
    let central = timed(&ChannelSet::centralised(scenario))?;
    let subsystems = sets.iter().map(timed).collect::<StudyResult<Vec<_>>>()?;
    let fim = if options.fim {
        Some(range_fim_series(scenario, &points, subset.as_deref()).map_err(refused)?)
    } else {
        None
    };
    let free_beacons = fim
        .as_deref()
        .and_then(|f| free_beacons(f, options.beacons));
    let pcrlb = if options.pcrlb {
        Some(pcrlb_bound(scenario, options.runs, options.seed)?)
    } else {
        None
    };
    Ok(Observation {
        options: options.clone(),
        points,
        scaling,
        central,
        subsystems,
        fim,
        free_beacons,
        pcrlb,
    })
}

/// Indices of the first `n` beacons that have a range channel.
fn first_range_beacons(scenario: &Scenario, n: usize) -> StudyResult<Vec<usize>> {
    let mut ranged: Vec<usize> = scenario
        .channels
        .iter()
        .filter_map(|c| match c.channel {
            entrynav::sensors::Channel::Range(b) => Some(b),
            _ => None,
        })
        .collect();
    ranged.dedup();
    if n == 0 || n > ranged.len() {
        return Err(StudyError::Refused(format!(
            "--beacons {n}: scenario '{}' has {} range beacon(s)",
            scenario.config.name,
            ranged.len()
        )));
    }
    ranged.truncate(n);
    Ok(ranged)
}

/// The best geometry of `beacons` free beacons (else the most in view of `fim`), from three.
fn free_beacons(fim: &[FimEpoch], beacons: Option<usize>) -> Option<FreeBeacons> {
    let n = beacons.unwrap_or_else(|| fim.iter().map(|e| e.summary.count).max().unwrap_or(0));
    (n >= 3).then(|| FreeBeacons {
        n,
        det: max_det_directions(n, 8, 1).det,
        bound: max_det_bound(n),
    })
}

/// The PCRLB over `runs` truth runs of master seed `seed`.
fn pcrlb_bound(scenario: &Scenario, runs: usize, seed: u64) -> StudyResult<PcrlbBound> {
    let started = Instant::now();
    let report = pcrlb_study(scenario, seed, runs)?;
    let mut names = state_names(scenario);
    names.extend(["pos_m".to_string(), "vel_mps".to_string()]);
    Ok(PcrlbBound {
        report,
        runs,
        seed,
        elapsed_s: started.elapsed().as_secs_f64(),
        names,
    })
}
