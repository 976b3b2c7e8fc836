//! What an instance answers for the FMI 3.0-only variables ([`crate::vars::fmi3`]) and the
//! FMI 3.0 type rules of its scalar variables (an Enumeration is read and written as `Int64`,
//! never as `Int32`).

use super::allowed::Operation;
use super::machine::Instance;
use super::status::Status;
use crate::vars::fmi3::{Extra, Var3, extras, state_slots};
use crate::vars::{Causality, Key, Type, Value};

/// How an FMI 3.0 value reference resolves.
#[derive(Debug, Clone, PartialEq)]
pub enum Ref3 {
    /// A scalar of the shared table (its index).
    Scalar(usize),
    /// An FMI 3.0-only variable.
    Extra(Var3),
}

/// The FMI 3.0 variable types this FMU has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Type3 {
    /// fmi3Float64: Real scalars, `time` and the arrays.
    Float64,
    /// fmi3Int32: Integer scalars that are not Enumerations.
    Int32,
    /// fmi3Int64: the Enumerations.
    Int64,
    /// fmi3UInt64: the structural parameter.
    UInt64,
    /// fmi3Boolean.
    Boolean,
    /// fmi3String.
    String,
}

impl Type3 {
    /// Its name in FMI 3.0 (`Float64`, …).
    pub fn name(self) -> &'static str {
        match self {
            Type3::Float64 => "Float64",
            Type3::Int32 => "Int32",
            Type3::Int64 => "Int64",
            Type3::UInt64 => "UInt64",
            Type3::Boolean => "Boolean",
            Type3::String => "String",
        }
    }

    /// The table type its scalars have.
    fn scalar(self) -> Option<Type> {
        match self {
            Type3::Float64 => Some(Type::Real),
            Type3::Int32 | Type3::Int64 => Some(Type::Integer),
            Type3::Boolean => Some(Type::Boolean),
            Type3::String => Some(Type::String),
            Type3::UInt64 => None,
        }
    }
}

impl Instance {
    /// The FMI 3.0 type of value reference `vr`, if it names a variable.
    fn type3_of(&self, vr: u32) -> Option<(Type3, Ref3)> {
        if let Some(v) = self.vars.get(vr as usize) {
            let t = match v.ty {
                Type::Real => Type3::Float64,
                Type::Integer if v.declared.is_some() => Type3::Int64,
                Type::Integer => Type3::Int32,
                Type::Boolean => Type3::Boolean,
                Type::String => Type3::String,
            };
            return Some((t, Ref3::Scalar(vr as usize)));
        }
        let x = extras(&self.spec).into_iter().find(|x| x.vr == vr)?;
        let t = match x.extra {
            Extra::Slots => Type3::UInt64,
            _ => Type3::Float64,
        };
        Some((t, Ref3::Extra(x)))
    }

    /// The variables of `vrs`, all of FMI 3.0 type `ty`, and how many values they hold; an
    /// unknown reference or one of another type is an error naming it (`func` the fmi3 name).
    pub fn resolve3(
        &self,
        func: &str,
        ty: Type3,
        vrs: &[u32],
    ) -> Result<(Vec<Ref3>, usize), Status> {
        let slots = state_slots(&self.spec);
        let mut refs = Vec::with_capacity(vrs.len());
        let mut n = 0usize;
        for &vr in vrs {
            match self.type3_of(vr) {
                Some((t, r)) if t == ty => {
                    n += match &r {
                        Ref3::Scalar(_) => 1,
                        Ref3::Extra(x) => x.len(slots),
                    };
                    refs.push(r);
                }
                Some((t, _)) => {
                    return Err(self.error(&format!(
                        "{func}: value reference {vr} ('{}') is a {} variable, not {}",
                        self.name3(vr),
                        t.name(),
                        ty.name()
                    )));
                }
                None => {
                    return Err(self.error(&format!(
                        "{func}: unknown value reference {vr} ({} has value references 0 to {})",
                        self.spec.identifier(),
                        self.vars.len() + extras(&self.spec).len() - 1
                    )));
                }
            }
        }
        Ok((refs, n))
    }

    fn name3(&self, vr: u32) -> String {
        match self.type3_of(vr) {
            Some((_, Ref3::Scalar(i))) => self.vars[i].name.clone(),
            Some((_, Ref3::Extra(x))) => x.name.to_string(),
            None => String::new(),
        }
    }

    /// The values of `refs` (resolved by [`Instance::resolve3`] for type `ty`), arrays expanded
    /// row-major, in the order given.
    pub fn get3(&mut self, ty: Type3, refs: &[Ref3]) -> Result<Vec<Value>, Status> {
        let scalar_ty = ty.scalar().unwrap_or(Type::Integer);
        let scalars: Vec<u32> = refs
            .iter()
            .filter_map(|r| match r {
                Ref3::Scalar(i) => Some(*i as u32),
                Ref3::Extra(_) => None,
            })
            .collect();
        // The phase check, and the engine when an output is read, as for FMI 2.0.
        let mut values = self.get(scalar_ty, &scalars)?.into_iter();
        let needs_engine = refs
            .iter()
            .any(|r| matches!(r, Ref3::Extra(x) if x.is_array()));
        if needs_engine && self.engine.is_none() && self.ensure_engine().is_err() {
            let func = Operation::getter(scalar_ty);
            return Err(self.error(&format!(
                "{func}: cannot compute outputs (the parameters do not build a run)"
            )));
        }
        let slots = state_slots(&self.spec);
        let mut out = Vec::new();
        for r in refs {
            match r {
                Ref3::Scalar(_) => out.extend(values.next()),
                Ref3::Extra(x) => match x.extra {
                    Extra::Time => out.push(Value::Real(self.last_successful_time())),
                    Extra::Slots => out.push(Value::Integer(slots as i32)),
                    Extra::Estimate => {
                        out.extend((0..slots).map(|i| self.output(Key::EstX(i))));
                    }
                    Extra::Sigma => {
                        out.extend((0..slots).map(|i| self.output(Key::EstSigma(i))));
                    }
                    Extra::Covariance => out.extend(self.covariance(slots)),
                },
            }
        }
        Ok(out)
    }

    /// The filter covariance over `slots` × `slots` (0 outside the filter's dimension or when
    /// not finite, as every output).
    fn covariance(&self, slots: usize) -> Vec<Value> {
        let nav = self.engine.as_ref().and_then(|e| e.nav());
        let mut out = vec![Value::Real(0.0); slots * slots];
        if let Some(nav) = nav {
            let est = nav.estimate();
            let n = est.x.len().min(slots);
            for i in 0..n {
                for j in 0..n {
                    let p = est.p[i * est.x.len() + j];
                    out[i * slots + j] = Value::Real(if p.is_finite() { p } else { 0.0 });
                }
            }
        }
        out
    }

    /// Set `refs` (resolved for type `ty`) to `values`, already expanded; a rejected call changes
    /// nothing. The structural parameter accepts only its own value.
    pub fn set3(&mut self, func: &str, ty: Type3, refs: &[Ref3], values: Vec<Value>) -> Status {
        let scalar_ty = ty.scalar().unwrap_or(Type::Integer);
        let slots = state_slots(&self.spec);
        let mut scalar_vrs = Vec::new();
        let mut scalar_values = Vec::new();
        let mut vals = values.into_iter();
        for r in refs {
            match r {
                Ref3::Scalar(i) => {
                    scalar_vrs.push(*i as u32);
                    scalar_values.extend(vals.next());
                }
                Ref3::Extra(x) => {
                    let v = vals.next();
                    let ok = match x.extra {
                        Extra::Slots => {
                            if let Err(s) = self.check(Operation::setter(Type::Integer)) {
                                return s;
                            }
                            // Fixed variability: settable until initialisation ends, as the
                            // other fixed parameters.
                            if self.phase == crate::state::Phase::StepComplete {
                                return self.error(&format!(
                                    "{func}: '{}' is a fixed structural parameter and cannot be set after initialisation",
                                    x.name
                                ));
                            }
                            v == Some(Value::Integer(slots as i32))
                        }
                        _ => false,
                    };
                    if !ok {
                        let why = match x.extra {
                            Extra::Slots => format!(
                                "is fixed at {slots} by this model (configuration mode is not supported); got {}",
                                v.map(|v| v.xml()).unwrap_or_default()
                            ),
                            Extra::Time => "is the independent variable and cannot be set".into(),
                            _ => format!("is an {} and cannot be set", Causality::Output.xml()),
                        };
                        return self.error(&format!("{func}: '{}' {why}", x.name));
                    }
                }
            }
        }
        if scalar_vrs.is_empty() {
            return match self.check(Operation::setter(scalar_ty)) {
                Ok(()) => Status::Ok,
                Err(s) => s,
            };
        }
        self.set(scalar_ty, &scalar_vrs, scalar_values)
    }
}
