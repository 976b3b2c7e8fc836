//! The inputs of a check run (and of a cross-check input table): a bank profile, a beacon
//! outage, the filter FMU's measurements one step late, the guidance FMU's recorded loop; and
//! the scenario and timing a run uses.

use super::super::guided::guided_input;
use anyhow::Result;
use entrynav::scenario::Scenario;
use entrynav::sim::engine::TruthSensors;
use entrynav::sim::guided::GuidedStep;
use entrynav_fmu::vars::{Causality, Key, MAX_BEACONS, Model, Slot, Value, Var};
use std::path::Path;
use std::sync::Arc;

/// The bank-angle command of `fmu check` at time `t` \[rad\].
pub(crate) fn check_bank(t: f64) -> f64 {
    if t < 100.0 {
        0.0
    } else if t < 200.0 {
        0.35
    } else {
        -0.2
    }
}

/// Beacon availability of the check runs: beacon 2 (slot 1) out from 120 s to 180 s.
pub(crate) fn check_available(t: f64) -> [bool; MAX_BEACONS] {
    std::array::from_fn(|b| !(b == 1 && (120.0..180.0).contains(&t)))
}

/// The bank input of a check run's row at `t` with communication step `h`: the command of the
/// step from `t`, except for the filter FMU, which is told the bank its measurements were flown
/// with — the previous step's, like the measurements (one step late; fmu/README "Split pair").
fn bank_input(model: Model, t: f64, h: f64) -> f64 {
    match model {
        Model::Filter => check_bank((t - h).max(0.0)),
        _ => check_bank(t),
    }
}

/// The inputs of a check run's row at `t` (communication step `h`); the filter FMU's
/// measurements are the last epoch of `truth`, the guidance FMU's inputs the recorded `guided`
/// step.
pub(crate) fn check_inputs(
    model: Model,
    vars: &[Var],
    t: f64,
    h: f64,
    truth: Option<&TruthSensors>,
    guided: Option<&GuidedStep>,
) -> Vec<(usize, Value)> {
    let bank = bank_input(model, t, h);
    let available = check_available(t);
    let epoch = truth.and_then(|ts| ts.last_epoch());
    let slot_value = |s: Slot| -> Option<f64> {
        let (ts, e) = (truth?, epoch?);
        let c = ts
            .scenario()
            .channels
            .iter()
            .position(|c| Slot::of(c.channel) == Some(s))?;
        e.values[c]
    };
    vars.iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Input)
        .map(|(i, v)| {
            if let Some(val) = guided.and_then(|g| guided_input(v.key, g)) {
                return (i, val);
            }
            let val = match v.key {
                Key::Bank => Value::Real(bank),
                Key::BeaconAvailable(b) => {
                    Value::Boolean(available.get(b).copied().unwrap_or(true))
                }
                Key::MeasEpoch => Value::Boolean(epoch.is_some()),
                Key::MeasTime => Value::Real(epoch.map(|e| e.t).unwrap_or(0.0)),
                Key::Meas(s) => Value::Real(slot_value(s).unwrap_or(0.0)),
                Key::MeasValid(s) => Value::Boolean(slot_value(s).is_some()),
                _ => v.start.clone().unwrap_or(Value::Real(0.0)),
            };
            (i, val)
        })
        .collect()
}

/// The scenario's duration and its fastest sensor period (the default communication step).
pub(super) fn scenario_timing(sc: &Scenario) -> (f64, f64) {
    let step = sc
        .channels
        .iter()
        .map(|c| c.period_s)
        .fold(f64::INFINITY, f64::min);
    (
        sc.config.timing.duration_s,
        if step.is_finite() { step } else { 1.0 },
    )
}

/// The scenario an FMU instance with `scenario = name` loads from the resources folder `res`.
pub(crate) fn load_scenario(name: &str, res: &Path) -> Result<Arc<Scenario>> {
    Ok(Arc::new(entrynav_loader::load(
        name,
        &[],
        entrynav_loader::Base::Folder(res),
    )?))
}
