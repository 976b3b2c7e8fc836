//! fmi2Get* and fmi2Set*: variable values across the C ABI.

use super::args::{TextError, null_arg, slice, slice_mut, text};
use super::inner::Inner;
use super::logger::c_text;
use super::registry::status;
use super::types::{Fmi2Boolean, Fmi2Component, Fmi2Status};
use crate::instance::{Operation, Status};
use crate::limits::{MAX_STRING_BYTES, MAX_STRING_REFS, MAX_VALUE_REFS};
use crate::vars::{Type, Value};
use std::ffi::{CString, c_char, c_int};

fn get_values<T>(
    inner: &mut Inner,
    ty: Type,
    vr: *const u32,
    nvr: usize,
    out: *mut T,
    mut conv: impl FnMut(Value, &mut Vec<CString>) -> T,
) -> Status {
    let max = if ty == Type::String {
        MAX_STRING_REFS
    } else {
        MAX_VALUE_REFS
    };
    // SAFETY: the master passes `nvr` references and room for `nvr` values (nvr bounded first).
    let (Some(vrs), Some(out)) = (unsafe { slice(vr, nvr, max) }, unsafe {
        slice_mut(out, nvr, max)
    }) else {
        return null_arg(inner, Operation::getter(ty), "vr or value");
    };
    match inner.inst.get(ty, vrs) {
        Ok(values) => {
            // Strings handed out by fmi2GetString stay valid until the next fmi2GetString.
            if ty == Type::String {
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

/// `fmi2GetReal`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut f64,
) -> Fmi2Status {
    status(c, Operation::GetReal, |i| {
        get_values(i, Type::Real, vr, nvr, value, |v, _| match v {
            Value::Real(x) => x,
            _ => f64::NAN,
        })
    })
}

/// `fmi2GetInteger`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut c_int,
) -> Fmi2Status {
    status(c, Operation::GetInteger, |i| {
        get_values(i, Type::Integer, vr, nvr, value, |v, _| match v {
            Value::Integer(x) => x,
            _ => 0,
        })
    })
}

/// `fmi2GetBoolean`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    status(c, Operation::GetBoolean, |i| {
        get_values(i, Type::Boolean, vr, nvr, value, |v, _| {
            matches!(v, Value::Boolean(true)) as Fmi2Boolean
        })
    })
}

/// `fmi2GetString`: the returned strings stay valid until the next fmi2GetString call on the
/// same instance (or its freeing).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut *const c_char,
) -> Fmi2Status {
    status(c, Operation::GetString, |i| {
        get_values(i, Type::String, vr, nvr, value, |v, store| {
            let s = match v {
                Value::String(s) => c_text(&s),
                _ => CString::default(),
            };
            let p = s.as_ptr();
            store.push(s);
            p
        })
    })
}

/// `max`: the bound on `nvr` ([`MAX_STRING_REFS`] for strings, each of which is copied).
#[allow(clippy::too_many_arguments)]
fn set_values<T: Copy>(
    inner: &mut Inner,
    ty: Type,
    vr: *const u32,
    nvr: usize,
    value: *const T,
    max: usize,
    mut conv: impl FnMut(T) -> Result<Value, TextError>,
) -> Status {
    let func = Operation::setter(ty);
    // SAFETY: the master passes `nvr` references and values (nvr bounded first).
    let (Some(vrs), Some(vals)) = (unsafe { slice(vr, nvr, max) }, unsafe {
        slice(value, nvr, max)
    }) else {
        return null_arg(inner, func, "vr or value");
    };
    let mut values = Vec::with_capacity(nvr);
    for v in vals {
        match conv(*v) {
            Ok(v) => values.push(v),
            Err(e) => {
                return inner
                    .inst
                    .error(&format!("{func}: {}", e.describe("a string value")));
            }
        }
    }
    inner.inst.set(ty, vrs, values)
}

/// `fmi2SetReal`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const f64,
) -> Fmi2Status {
    status(c, Operation::SetReal, |i| {
        set_values(i, Type::Real, vr, nvr, value, MAX_VALUE_REFS, |x| {
            Ok(Value::Real(x))
        })
    })
}

/// `fmi2SetInteger`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const c_int,
) -> Fmi2Status {
    status(c, Operation::SetInteger, |i| {
        set_values(i, Type::Integer, vr, nvr, value, MAX_VALUE_REFS, |x| {
            Ok(Value::Integer(x))
        })
    })
}

/// `fmi2SetBoolean`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    status(c, Operation::SetBoolean, |i| {
        set_values(i, Type::Boolean, vr, nvr, value, MAX_VALUE_REFS, |x| {
            Ok(Value::Boolean(x != 0))
        })
    })
}

/// `fmi2SetString`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const *const c_char,
) -> Fmi2Status {
    status(c, Operation::SetString, |i| {
        set_values(i, Type::String, vr, nvr, value, MAX_STRING_REFS, |p| {
            // SAFETY: each value is null (rejected) or a C string.
            unsafe { text(p, MAX_STRING_BYTES) }.map(|s| Value::String(s.to_string()))
        })
    })
}
