//! One FMI 3.0 instance of the fuzzer ([`Inst`]: made by fmi3InstantiateCoSimulation with the
//! host's log callback, its messages taken after every call, freed on drop), and the
//! instantiations the FMU must refuse (NULL and a logged reason) or accept.

use super::model::{Expect, Sim};
use super::*;
use entrynav_fmi_host::{Inst3, Log3, host_logger3};
use entrynav_fmu::limits::{MAX_GUID_BYTES, MAX_STRING_BYTES};
use std::ffi::{CStr, c_void};

/// The arguments of an instantiation (null where `None`).
pub(super) struct Args<'s> {
    pub(super) name: Option<&'s CStr>,
    pub(super) token: Option<&'s CStr>,
    pub(super) resources: Option<&'s CStr>,
    pub(super) logging_on: bool,
    pub(super) event_mode_used: bool,
    /// requiredIntermediateVariables.
    pub(super) required: &'s [u32],
    /// Pass the host's log callback (else NULL: nothing may be logged, nothing may crash).
    pub(super) logger: bool,
}

impl<'s> Args<'s> {
    pub(super) fn new(
        name: Option<&'s CStr>,
        token: Option<&'s CStr>,
        resources: Option<&'s CStr>,
    ) -> Args<'s> {
        Args {
            name,
            token,
            resources,
            logging_on: false,
            event_mode_used: false,
            required: &[],
            logger: true,
        }
    }
}

/// One instance (or a refused instantiation: `c` null) with its message buffer.
pub(super) struct Inst<'a> {
    api: &'a Api3,
    pub(super) c: Inst3,
    log: Box<Log3>,
    freed: bool,
}

fn ptr(s: Option<&CStr>) -> *const std::ffi::c_char {
    s.map_or(std::ptr::null(), CStr::as_ptr)
}

impl<'a> Inst<'a> {
    /// fmi3InstantiateCoSimulation with `a`.
    pub(super) fn cosim(api: &'a Api3, a: &Args) -> Inst<'a> {
        let log: Box<Log3> = Box::default();
        let env = &*log as *const Log3 as *mut c_void;
        // SAFETY: null or C strings, `required.len()` references, and a log buffer that outlives
        // the instance (freed before the box is dropped).
        let c = unsafe {
            (api.fmi3InstantiateCoSimulation)(
                ptr(a.name),
                ptr(a.token),
                ptr(a.resources),
                0,
                a.logging_on as u8,
                a.event_mode_used as u8,
                0,
                a.required.as_ptr(),
                a.required.len(),
                env,
                a.logger.then_some(host_logger3 as _),
                None,
            )
        };
        Inst {
            api,
            c,
            log,
            freed: false,
        }
    }

    /// The messages logged since the last call, taken.
    pub(super) fn take(&self) -> Vec<Message3> {
        self.log
            .lock()
            .map(|mut l| std::mem::take(&mut *l))
            .unwrap_or_default()
    }

    /// fmi3FreeInstance (the token stays, for calls on a freed instance).
    pub(super) fn free(&mut self) {
        if !self.freed {
            // SAFETY: our instance, or null.
            unsafe { (self.api.fmi3FreeInstance)(self.c) };
            self.freed = true;
        }
    }
}

impl Drop for Inst<'_> {
    fn drop(&mut self) {
        self.free();
    }
}

impl Fuzzer<'_> {
    /// An instantiation the FMU must refuse, or accept, chosen at random; an accepted instance
    /// answers an illegal call with fmi3Error (logged only if it has a logger) and is freed.
    pub(super) fn instantiate_variants(&mut self) -> Result<()> {
        let u = self.u;
        let api = self.api;
        let other = Model::ALL
            .into_iter()
            .find(|m| m.identifier() != u.spec.identifier())
            .map(entrynav_fmu::guid_of)
            .unwrap_or_default();
        let (ok_name, blank, long_name) = (
            c"ok".to_owned(),
            c"  ".to_owned(),
            CString::new("n".repeat(MAX_STRING_BYTES + 1))?,
        );
        let (other, long_token) = (
            CString::new(other)?,
            CString::new("{".repeat(MAX_GUID_BYTES + 1))?,
        );
        let nowhere = c"/nonexistent/resources".to_owned();
        let (token, res) = (self.token.clone(), self.resources.clone());
        let generic = u.binding.is_none() && u.spec.specific().is_none();
        let mut a = Args::new(Some(&ok_name), Some(&token), Some(&res));
        let which = self.rng.random_range(0..13);
        let accept = match which {
            0 => {
                a.event_mode_used = true;
                false
            }
            1 => {
                a.required = &[0, 1];
                false
            }
            2 => {
                a.token = Some(&other);
                generic
            }
            3 => {
                a.token = Some(&long_token);
                false
            }
            4 => {
                a.name = Some(&long_name);
                false
            }
            5 => {
                a.name = Some(&blank);
                false
            }
            6 => {
                a.name = None;
                false
            }
            7 => {
                a.token = None;
                false
            }
            8 => return self.other_interfaces(),
            9 => {
                // No resources: a generic model needs none at instantiation.
                a.resources = None;
                u.spec.specific().is_none()
            }
            10 => {
                a.resources = Some(&nowhere);
                u.spec.specific().is_none()
            }
            11 => {
                a.logger = false;
                a.event_mode_used = self.rng.random_bool(0.5);
                !a.event_mode_used
            }
            _ => {
                a.logging_on = true;
                true
            }
        };
        if matches!(which, 3 | 4) {
            self.stats.over_bound += 1;
        }
        let s = Inst::cosim(api, &a);
        self.stats.calls += 1;
        let msgs = s.take();
        let what = format!("fmi3InstantiateCoSimulation variant {which}");
        ensure!(
            s.c.is_null() != accept,
            "{what} answered {:?}, expected {}; log: {msgs:?}",
            s.c,
            if accept { "an instance" } else { "NULL" }
        );
        self.messages(&what, &msgs)?;
        if s.c.is_null() {
            self.stats.refused_instances += 1;
            ensure!(
                !a.logger || msgs.iter().any(|m| m.0 == 3),
                "{what}: NULL without a logged reason"
            );
            return Ok(());
        }
        // An illegal call: refused, with a reason if there is a logger.
        // SAFETY: our instance.
        let r = unsafe { (api.fmi3ExitInitializationMode)(s.c) };
        let fresh = Sim::new(self.specific());
        if a.logger {
            self.expect(&s, "fmi3ExitInitializationMode", &fresh, Expect::Refused, r)?;
        } else {
            self.stats.calls += 1;
            self.stats.statuses[r.clamp(0, 4) as usize] += 1;
            ensure!(
                r == 3,
                "fmi3ExitInitializationMode in Instantiated, without a logger, answered {r}"
            );
        }
        self.free(s)
    }

    /// fmi3InstantiateModelExchange and fmi3InstantiateScheduledExecution: NULL, with a reason.
    fn other_interfaces(&mut self) -> Result<()> {
        let api = self.api;
        let log: Box<Log3> = Box::default();
        let env = &*log as *const Log3 as *mut c_void;
        let name = c"x";
        let me = self.rng.random_bool(0.5);
        // SAFETY: C strings, a log buffer that outlives the calls.
        let c = unsafe {
            if me {
                (api.fmi3InstantiateModelExchange)(
                    name.as_ptr(),
                    self.token.as_ptr(),
                    self.resources.as_ptr(),
                    0,
                    1,
                    env,
                    Some(host_logger3),
                )
            } else {
                (api.fmi3InstantiateScheduledExecution)(
                    name.as_ptr(),
                    self.token.as_ptr(),
                    self.resources.as_ptr(),
                    0,
                    1,
                    env,
                    Some(host_logger3),
                    None,
                    None,
                    None,
                )
            }
        };
        let what = if me {
            "fmi3InstantiateModelExchange"
        } else {
            "fmi3InstantiateScheduledExecution"
        };
        self.stats.calls += 1;
        self.stats.unsupported += 1;
        self.stats.refused_instances += 1;
        let msgs = log.lock().map(|l| l.clone()).unwrap_or_default();
        ensure!(c.is_null(), "{what} returned an instance");
        ensure!(
            msgs.iter().any(|m| m.0 == 3),
            "{what}: NULL without a logged reason"
        );
        self.messages(what, &msgs)
    }
}
