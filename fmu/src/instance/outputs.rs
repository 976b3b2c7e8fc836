//! Output values of an instance, computed from its engine, and the checks on values set.

use super::Instance;
use super::engine::{Engine, InstanceError};
use crate::limits::MAX_STRING_BYTES;
use crate::vars::{Key, MAX_WEIGHTS, Type, Value};
use entrynav::estimation::nav::FilterKind;
use entrynav::frames::inertial_to_spherical;
use entrynav::sim::StopReason;
use entrynav::sim::engine::Navigator;

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
        let undefined = 0.0;
        let real = |x: f64| Value::Real(if x.is_finite() { x } else { undefined });
        if let Some(ts) = engine.truth() {
            let o = ts.outputs();
            let nb = ts.scenario().beacons.len();
            match key {
                Key::TruthSph(k) => return real(o.sample.spherical[k]),
                Key::TruthAltitude => return real(o.sample.altitude),
                Key::TruthDensity => return real(o.sample.density),
                Key::TruthDynamicPressure => return real(o.sample.dynamic_pressure),
                Key::TruthHeating => return real(o.sample.heating),
                Key::TruthAeroAccel => return real(o.sample.aero_accel),
                Key::TruthSensedAccel(k) => return real(o.sensed_accel[k]),
                Key::BeaconRange(i) => return real(if i < nb { o.ranges[i] } else { 0.0 }),
                Key::BeaconVisible(i) => {
                    return Value::Boolean(i < nb && o.sample.visible[i]);
                }
                Key::TruthStop | Key::TruthStopCode => {
                    return Value::Integer(match ts.stop() {
                        None => 0,
                        Some(StopReason::Duration) => 1,
                        Some(StopReason::StopSpeed) => 2,
                        Some(StopReason::Ground) => 3,
                    });
                }
                Key::NBeacons => return Value::Integer(nb as i32),
                Key::TruthBankFlown => return real(self.flown_bank.unwrap_or(0.0)),
                Key::MeasEpoch => return Value::Boolean(ts.last_epoch().is_some()),
                Key::MeasTime => return real(ts.last_epoch().map(|e| e.t).unwrap_or(0.0)),
                Key::Meas(s) | Key::MeasValid(s) => {
                    let v = ts
                        .last_epoch()
                        .zip(self.slot_channel.get(&s))
                        .and_then(|(e, &c)| e.values[c]);
                    return if matches!(key, Key::Meas(_)) {
                        real(v.unwrap_or(0.0))
                    } else {
                        Value::Boolean(v.is_some())
                    };
                }
                _ => {}
            }
        }
        if let Some(nav) = engine.nav() {
            let est = nav.estimate();
            let n = est.x.len();
            let slot = |v: &[f64], i: usize| real(if i < n { v[i] } else { 0.0 });
            match key {
                Key::NavTime => return real(est.t),
                Key::NavStatus | Key::NavStatusCode => {
                    return Value::Integer(nav.status().code());
                }
                Key::NStates => return Value::Integer(n as i32),
                Key::EstX(i) => return slot(&est.x, i),
                Key::EstSigma(i) => return slot(&est.sigma, i),
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
                    return real(s[k]);
                }
                Key::EstDensity => return real(est.density.unwrap_or(undefined)),
                Key::Nis => return real(est.info.nis.unwrap_or(undefined)),
                Key::NMeas => return Value::Integer(est.info.n_meas as i32),
                Key::Weight(i) => {
                    return real(
                        est.info
                            .weights
                            .as_ref()
                            .and_then(|w| w.get(i).copied())
                            .unwrap_or(0.0),
                    );
                }
                Key::NWeights => {
                    let nw = nav_weights(nav);
                    return Value::Integer(nw.min(MAX_WEIGHTS) as i32);
                }
                _ => {}
            }
        }
        if let Engine::Guidance(g) = engine {
            match key {
                Key::GuidanceBank => return real(g.bank()),
                Key::GuidanceBankRate => return real(g.bank_rate()),
                Key::GuidanceCommand => return real(g.command()),
                Key::GuidanceTime => return real(g.last_cycle_time()),
                Key::GuidanceCycles => {
                    return Value::Integer(i32::try_from(g.cycles()).unwrap_or(i32::MAX));
                }
                Key::SensedDrag => return real(g.drag()),
                Key::RangeToGo => return real(g.range().0),
                Key::Crossrange => return real(g.range().1),
                Key::DeployTrigger => return real(g.trigger_value()),
                Key::Deployed => return Value::Boolean(g.deployed()),
                _ => {}
            }
        }
        if let Engine::Guided(g) = engine {
            let f = g.flight();
            let d = g.delivery();
            let of = |x: fn(&entrynav::sim::guided::Delivery) -> f64| real(d.map(x).unwrap_or(0.0));
            match key {
                Key::GuidanceBankRate => return real(f.bank_rate()),
                Key::GuidanceCommand => return real(f.command()),
                Key::GuidanceCycles => {
                    return Value::Integer(i32::try_from(f.cycles()).unwrap_or(i32::MAX));
                }
                Key::SensedDrag => return real(f.drag()),
                Key::GuidedStatus => return Value::Integer(g.status() as i32),
                Key::Deployed => return Value::Boolean(d.is_some()),
                Key::DeployTime => return of(|d| d.t_deploy_s),
                Key::DeployAltitude => return of(|d| d.altitude_m),
                Key::MissDistance => return of(|d| d.miss_m),
                Key::MissDownrange => return of(|d| d.downrange_m),
                Key::MissCrossrange => return of(|d| d.crossrange_m),
                _ => {}
            }
        }
        if let Some(c) = engine.cosim() {
            let j = c.judgement();
            let n = j.err.len();
            let slot = |v: &[f64], i: usize| real(if i < n { v[i] } else { 0.0 });
            match key {
                Key::TruthX(i) => return slot(&j.truth, i),
                Key::Err(i) => return slot(&j.err, i),
                Key::Nees => return real(j.nees.map(|x| x.0).unwrap_or(undefined)),
                Key::NeesDof => return Value::Integer(j.nees.map(|x| x.1 as i32).unwrap_or(0)),
                Key::NavTruthDensity => return real(j.density_true),
                _ => {}
            }
        }
        self.undefined(key)
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
