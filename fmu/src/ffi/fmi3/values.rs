//! fmi3Get* and fmi3Set* of the types this FMU has (Float64, Int32, Int64 for Enumerations,
//! UInt64 for the structural parameter, Boolean, String): value references resolved by the
//! instance ([`crate::instance::Ref3`]), arrays expanded row-major, `nValues` checked against
//! what the references hold before any value is read or written.

use super::super::args::{TextError, slice, slice_mut, text};
use super::super::inner::Inner;
use super::super::logger::c_text;
use super::super::registry::status;
use super::lifecycle::{Fmi3Boolean, Fmi3Instance, Fmi3Status};
use crate::instance::Type3;
use crate::instance::{Operation, Status};
use crate::limits::{MAX_STRING_BYTES, MAX_STRING_REFS, MAX_VALUE_REFS};
use crate::vars::{Type, Value};
use std::ffi::{CString, c_char};

/// The instance operation whose allowed states a getter or setter of `ty` has.
fn op(ty: Type3, get: bool) -> Operation {
    let t = match ty {
        Type3::Float64 => Type::Real,
        Type3::Int32 | Type3::Int64 | Type3::UInt64 => Type::Integer,
        Type3::Boolean => Type::Boolean,
        Type3::String => Type::String,
    };
    if get {
        Operation::getter(t)
    } else {
        Operation::setter(t)
    }
}

/// Why a value handed to an fmi3Set function is refused.
#[derive(Debug, thiserror::Error)]
enum BadValue {
    /// An Int64 that is no item of the Enumeration (items are Int32).
    #[error("value {0} is not an item of the Enumeration")]
    NotItem(i64),
    /// A UInt64 past the structural parameter's range.
    #[error("value {0} is out of range")]
    OutOfRange(u64),
    /// A string that cannot be read.
    #[error("{}", .0.describe("a string value"))]
    Text(TextError),
}

fn max_refs(ty: Type3) -> usize {
    if ty == Type3::String {
        MAX_STRING_REFS
    } else {
        MAX_VALUE_REFS
    }
}

#[allow(clippy::too_many_arguments)]
fn get_values<T>(
    inner: &mut Inner,
    func: &'static str,
    ty: Type3,
    vr: *const u32,
    nvr: usize,
    out: *mut T,
    n_values: usize,
    mut conv: impl FnMut(Value, &mut Vec<CString>) -> T,
) -> Status {
    if let Err(s) = inner.inst.check_as(op(ty, true), func) {
        return s;
    }
    let max = max_refs(ty);
    // SAFETY: the master passes `nvr` references (nvr bounded first).
    let Some(vrs) = (unsafe { slice(vr, nvr, max) }) else {
        return inner.inst.error(&format!(
            "{func}: valueReferences is a null pointer, or nValueReferences = {nvr} is over the limit ({max})"
        ));
    };
    let (refs, n) = match inner.inst.resolve3(func, ty, vrs) {
        Ok(r) => r,
        Err(s) => return s,
    };
    if n != n_values {
        return inner.inst.error(&format!(
            "{func}: nValues = {n_values}, but the {nvr} variables hold {n} values"
        ));
    }
    // SAFETY: the master passes room for `nValues` values (checked equal to `n`, bounded).
    let Some(out) = (unsafe { slice_mut(out, n, max) }) else {
        return inner.inst.error(&format!(
            "{func}: values is a null pointer, or nValues = {n} is over the limit ({max})"
        ));
    };
    match inner.inst.get3(ty, &refs) {
        Ok(values) => {
            // Strings handed out by fmi3GetString stay valid until the next fmi3GetString.
            if ty == Type3::String {
                inner.strings.clear();
            }
            for (o, v) in out.iter_mut().zip(values) {
                *o = conv(v, &mut inner.strings);
            }
            Status::Ok
        }
        Err(s) => s,
    }
}

#[allow(clippy::too_many_arguments)]
fn set_values<T: Copy>(
    inner: &mut Inner,
    func: &'static str,
    ty: Type3,
    vr: *const u32,
    nvr: usize,
    value: *const T,
    n_values: usize,
    mut conv: impl FnMut(T) -> Result<Value, BadValue>,
) -> Status {
    if let Err(s) = inner.inst.check_as(op(ty, false), func) {
        return s;
    }
    let max = max_refs(ty);
    // SAFETY: the master passes `nvr` references (nvr bounded first).
    let Some(vrs) = (unsafe { slice(vr, nvr, max) }) else {
        return inner.inst.error(&format!(
            "{func}: valueReferences is a null pointer, or nValueReferences = {nvr} is over the limit ({max})"
        ));
    };
    let (refs, n) = match inner.inst.resolve3(func, ty, vrs) {
        Ok(r) => r,
        Err(s) => return s,
    };
    if n != n_values {
        return inner.inst.error(&format!(
            "{func}: nValues = {n_values}, but the {nvr} variables hold {n} values"
        ));
    }
    // SAFETY: the master passes `nValues` values (checked equal to `n`, bounded).
    let Some(vals) = (unsafe { slice(value, n, max) }) else {
        return inner.inst.error(&format!(
            "{func}: values is a null pointer, or nValues = {n} is over the limit ({max})"
        ));
    };
    let mut values = Vec::with_capacity(n);
    for v in vals {
        match conv(*v) {
            Ok(v) => values.push(v),
            Err(e) => return inner.inst.error(&format!("{func}: {e}")),
        }
    }
    inner.inst.set3(func, ty, &refs, values)
}

macro_rules! getter {
    ($name:ident, $c:literal, $ty:expr, $t:ty, |$v:ident, $store:ident| $conv:expr) => {
        #[doc = concat!("`", $c, "`.")]
        ///
        /// # Safety
        /// FMI 3.0 calling conventions.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vr: *const u32,
            nvr: usize,
            values: *mut $t,
            n_values: usize,
        ) -> Fmi3Status {
            status(c, $c, |i| {
                get_values(i, $c, $ty, vr, nvr, values, n_values, |$v, $store| $conv)
            })
        }
    };
}

macro_rules! setter {
    ($name:ident, $c:literal, $ty:expr, $t:ty, |$v:ident| $conv:expr) => {
        #[doc = concat!("`", $c, "`.")]
        ///
        /// # Safety
        /// FMI 3.0 calling conventions.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vr: *const u32,
            nvr: usize,
            values: *const $t,
            n_values: usize,
        ) -> Fmi3Status {
            status(c, $c, |i| {
                set_values(i, $c, $ty, vr, nvr, values, n_values, |$v| $conv)
            })
        }
    };
}

getter!(
    fmi3GetFloat64,
    "fmi3GetFloat64",
    Type3::Float64,
    f64,
    |v, _s| match v {
        Value::Real(x) => x,
        _ => 0.0,
    }
);
getter!(
    fmi3GetInt32,
    "fmi3GetInt32",
    Type3::Int32,
    i32,
    |v, _s| match v {
        Value::Integer(x) => x,
        _ => 0,
    }
);
getter!(
    fmi3GetInt64,
    "fmi3GetInt64",
    Type3::Int64,
    i64,
    |v, _s| match v {
        Value::Integer(x) => x as i64,
        _ => 0,
    }
);
getter!(
    fmi3GetUInt64,
    "fmi3GetUInt64",
    Type3::UInt64,
    u64,
    |v, _s| match v {
        Value::Integer(x) => x.max(0) as u64,
        _ => 0,
    }
);
getter!(
    fmi3GetBoolean,
    "fmi3GetBoolean",
    Type3::Boolean,
    Fmi3Boolean,
    |v, _s| { matches!(v, Value::Boolean(true)) as Fmi3Boolean }
);
getter!(
    fmi3GetString,
    "fmi3GetString",
    Type3::String,
    *const c_char,
    |v, store| {
        let s = match v {
            Value::String(s) => c_text(&s),
            _ => CString::default(),
        };
        let p = s.as_ptr();
        store.push(s);
        p
    }
);

setter!(fmi3SetFloat64, "fmi3SetFloat64", Type3::Float64, f64, |x| {
    Ok(Value::Real(x))
});
setter!(fmi3SetInt32, "fmi3SetInt32", Type3::Int32, i32, |x| Ok(
    Value::Integer(x)
));
setter!(fmi3SetInt64, "fmi3SetInt64", Type3::Int64, i64, |x| {
    i32::try_from(x)
        .map(Value::Integer)
        .map_err(|_| BadValue::NotItem(x))
});
setter!(fmi3SetUInt64, "fmi3SetUInt64", Type3::UInt64, u64, |x| {
    i32::try_from(x)
        .map(Value::Integer)
        .map_err(|_| BadValue::OutOfRange(x))
});
setter!(
    fmi3SetBoolean,
    "fmi3SetBoolean",
    Type3::Boolean,
    Fmi3Boolean,
    |x| Ok(Value::Boolean(x != 0))
);
setter!(
    fmi3SetString,
    "fmi3SetString",
    Type3::String,
    *const c_char,
    |p| {
        // SAFETY: each value is null (rejected) or a C string.
        unsafe { text(p, MAX_STRING_BYTES) }
            .map(|s| Value::String(s.to_string()))
            .map_err(BadValue::Text)
    }
);
