//! One run of a trade replayed in full (`trade --replay-run K`): per filter, truth, estimate, σ,
//! error, NEES, per-channel innovation and NIS, weights at every epoch, as CSV rows.

use crate::error::StudyResult;
use crate::trade::options::{TradeMode, TradeOptions};
use crate::trade::setup::TradeSetup;
use entrynav::scenario::Scenario;
use entrynav::sim::monte_carlo::replay::{Replay, replay_run};
use entrynav::sim::{channel_names, state_names};
use std::io::Write;
use std::sync::Arc;

/// Run `run` of a study, replayed.
pub struct ReplayedRun {
    /// The run index.
    pub run: usize,
    /// One replay per filter.
    pub replays: Vec<Replay>,
    /// State names, in state order.
    pub states: Vec<String>,
    /// Measurement channel names.
    pub channels: Vec<String>,
    /// Names of the weight columns: beacons for fusion filters, member biases for banks.
    pub weights: Vec<String>,
}

impl ReplayedRun {
    /// The CSV of `replay`; returns the `# failed at …` line that follows the rows if the filter
    /// stopped on a numerical failure.
    pub fn write_csv<W: Write>(
        &self,
        w: &mut csv::Writer<W>,
        replay: &Replay,
    ) -> csv::Result<Option<String>> {
        write_csv(w, replay, &self.states, &self.channels, &self.weights)
    }
}

/// Replay run `run` of the study of `setup` (same scenario, overrides, seed and filters).
pub fn replay_trade_run(
    setup: &TradeSetup,
    options: &TradeOptions,
    run: usize,
) -> StudyResult<ReplayedRun> {
    options.validate()?;
    options.check_mode(TradeMode::Replay)?;
    let scenario = Arc::new(setup.scenario.clone());
    let replays = replay_run(&scenario, &setup.filters, options.seed, run)?;
    Ok(ReplayedRun {
        run,
        replays,
        states: state_names(&scenario),
        channels: channel_names(&scenario),
        weights: weight_names(&scenario),
    })
}

/// Names of the weight columns: beacons for fusion filters, member biases for banks.
fn weight_names(scenario: &Scenario) -> Vec<String> {
    let onboard = &scenario.onboard;
    let banks = &onboard.tuning.model_bank_density_bias;
    let mut names: Vec<String> = onboard
        .radio_beacons()
        .iter()
        .map(|&b| format!("weight_{}", onboard.beacon_names[b]))
        .collect();
    names.extend(banks.iter().map(|d| format!("prob_delta_{d}")));
    names
}

/// The header of a replay's CSV and its number of weight columns.
fn header(
    r: &Replay,
    states: &[String],
    channels: &[String],
    weight_names: &[String],
) -> (Vec<String>, usize) {
    let mut header = vec!["t_s".to_string()];
    for s in states {
        for q in ["truth", "est", "sigma", "err"] {
            header.push(format!("{q}_{s}"));
        }
    }
    header.extend(
        [
            "nees",
            "nees_dof",
            "nees_kinematic",
            "pos_err_m",
            "vel_err_mps",
            "nis",
        ]
        .map(String::from),
    );
    for c in channels {
        header.push(format!("innov_{c}"));
        header.push(format!("nis_{c}"));
    }
    let n_weights = r
        .epochs
        .iter()
        .filter_map(|e| e.weights.as_ref().map(Vec::len))
        .max()
        .unwrap_or(0);
    let weight_header = |j: usize| {
        // Fusion weights first, then bank probabilities: pick the list that matches the count.
        let fusion = weight_names
            .iter()
            .filter(|n| n.starts_with("weight_"))
            .count();
        let offset = if n_weights == fusion { 0 } else { fusion };
        weight_names
            .get(offset + j)
            .cloned()
            .unwrap_or_else(|| format!("weight_{j}"))
    };
    header.extend((0..n_weights).map(weight_header));
    (header, n_weights)
}

/// The replay's rows; returns the `# failed at …` line that follows them if the filter stopped
/// on a numerical failure.
fn write_csv<W: Write>(
    w: &mut csv::Writer<W>,
    r: &Replay,
    states: &[String],
    channels: &[String],
    weight_names: &[String],
) -> csv::Result<Option<String>> {
    let (header, n_weights) = header(r, states, channels, weight_names);
    w.write_record(&header)?;
    let o = |v: Option<f64>| v.map(|x| format!("{x:e}")).unwrap_or_default();
    for e in &r.epochs {
        let mut row = vec![format!("{}", e.t)];
        for i in 0..states.len() {
            for v in [&e.truth, &e.estimate, &e.sigma, &e.err] {
                row.push(o(v.get(i).copied().filter(|x| x.is_finite())));
            }
        }
        row.push(o(e.nees.map(|n| n.0)));
        row.push(e.nees.map(|n| n.1.to_string()).unwrap_or_default());
        row.push(o(e.nees_kinematic));
        row.push(o(Some(e.pos_vel_err.0)));
        row.push(o(Some(e.pos_vel_err.1)));
        row.push(o(e.nis));
        for c in 0..channels.len() {
            let terms: Vec<&(usize, Option<f64>, f64)> =
                e.channels.iter().filter(|t| t.0 == c).collect();
            let innov = terms.iter().find_map(|t| t.1);
            let nis = (!terms.is_empty())
                .then(|| terms.iter().map(|t| t.2).sum::<f64>() / terms.len() as f64);
            row.push(o(innov));
            row.push(o(nis));
        }
        for j in 0..n_weights {
            row.push(o(e.weights.as_ref().and_then(|w| w.get(j).copied())));
        }
        w.write_record(&row)?;
    }
    Ok(r.failure
        .as_ref()
        .map(|(t, why)| format!("# failed at t = {t} s: {why}")))
}
