//! The FMI 3.0 instantiations the FMU must refuse (NULL and a logged reason: event mode,
//! intermediate variables, another model's token, over-long, blank or missing names and tokens,
//! the other interfaces' instantiation functions) or accept (no or an unusable resources folder
//! for a generic model, no logger, logging on).

use super::super::fuzzer::Fuzzer;
use super::super::model::Expect;
use super::Fmi3;
use anyhow::{Result, ensure};
use entrynav_fmi_host::{FmiInstance, Instantiate3, Log3, Slave3, host_logger3};
use entrynav_fmu::guid_of;
use entrynav_fmu::limits::{MAX_GUID_BYTES, MAX_STRING_BYTES};
use entrynav_fmu::vars::Model;
use rand::RngExt;
use std::ffi::{CString, c_void};

/// The strings the instantiation variants pass.
struct Strings {
    ok_name: CString,
    blank: CString,
    long_name: CString,
    other: CString,
    long_token: CString,
    nowhere: CString,
    token: CString,
    res: CString,
}

impl Fuzzer<Fmi3> {
    /// The strings of the variants: names, tokens (this model's, another model's, an over-long
    /// one) and resource paths.
    fn strings(&self) -> Result<Strings> {
        let other = Model::ALL
            .into_iter()
            .find(|m| m.identifier() != self.spec.identifier())
            .map(guid_of)
            .unwrap_or_default();
        Ok(Strings {
            ok_name: c"ok".to_owned(),
            blank: c"  ".to_owned(),
            long_name: CString::new("n".repeat(MAX_STRING_BYTES + 1))?,
            other: CString::new(other)?,
            long_token: CString::new("{".repeat(MAX_GUID_BYTES + 1))?,
            nowhere: c"/nonexistent/resources".to_owned(),
            token: self.version.token.clone(),
            res: self.version.resources.clone(),
        })
    }

    /// Variant `which` (0 to 12 but 8) of the instantiation and whether the FMU must accept it.
    fn variant<'s>(&mut self, which: u32, t: &'s Strings) -> (Instantiate3<'s>, bool) {
        let generic = !self.bound && self.spec.specific().is_none();
        let mut a = Instantiate3::new(Some(&t.ok_name), Some(&t.token), Some(&t.res));
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
                a.token = Some(&t.other);
                generic
            }
            3 => {
                a.token = Some(&t.long_token);
                false
            }
            4 => {
                a.name = Some(&t.long_name);
                false
            }
            5 => {
                a.name = Some(&t.blank);
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
            9 => {
                // No resources: a generic model needs none at instantiation.
                a.resources = None;
                self.spec.specific().is_none()
            }
            10 => {
                a.resources = Some(&t.nowhere);
                self.spec.specific().is_none()
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
        (a, accept)
    }

    /// An instantiation the FMU must refuse, or accept, chosen at random; an accepted instance
    /// answers an illegal call with fmi3Error (logged only if it has a logger) and is freed.
    pub(super) fn instantiate_variants(&mut self) -> Result<()> {
        let which = self.rng.random_range(0..13u32);
        if which == 8 {
            return self.other_interfaces();
        }
        let strings = self.strings()?;
        let (a, accept) = self.variant(which, &strings);
        if matches!(which, 3 | 4) {
            self.stats.over_bound += 1;
        }
        let s = Slave3::new(&self.version.api, &a);
        self.stats.calls += 1;
        let msgs = s.take_messages();
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
                !a.logger || msgs.iter().any(|m| m.status == 3),
                "{what}: NULL without a logged reason"
            );
            return Ok(());
        }
        // An illegal call: refused, with a reason if there is a logger.
        let r = s.exit_initialization_mode();
        let fresh = self.fresh();
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
        let api = std::sync::Arc::clone(&self.version.api);
        let log: Box<Log3> = Box::default();
        let env = &*log as *const Log3 as *mut c_void;
        let name = c"x";
        let me = self.rng.random_bool(0.5);
        // SAFETY: C strings, a log buffer that outlives the calls.
        let c = unsafe {
            if me {
                (api.fmi3InstantiateModelExchange)(
                    name.as_ptr(),
                    self.version.token.as_ptr(),
                    self.version.resources.as_ptr(),
                    0,
                    1,
                    env,
                    Some(host_logger3),
                )
            } else {
                (api.fmi3InstantiateScheduledExecution)(
                    name.as_ptr(),
                    self.version.token.as_ptr(),
                    self.version.resources.as_ptr(),
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
            msgs.iter().any(|m| m.status == 3),
            "{what}: NULL without a logged reason"
        );
        self.messages(what, &msgs)
    }
}
