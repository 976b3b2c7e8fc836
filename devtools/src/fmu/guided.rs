//! Inputs of the guidance FMU (`MarsEntryGuidance`) for `entrynav-dev fmu check` and `fmu cross-check`: what
//! the in-process guided loop (`entrynav::sim::guided_run`, the EKF in the loop, Monte Carlo run
//! 0 of the seed) gave its guidance at each communication point. With a communication step equal
//! to the guidance period, the FMU's bank then equals the loop's bank at every communication point
//! bit for bit (`fmu/tests/guidance.rs` checks every truth step).

use anyhow::{Context, Result, ensure};
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::guided::{GuidedStep, fly_with_filter_recorded};
use entrynav_fmu::vars::{Key, Slot, Value};
use std::sync::Arc;

/// The recorded loop on `scenario` with `seed`, sampled at `t = k·h` for `k = 0..=n` (`h` a
/// multiple of the truth step; after the loop's end at deployment the last inputs are held).
pub(super) fn guided_rows(
    scenario: &Arc<Scenario>,
    seed: u64,
    h: f64,
    n: usize,
) -> Result<Vec<GuidedStep>> {
    let dt = scenario.config.timing.truth_step_s;
    let every = (h / dt).round() as usize;
    ensure!(
        every >= 1 && ((h / dt) - every as f64).abs() < 1e-9,
        "the guidance FMU's inputs are recorded per truth step ({dt} s): the communication step {h} s must be a multiple of it"
    );
    let mut steps = Vec::new();
    fly_with_filter_recorded(scenario, FilterKind::Ekf, seed, 0, |s| {
        steps.push(s.clone())
    })
    .context("the guided loop that records the guidance FMU's inputs failed")?;
    let last = steps
        .len()
        .checked_sub(1)
        .context("the guided loop ran no step")?;
    Ok((0..=n)
        .map(|k| steps[(k * every).min(last)].clone())
        .collect())
}

/// The value of the guidance FMU's input `key` in the recorded step `s` (`None`: not an input of
/// that model).
pub(super) fn guided_input(key: Key, s: &GuidedStep) -> Option<Value> {
    let accel = |k: u8| s.accel.map(|a| a[k as usize]);
    Some(match key {
        // Slots past the filter's dimension read 0, as the navigation FMUs' do.
        Key::EstX(i) => Value::Real(s.est_x.get(i).copied().unwrap_or(0.0)),
        Key::EstSigma(i) => Value::Real(*s.est_sigma.get(i)?),
        Key::NavTime => Value::Real(s.est_t),
        Key::NavStatusCode => Value::Integer(s.nav_status),
        Key::Meas(Slot::Accel(k)) => Value::Real(accel(k).unwrap_or(0.0)),
        Key::MeasValid(Slot::Accel(k)) => Value::Boolean(accel(k).is_some()),
        _ => return None,
    })
}
