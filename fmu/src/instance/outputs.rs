//! Output values of an instance, computed from its engine, and the checks on values set.

use super::engine::{Engine, InstanceError};
use super::guidance::GuidanceEngine;
use super::guided::GuidedEngine;
use super::machine::Instance;
use crate::limits::MAX_STRING_BYTES;
use crate::vars::{Key, MAX_WEIGHTS, Type, Value};
use entrynav::estimation::nav::FilterKind;
use entrynav::frames::inertial_to_spherical;
use entrynav::sim::StopReason;
use entrynav::sim::engine::{EntryCoSim, Navigator, TruthSensors};
use entrynav::sim::guided::Delivery;

impl Instance {
    /// The value of output `key`. No output is ever NaN (system masters such as OMSimulator reject
    /// a NaN and drop the step's whole result row): a value that is not defined yet or not at all
    /// reads 0, and the output that says why is beside it — `n_meas` = 0 for `nis`, `nees_dof` = 0
    /// for `nees`, a filter without density state for `est_density`, a state without truth
    /// counterpart for `truth_x_*`/`err_*`, no engine before initialisation ends.
    pub(super) fn output(&self, key: Key) -> Value {
        let Some(engine) = &self.engine else {
            return self.undefined(key);
        };
        let guidance = |key| match engine {
            Engine::Guidance(g) => guidance_output(g, key),
            _ => None,
        };
        let guided = |key| match engine {
            Engine::Guided(g) => guided_output(g, key),
            _ => None,
        };
        engine
            .truth()
            .and_then(|ts| self.truth_output(ts, key))
            .or_else(|| engine.nav().and_then(|nav| nav_output(nav, key)))
            .or_else(|| guidance(key))
            .or_else(|| guided(key))
            .or_else(|| engine.cosim().and_then(|c| judgement_output(c, key)))
            .unwrap_or_else(|| self.undefined(key))
    }

    /// The truth and sensor outputs (`None`: `key` is none of them).
    fn truth_output(&self, ts: &TruthSensors, key: Key) -> Option<Value> {
        let o = ts.outputs();
        let nb = ts.scenario().beacons.len();
        Some(match key {
            Key::TruthSph(k) => real(o.sample.spherical[k]),
            Key::TruthAltitude => real(o.sample.altitude),
            Key::TruthDensity => real(o.sample.density),
            Key::TruthDynamicPressure => real(o.sample.dynamic_pressure),
            Key::TruthHeating => real(o.sample.heating),
            Key::TruthAeroAccel => real(o.sample.aero_accel),
            Key::TruthSensedAccel(k) => real(o.sensed_accel[k]),
            Key::BeaconRange(i) => real(if i < nb { o.ranges[i] } else { 0.0 }),
            Key::BeaconVisible(i) => Value::Boolean(i < nb && o.sample.visible[i]),
            Key::TruthStop | Key::TruthStopCode => Value::Integer(match ts.stop() {
                None => 0,
                Some(StopReason::Duration) => 1,
                Some(StopReason::StopSpeed) => 2,
                Some(StopReason::Ground) => 3,
            }),
            Key::NBeacons => Value::Integer(nb as i32),
            Key::TruthBankFlown => real(self.flown_bank.unwrap_or(0.0)),
            Key::MeasEpoch => Value::Boolean(ts.last_epoch().is_some()),
            Key::MeasTime => real(ts.last_epoch().map(|e| e.t).unwrap_or(0.0)),
            Key::Meas(s) | Key::MeasValid(s) => {
                let v = ts
                    .last_epoch()
                    .zip(self.slot_channel.get(&s))
                    .and_then(|(e, &c)| e.values[c]);
                if matches!(key, Key::Meas(_)) {
                    real(v.unwrap_or(0.0))
                } else {
                    Value::Boolean(v.is_some())
                }
            }
            _ => return None,
        })
    }

    /// The value of an output that is not defined: 0, false or the empty string by type.
    fn undefined(&self, key: Key) -> Value {
        match self.vars.iter().find(|v| v.key == key).map(|v| v.ty) {
            Some(Type::Integer) => Value::Integer(0),
            Some(Type::Boolean) => Value::Boolean(false),
            Some(Type::String) => Value::String(String::new()),
            _ => Value::Real(0.0),
        }
    }
}

/// A real output: 0 where the value is not finite (no output is ever NaN).
fn real(x: f64) -> Value {
    Value::Real(if x.is_finite() { x } else { UNDEFINED })
}

/// What an output that is not defined (yet) reads.
const UNDEFINED: f64 = 0.0;

/// The navigation outputs (`None`: `key` is none of them).
fn nav_output(nav: &Navigator, key: Key) -> Option<Value> {
    let est = nav.estimate();
    let n = est.x.len();
    let slot = |v: &[f64], i: usize| real(if i < n { v[i] } else { 0.0 });
    Some(match key {
        Key::NavTime => real(est.t),
        Key::NavStatus | Key::NavStatusCode => Value::Integer(nav.status().code()),
        Key::NStates => Value::Integer(n as i32),
        Key::EstX(i) => slot(&est.x, i),
        Key::EstSigma(i) => slot(&est.sigma, i),
        Key::EstSph(k) => {
            let fm = &nav.onboard().model;
            let x = &est.x;
            let s = if fm.kind.is_cartesian() {
                inertial_to_spherical(
                    &[x[0], x[1], x[2]],
                    &[x[3], x[4], x[5]],
                    est.t,
                    fm.planet.rotation_rate,
                )
            } else {
                [x[0], x[1], x[2], x[3], x[4], x[5]]
            };
            real(s[k])
        }
        Key::EstDensity => real(est.density.unwrap_or(UNDEFINED)),
        Key::Nis => real(est.info.nis.unwrap_or(UNDEFINED)),
        Key::NMeas => Value::Integer(est.info.n_meas as i32),
        Key::Weight(i) => real(
            est.info
                .weights
                .as_ref()
                .and_then(|w| w.get(i).copied())
                .unwrap_or(0.0),
        ),
        Key::NWeights => Value::Integer(nav_weights(nav).min(MAX_WEIGHTS) as i32),
        _ => return None,
    })
}

/// The guidance FMU's outputs (`None`: `key` is none of them).
fn guidance_output(g: &GuidanceEngine, key: Key) -> Option<Value> {
    Some(match key {
        Key::GuidanceBank => real(g.bank()),
        Key::GuidanceBankRate => real(g.bank_rate()),
        Key::GuidanceCommand => real(g.command()),
        Key::GuidanceTime => real(g.last_cycle_time()),
        Key::GuidanceCycles => Value::Integer(i32::try_from(g.cycles()).unwrap_or(i32::MAX)),
        Key::SensedDrag => real(g.drag()),
        Key::RangeToGo => real(g.range().0),
        Key::Crossrange => real(g.range().1),
        Key::DeployTrigger => real(g.trigger_value()),
        Key::Deployed => Value::Boolean(g.deployed()),
        Key::GuidanceStatus | Key::GuidanceStatusCode => Value::Integer(g.status()),
        _ => return None,
    })
}

/// The guided FMU's guidance and delivery outputs (`None`: `key` is none of them).
fn guided_output(g: &GuidedEngine, key: Key) -> Option<Value> {
    let f = g.flight();
    let d = g.delivery();
    let of = |x: fn(&Delivery) -> f64| real(d.map(x).unwrap_or(0.0));
    Some(match key {
        Key::GuidanceBankRate => real(f.bank_rate()),
        Key::GuidanceCommand => real(f.command()),
        Key::GuidanceCycles => Value::Integer(i32::try_from(f.cycles()).unwrap_or(i32::MAX)),
        Key::SensedDrag => real(f.drag()),
        Key::GuidedStatus => Value::Integer(g.status() as i32),
        Key::Deployed => Value::Boolean(d.is_some()),
        Key::DeployTime => of(|d| d.t_deploy_s),
        Key::DeployAltitude => of(|d| d.altitude_m),
        Key::MissDistance => of(|d| d.miss_m),
        Key::MissDownrange => of(|d| d.downrange_m),
        Key::MissCrossrange => of(|d| d.crossrange_m),
        _ => return None,
    })
}

/// The judgement of the combined model's estimate against its truth (`None`: `key` is none of
/// them).
fn judgement_output(c: &EntryCoSim, key: Key) -> Option<Value> {
    let j = c.judgement();
    let n = j.err.len();
    let slot = |v: &[f64], i: usize| real(if i < n { v[i] } else { 0.0 });
    Some(match key {
        Key::TruthX(i) => slot(&j.truth, i),
        Key::Err(i) => slot(&j.err, i),
        Key::Nees => real(j.nees.map(|x| x.0).unwrap_or(UNDEFINED)),
        Key::NeesDof => Value::Integer(j.nees.map(|x| x.1 as i32).unwrap_or(0)),
        Key::NavTruthDensity => real(j.density_true),
        _ => return None,
    })
}

fn nav_weights(nav: &Navigator) -> usize {
    nav.estimate()
        .info
        .weights
        .as_ref()
        .map(Vec::len)
        .unwrap_or(0)
}

/// Check a value before it is stored.
pub(super) fn validate(key: Key, v: &Value) -> Result<(), InstanceError> {
    match (key, v) {
        (_, Value::Real(x)) if !x.is_finite() => Err(InstanceError::NonFinite(*x)),
        (_, Value::String(s)) if s.len() > MAX_STRING_BYTES => {
            Err(InstanceError::TooLong(crate::limits::LimitError::TooMany {
                what: "the length of the string in bytes",
                got: s.len() as u64,
                max: MAX_STRING_BYTES as u64,
            }))
        }
        (Key::Seed, Value::Integer(s)) if *s < 0 => Err(InstanceError::NegativeSeed(*s)),
        (Key::Run, Value::Integer(r)) => super::engine::check_run(*r),
        // Inputs of the guidance FMU (outputs, never set, in the other models).
        (Key::EstSigma(_), Value::Real(x)) if *x < 0.0 => Err(InstanceError::NegativeSigma(*x)),
        (Key::NavStatusCode, Value::Integer(c)) if !(0..=2).contains(c) => {
            Err(InstanceError::StatusCode(*c))
        }
        (Key::Filter, Value::String(s)) => Ok(FilterKind::parse(s).map(|_| ())?),
        (Key::Scenario, Value::String(s)) if s.trim().is_empty() => {
            Err(InstanceError::EmptyScenario)
        }
        _ => Ok(()),
    }
}
