//! The variables as the fuzzer calls them: every value reference with the value type of the
//! function that reads and writes it, what it is, and how many values it holds. FMI 2.0 has the
//! table's scalars (Real as Float64, Integer and its Enumerations as Int32); FMI 3.0 has them
//! with Enumerations as Int64, then `time`, the structural parameter and the arrays.

use entrynav_fmu::instance::Type3;
use entrynav_fmu::vars::fmi3::{Extra, extras, state_slots};
use entrynav_fmu::vars::{ModelSpec, Type};

/// What a variable is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum What {
    /// A scalar of the shared table (its index = value reference).
    Scalar(usize),
    /// `time`, the independent variable (FMI 3.0).
    Time,
    /// `n_state_slots`, the structural parameter (FMI 3.0).
    Slots,
    /// `est_x`, `est_sigma` or `est_covariance` (FMI 3.0).
    Array(Extra),
}

/// A variable of the description.
#[derive(Debug, Clone, Copy)]
pub(super) struct Variable {
    pub(super) vr: u32,
    /// The value type of its getter and setter.
    pub(super) ty: Type3,
    pub(super) what: What,
    /// The number of values it holds.
    pub(super) len: usize,
}

/// The table's scalars of `spec`, an Enumeration read and written as `enumeration`.
fn scalars(spec: &ModelSpec, enumeration: Type3) -> Vec<Variable> {
    spec.vars()
        .iter()
        .enumerate()
        .map(|(i, v)| Variable {
            vr: v.vr,
            ty: match v.ty {
                Type::Real => Type3::Float64,
                Type::Integer if v.declared.is_some() => enumeration,
                Type::Integer => Type3::Int32,
                Type::Boolean => Type3::Boolean,
                Type::String => Type3::String,
            },
            what: What::Scalar(i),
            len: 1,
        })
        .collect()
}

/// The variables of the FMI 2.0 description of `spec`.
pub(super) fn fmi2_variables(spec: &ModelSpec) -> Vec<Variable> {
    scalars(spec, Type3::Int32)
}

/// The variables of the FMI 3.0 description of `spec`: the scalars with their FMI 2.0 value
/// references (an Enumeration as Int64), then `time`, `n_state_slots` and the arrays.
pub(super) fn fmi3_variables(spec: &ModelSpec) -> Vec<Variable> {
    let slots = state_slots(spec);
    let mut out = scalars(spec, Type3::Int64);
    for x in extras(spec) {
        let (ty, what) = match x.extra {
            Extra::Time => (Type3::Float64, What::Time),
            Extra::Slots => (Type3::UInt64, What::Slots),
            e => (Type3::Float64, What::Array(e)),
        };
        out.push(Variable {
            vr: x.vr,
            ty,
            what,
            len: x.len(slots),
        });
    }
    out
}
