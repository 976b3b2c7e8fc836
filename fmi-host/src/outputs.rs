//! Reading all outputs of a model the same way through the host ([`Slave::get_all`]) and from an
//! in-process instance ([`in_process_get_all`]), as bit patterns that `entrynav-dev fmu check`
//! compares.

use crate::error::{HostError, Result};
use crate::slave::Slave;
use entrynav_fmu::instance::{Instance, Operation};
use entrynav_fmu::vars::{Causality, Type, Value, Var};

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

impl Slave {
    /// All values of `groups` (one call per type), as f64 bit patterns / integers.
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
