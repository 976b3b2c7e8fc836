//! The fuzzer's calls: one random fmi2 call (or a short group, such as a serialisation round trip)
//! per [`Fuzzer::op`], with its expected answer from the model; the lifecycle, step and value
//! calls here, the others in [`super::calls`].

use super::model::{Expect, Sim, St};
use super::*;
use std::ffi::{c_int, c_void};

/// Step sizes: ordinary, tiny (down to the smallest denormal), huge (up to f64::MAX) and invalid.
const STEPS: [f64; 20] = [
    1.0,
    0.5,
    0.1,
    2.0,
    10.0,
    1e-3,
    1e-9,
    1e-300,
    5e-324,
    1e3,
    1e9,
    1e18,
    1e300,
    f64::MAX,
    0.0,
    -1.0,
    -0.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
];

pub(super) type State = *mut c_void;

impl Fuzzer<'_> {
    pub(super) fn var(&mut self, ty: Option<Type>) -> Option<Var> {
        if self.rng.random_bool(0.08) {
            return None;
        }
        let pool: Vec<&Var> = self
            .vars
            .iter()
            .filter(|v| ty.is_none_or(|t| v.ty == t))
            .collect();
        (!pool.is_empty()).then(|| pool[self.rng.random_range(0..pool.len())].clone())
    }

    pub(super) fn vr_of(&mut self, v: &Option<Var>) -> u32 {
        v.as_ref()
            .map(|v| v.vr)
            .unwrap_or(self.vars.len() as u32 + self.rng.random_range(0..1000u32))
    }

    pub(super) fn key_vr(&self, key: Key) -> Option<u32> {
        self.vars.iter().find(|v| v.key == key).map(|v| v.vr)
    }

    /// One random call (or group of calls).
    pub(super) fn op(
        &mut self,
        s: &Slave,
        sim: &mut Sim,
        saved: &mut Vec<(State, Sim)>,
    ) -> Result<()> {
        let u = self.u;
        let api = &u.api;
        let seen = s.messages().len();
        let model = u.model;
        // Half of the calls move the instance on (set up, initialise, step, start again), so
        // sequences spend their time in every state rather than mostly refused.
        let pick = if self.rng.random_bool(0.5) {
            match sim.st {
                St::Instantiated if sim.stop.is_none() && self.rng.random_bool(0.5) => 0,
                St::Instantiated => 1,
                St::Init => 2,
                St::Step => 3,
                St::Terminated | St::Error => 10,
            }
        } else {
            self.rng.random_range(0..32u32)
        };
        match pick {
            0 => {
                let start = [0.0, 0.0, 0.0, 1.0, f64::NAN][self.rng.random_range(0..5)];
                let defined = self.rng.random_bool(0.6);
                let stop = [300.0, 1e9, 10.0, 1e-9, f64::INFINITY, f64::NAN, -5.0]
                    [self.rng.random_range(0..7)];
                // SAFETY: our instance.
                let r = unsafe {
                    (api.fmi2SetupExperiment)(s.c, 0, 0.0, start, defined as c_int, stop)
                };
                let legal = sim.st == St::Instantiated
                    && start == 0.0
                    && (!defined || (stop.is_finite() && stop > 0.0));
                let e = if legal { Expect::Ok } else { Expect::Refused };
                self.expect(s, "fmi2SetupExperiment", sim, e, r, seen)?;
                if legal {
                    sim.stop = defined.then_some(stop);
                }
            }
            1 => {
                // SAFETY: our instance.
                let r = unsafe { (api.fmi2EnterInitializationMode)(s.c) };
                let legal = sim.st == St::Instantiated;
                self.expect(
                    s,
                    "fmi2EnterInitializationMode",
                    sim,
                    if legal { Expect::Ok } else { Expect::Refused },
                    r,
                    seen,
                )?;
                if legal {
                    sim.st = St::Init;
                }
            }
            2 => {
                // SAFETY: our instance.
                let r = unsafe { (api.fmi2ExitInitializationMode)(s.c) };
                let e = match (sim.st, sim.params_ok(&self.sc, model)) {
                    (St::Init, true) => Expect::Ok,
                    (St::Init, false) => Expect::Fails,
                    _ => Expect::Refused,
                };
                self.expect(s, "fmi2ExitInitializationMode", sim, e, r, seen)?;
                match e {
                    Expect::Ok => (sim.st, sim.engine) = (St::Step, true),
                    Expect::Fails => sim.st = St::Error,
                    _ => {}
                }
            }
            3..=8 => self.do_step(s, sim, seen)?,
            9 => {
                // SAFETY: our instance.
                let r = unsafe { (api.fmi2Terminate)(s.c) };
                let legal = sim.st == St::Step;
                self.expect(
                    s,
                    "fmi2Terminate",
                    sim,
                    if legal { Expect::Ok } else { Expect::Refused },
                    r,
                    seen,
                )?;
                if legal {
                    sim.st = St::Terminated;
                }
            }
            10 => {
                // SAFETY: our instance.
                let r = unsafe { (api.fmi2Reset)(s.c) };
                self.expect(s, "fmi2Reset", sim, Expect::Ok, r, seen)?;
                *sim = Sim::new(super::model::start_params(&u.spec));
            }
            11..=13 => self.get(s, sim, seen)?,
            14..=16 => self.set_real(s, sim, seen)?,
            17 => self.set_boolean(s, sim, seen)?,
            18 => self.set_param(s, sim, seen)?,
            19 => self.get_state(s, sim, saved, seen)?,
            20 => {
                if saved.is_empty() {
                    let mut local = 0u8;
                    // SAFETY: a pointer the instance never handed out: it must be refused unread.
                    let r = unsafe { (api.fmi2SetFMUstate)(s.c, &mut local as *mut u8 as State) };
                    self.expect(
                        s,
                        "fmi2SetFMUstate (foreign)",
                        sim,
                        Expect::Refused,
                        r,
                        seen,
                    )?;
                } else {
                    let i = self.rng.random_range(0..saved.len());
                    // SAFETY: our instance and a state it handed out.
                    let r = unsafe { (api.fmi2SetFMUstate)(s.c, saved[i].0) };
                    self.expect(s, "fmi2SetFMUstate", sim, Expect::Ok, r, seen)?;
                    *sim = saved[i].1.clone();
                    sim.engine = matches!(sim.st, St::Step | St::Terminated) || sim.stepped;
                }
            }
            21 => self.serialize(s, sim, saved, seen)?,
            22 => {
                if let Some((mut p, _)) = (!saved.is_empty())
                    .then(|| saved.swap_remove(self.rng.random_range(0..saved.len())))
                {
                    // SAFETY: our instance and a state it handed out.
                    let r = unsafe { (api.fmi2FreeFMUstate)(s.c, &mut p) };
                    self.expect(s, "fmi2FreeFMUstate", sim, Expect::Ok, r, seen)?;
                    ensure!(p.is_null(), "fmi2FreeFMUstate left the pointer set");
                }
            }
            23 | 24 => self.status(s, sim, seen)?,
            25 => self.debug_logging(s, sim, seen)?,
            26 => {
                // SAFETY: our instance.
                let r = unsafe { (api.fmi2CancelStep)(s.c) };
                self.expect(s, "fmi2CancelStep", sim, Expect::Refused, r, seen)?;
            }
            27 => {
                let (mut x, d, vr) = (0.0, 1.0, 0u32);
                // SAFETY: one element per array.
                let r =
                    unsafe { (api.fmi2GetDirectionalDerivative)(s.c, &vr, 1, &vr, 1, &d, &mut x) };
                self.expect(
                    s,
                    "fmi2GetDirectionalDerivative",
                    sim,
                    Expect::Refused,
                    r,
                    seen,
                )?;
            }
            28 => self.over_bound(s, sim, seen)?,
            29 => {
                // SAFETY: null arrays with a non-zero length must be refused unread.
                let r =
                    unsafe { (api.fmi2GetReal)(s.c, std::ptr::null(), 3, std::ptr::null_mut()) };
                self.expect(s, "fmi2GetReal (null)", sim, Expect::Refused, r, seen)?;
            }
            _ => self.instantiate_variants()?,
        }
        Ok(())
    }

    fn do_step(&mut self, s: &Slave, sim: &mut Sim, seen: usize) -> Result<()> {
        let u = self.u;
        let api = &u.api;
        let h = if self.rng.random_bool(0.7) {
            STEPS[self.rng.random_range(0..5)]
        } else {
            STEPS[self.rng.random_range(0..STEPS.len())]
        };
        let t = match self.rng.random_range(0..20) {
            0 => sim.time + 0.5,
            1 => sim.time * (1.0 + 1e-6) + 1e-3,
            2 => f64::NAN,
            3 => 1e300,
            _ => sim.time,
        };
        if h >= 1e3 && h.is_finite() {
            self.stats.huge_steps += 1;
        }
        if h > 0.0 && h <= 1e-9 {
            self.stats.tiny_steps += 1;
        }
        // The filter FMU's last processed epoch, read through the API as a master would.
        let mut nav = None;
        if self.u.model == Model::Filter && sim.st == St::Step {
            let (tv, sv) = (self.key_vr(Key::NavTime), self.key_vr(Key::NavStatus));
            if let (Some(tv), Some(sv)) = (tv, sv) {
                let (mut last, mut status) = (0.0, 0 as c_int);
                // SAFETY: one element each.
                let r = unsafe {
                    [
                        (api.fmi2GetReal)(s.c, &tv, 1, &mut last),
                        (api.fmi2GetInteger)(s.c, &sv, 1, &mut status),
                    ]
                };
                self.stats.calls += 2;
                self.stats.statuses[0] += 2;
                ensure!(
                    r == [0, 0],
                    "reading nav_time / nav_status failed: {:?}",
                    s.messages().last()
                );
                nav = Some((last, status == 2));
            }
        }
        let e = sim.do_step(&self.sc, self.u.model, t, h, nav);
        if e == Expect::Refused && sim.do_step(&self.sc, self.u.model, t, h, None) != e {
            self.stats.work_refused += 1;
        }
        // SAFETY: our instance.
        let r = unsafe { (api.fmi2DoStep)(s.c, t, h, 0) };
        self.expect(s, &format!("fmi2DoStep({t}, {h})"), sim, e, r, seen)?;
        if e == Expect::OkOrWarning {
            sim.time = t + h;
            sim.stepped = true;
        }
        Ok(())
    }

    fn get(&mut self, s: &Slave, sim: &mut Sim, seen: usize) -> Result<()> {
        let u = self.u;
        let api = &u.api;
        let ty =
            [Type::Real, Type::Integer, Type::Boolean, Type::String][self.rng.random_range(0..4)];
        let n = self.rng.random_range(1..=3);
        let vars: Vec<Option<Var>> = (0..n).map(|_| self.var(Some(ty))).collect();
        let vrs: Vec<u32> = vars.iter().map(|v| self.vr_of(v)).collect::<Vec<_>>();
        let refs: Vec<Option<&Var>> = vars.iter().map(Option::as_ref).collect();
        let e = sim.get(&self.sc, self.u.model, &refs, ty);
        // SAFETY: n references and room for n values of the function's type.
        let r = unsafe {
            match ty {
                Type::Real => (api.fmi2GetReal)(s.c, vrs.as_ptr(), n, vec![0.0; n].as_mut_ptr()),
                Type::Integer => {
                    (api.fmi2GetInteger)(s.c, vrs.as_ptr(), n, vec![0; n].as_mut_ptr())
                }
                Type::Boolean => {
                    (api.fmi2GetBoolean)(s.c, vrs.as_ptr(), n, vec![0; n].as_mut_ptr())
                }
                Type::String => (api.fmi2GetString)(
                    s.c,
                    vrs.as_ptr(),
                    n,
                    vec![std::ptr::null(); n].as_mut_ptr(),
                ),
            }
        };
        self.expect(s, &format!("fmi2Get{}", ty.xml()), sim, e, r, seen)?;
        if r == 0 && sim.st == St::Init {
            sim.engine |= refs
                .iter()
                .any(|v| v.is_some_and(|v| v.causality == Causality::Output));
        }
        Ok(())
    }
}

pub(super) fn same_or_close(a: f64, b: f64) -> bool {
    super::model::same_time(a, b)
}
