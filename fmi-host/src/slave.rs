//! One instance of a loaded FMU through the host ([`Slave`]), and reading all outputs of a slave or
//! of an in-process instance the same way.

use crate::api::{Api, Callbacks, Comp, host_logger};
use crate::{HostError, Result, Unpacked};
use entrynav_fmu::instance::{Instance, Operation};
use entrynav_fmu::vars::{Causality, Type, Value, Var};
use std::ffi::{CString, c_int, c_void};
use std::path::Path;
use std::sync::Mutex;

/// One instance through the host.
pub struct Slave<'a> {
    /// The library's functions.
    pub api: &'a Api,
    /// The instance.
    pub c: Comp,
    /// Messages the instance logged: (status, text).
    pub log: Box<Mutex<Vec<(i32, String)>>>,
    _callbacks: Box<Callbacks>,
}

impl<'a> Slave<'a> {
    /// Instantiate `u`'s model as co-simulation slave `name` with `guid` and the resource URI
    /// `resources`, logging on.
    pub fn new(u: &'a Unpacked, name: &str, guid: &str, resources: &str) -> Result<Slave<'a>> {
        let log: Box<Mutex<Vec<(i32, String)>>> = Box::new(Mutex::new(Vec::new()));
        let callbacks = Box::new(Callbacks {
            logger: Some(host_logger),
            allocate: None,
            free: None,
            step_finished: None,
            env: &*log as *const _ as *mut c_void,
        });
        let (n, g, r) = (
            CString::new(name)?,
            CString::new(guid)?,
            CString::new(resources)?,
        );
        // SAFETY: valid C strings and callbacks that outlive the instance.
        let c = unsafe {
            (u.api.fmi2Instantiate)(n.as_ptr(), 1, g.as_ptr(), r.as_ptr(), &*callbacks, 0, 0)
        };
        let s = Slave {
            api: &u.api,
            c,
            log,
            _callbacks: callbacks,
        };
        if c.is_null() {
            return Err(HostError::Instantiate(s.messages()));
        }
        Ok(s)
    }

    /// The messages logged so far.
    pub fn messages(&self) -> Vec<(i32, String)> {
        self.log.lock().map(|l| l.clone()).unwrap_or_default()
    }

    /// Set one variable; returns the fmi2Status.
    pub fn set(&self, v: &Var, val: &Value) -> i32 {
        let vr = [v.vr];
        // SAFETY: one reference and one value of the right type.
        unsafe {
            match val {
                Value::Real(x) => (self.api.fmi2SetReal)(self.c, vr.as_ptr(), 1, x),
                Value::Integer(x) => (self.api.fmi2SetInteger)(self.c, vr.as_ptr(), 1, x),
                Value::Boolean(x) => {
                    (self.api.fmi2SetBoolean)(self.c, vr.as_ptr(), 1, &(*x as c_int))
                }
                Value::String(s) => {
                    let cs = CString::new(s.as_str()).unwrap_or_default();
                    (self.api.fmi2SetString)(self.c, vr.as_ptr(), 1, &cs.as_ptr())
                }
            }
        }
    }

    /// All values of `vars` (one call per type), as f64 bit patterns / integers.
    pub fn get_all(&self, groups: &OutputGroups) -> Result<Vec<u64>> {
        let mut out = Vec::new();
        let mut r = vec![0.0; groups.real.len()];
        let mut i = vec![0; groups.int.len()];
        let mut b = vec![0; groups.bool.len()];
        // SAFETY: buffers sized to the reference lists.
        let st = unsafe {
            [
                (self.api.fmi2GetReal)(self.c, groups.real.as_ptr(), r.len(), r.as_mut_ptr()),
                (self.api.fmi2GetInteger)(self.c, groups.int.as_ptr(), i.len(), i.as_mut_ptr()),
                (self.api.fmi2GetBoolean)(self.c, groups.bool.as_ptr(), b.len(), b.as_mut_ptr()),
            ]
        };
        if st != [0, 0, 0] {
            return Err(HostError::Call {
                call: "fmi2Get*",
                status: st.to_vec(),
                messages: self.messages(),
            });
        }
        out.extend(r.iter().map(|x| x.to_bits()));
        out.extend(i.iter().map(|x| *x as u64));
        out.extend(b.iter().map(|x| (*x != 0) as u64));
        Ok(out)
    }
}

impl Drop for Slave<'_> {
    fn drop(&mut self) {
        // SAFETY: our instance (or null).
        unsafe { (self.api.fmi2FreeInstance)(self.c) };
    }
}

/// The output value references of a model, by type.
pub struct OutputGroups {
    /// Real outputs.
    pub real: Vec<u32>,
    /// Integer outputs.
    pub int: Vec<u32>,
    /// Boolean outputs.
    pub bool: Vec<u32>,
}

/// The output references of `vars`, grouped by type.
pub fn output_groups(vars: &[Var]) -> OutputGroups {
    let pick = |t: Type| {
        vars.iter()
            .filter(|v| v.causality == Causality::Output && v.ty == t)
            .map(|v| v.vr)
            .collect()
    };
    OutputGroups {
        real: pick(Type::Real),
        int: pick(Type::Integer),
        bool: pick(Type::Boolean),
    }
}

/// [`Slave::get_all`] on an in-process instance.
pub fn in_process_get_all(inst: &mut Instance, g: &OutputGroups) -> Result<Vec<u64>> {
    let mut out = Vec::new();
    for (t, vrs) in [
        (Type::Real, &g.real),
        (Type::Integer, &g.int),
        (Type::Boolean, &g.bool),
    ] {
        let vals = inst.get(t, vrs).map_err(|status| HostError::InProcess {
            call: Operation::getter(t).name(),
            status,
        })?;
        out.extend(vals.into_iter().map(|v| match v {
            Value::Real(x) => x.to_bits(),
            Value::Integer(x) => x as u64,
            Value::Boolean(x) => x as u64,
            Value::String(_) => 0,
        }));
    }
    Ok(out)
}

/// The `file://` URI of a folder, percent-encoded.
pub fn file_uri(dir: &Path) -> String {
    let mut s = String::from("file://");
    for b in dir.to_string_lossy().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => {
                s.push(b as char)
            }
            _ => s.push_str(&format!("%{b:02X}")),
        }
    }
    s
}
