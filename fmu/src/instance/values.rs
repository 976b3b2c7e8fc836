//! Variable access of an instance: fmi2Get* and fmi2Set* by value reference, and the parameter and
//! input values the engine reads.

use super::allowed::Operation;
use super::machine::Instance;
use super::outputs::validate;
use super::status::Status;
use crate::state::Phase;
use crate::vars::{Causality, Key, Type, Value};

impl Instance {
    pub(super) fn param_str(&self, key: Key) -> String {
        match self.value_of(key) {
            Some(Value::String(s)) => s.clone(),
            _ => String::new(),
        }
    }

    pub(super) fn value_of(&self, key: Key) -> Option<&Value> {
        self.vars
            .iter()
            .position(|v| v.key == key)
            .and_then(|i| self.values[i].as_ref())
    }

    fn lookup(&self, func: Operation, vr: u32, ty: Type) -> Result<usize, Status> {
        match self.vars.get(vr as usize) {
            Some(v) if v.ty == ty => Ok(vr as usize),
            Some(v) => Err(self.error(&format!(
                "{func}: value reference {vr} ('{}') is a {} variable, not {}",
                v.name,
                v.ty.xml(),
                ty.xml()
            ))),
            None => Err(self.error(&format!(
                "{func}: unknown value reference {vr} ({} has value references 0 to {})",
                self.spec.identifier(),
                self.vars.len().saturating_sub(1)
            ))),
        }
    }

    /// fmi2GetReal / Integer / Boolean / String: the values of `vrs`, all of type `ty`.
    pub fn get(&mut self, ty: Type, vrs: &[u32]) -> Result<Vec<Value>, Status> {
        let func = Operation::getter(ty);
        self.check(func)?;
        let mut idx = Vec::with_capacity(vrs.len());
        for vr in vrs {
            idx.push(self.lookup(func, *vr, ty)?);
        }
        if self.engine.is_none()
            && idx
                .iter()
                .any(|i| self.vars[*i].causality == Causality::Output)
            && let Err(e) = self.ensure_engine()
        {
            return Err(self.error(&format!("{func}: cannot compute outputs: {e}")));
        }
        Ok(idx
            .iter()
            .map(|&i| match &self.values[i] {
                Some(v) => v.clone(),
                None => self.output(self.vars[i].key),
            })
            .collect())
    }

    /// fmi2SetReal / Integer / Boolean / String: the `values` of `vrs`, all of type `ty`; a
    /// rejected call changes nothing.
    pub fn set(&mut self, ty: Type, vrs: &[u32], values: Vec<Value>) -> Status {
        let func = Operation::setter(ty);
        if let Err(s) = self.check(func) {
            return s;
        }
        if let Some(v) = values.iter().find(|v| v.ty() != ty) {
            return self.error(&format!(
                "{func}: a {} value among {} values",
                v.ty().xml(),
                ty.xml()
            ));
        }
        if vrs.len() != values.len() {
            return self.error(&format!(
                "{func}: {} references but {} values",
                vrs.len(),
                values.len()
            ));
        }
        for (vr, val) in vrs.iter().zip(&values) {
            let i = match self.lookup(func, *vr, ty) {
                Ok(i) => i,
                Err(s) => return s,
            };
            let v = &self.vars[i];
            match v.causality {
                Causality::Output => {
                    return self.error(&format!(
                        "{func}: '{}' is an output and cannot be set",
                        v.name
                    ));
                }
                Causality::Parameter if self.phase == Phase::StepComplete => {
                    return self.error(&format!(
                        "{func}: parameter '{}' is fixed after initialisation (reset the instance to change it)",
                        v.name
                    ));
                }
                _ => {}
            }
            if let Err(e) = validate(v.key, val) {
                return self.error(&format!("{func}: '{}': {e}", v.name));
            }
        }
        for (vr, val) in vrs.iter().zip(values) {
            let i = *vr as usize;
            if self.vars[i].causality == Causality::Parameter
                && self.values[i].as_ref() != Some(&val)
            {
                self.engine = None;
            }
            self.values[i] = Some(val);
        }
        Status::Ok
    }

    /// A Boolean input or parameter; `default` when the model has no such variable.
    pub(super) fn input_bool(&self, key: Key, default: bool) -> bool {
        match self.value_of(key) {
            Some(Value::Boolean(b)) => *b,
            _ => default,
        }
    }

    pub(super) fn input_real(&self, key: Key) -> f64 {
        match self.value_of(key) {
            Some(Value::Real(x)) => *x,
            _ => 0.0,
        }
    }
}
