//! Co-simulation: fmi2DoStep, fmi2CancelStep and the status queries; and the capabilities this
//! FMU does not have (directional derivatives, input derivatives), answered with fmi2Error.

use super::args::null_arg;
use super::inner::Inner;
use super::registry::status;
use super::types::{Fmi2Boolean, Fmi2Component, Fmi2Status};
use crate::instance::{Operation, Status};
use std::ffi::{c_char, c_int};

use crate::instance::{StatusAnswer, StatusType};

/// `fmi2GetDirectionalDerivative`: not supported (providesDirectionalDerivative = false).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Fmi2Component,
    _unknown: *const u32,
    _n_unknown: usize,
    _known: *const u32,
    _n_known: usize,
    _dv_known: *const f64,
    _dv_unknown: *mut f64,
) -> Fmi2Status {
    status(c, Operation::GetDirectionalDerivative, |i| {
        i.inst.unsupported(
            Operation::GetDirectionalDerivative,
            "directional derivatives (providesDirectionalDerivative = false)",
        )
    })
}

/// `fmi2SetRealInputDerivatives`: not supported (canInterpolateInputs = false).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Fmi2Component,
    _vr: *const u32,
    _nvr: usize,
    _order: *const c_int,
    _value: *const f64,
) -> Fmi2Status {
    status(c, Operation::SetRealInputDerivatives, |i| {
        i.inst.unsupported(
            Operation::SetRealInputDerivatives,
            "input derivatives (canInterpolateInputs = false)",
        )
    })
}

/// `fmi2GetRealOutputDerivatives`: not supported (maxOutputDerivativeOrder = 0).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Fmi2Component,
    _vr: *const u32,
    _nvr: usize,
    _order: *const c_int,
    _value: *mut f64,
) -> Fmi2Status {
    status(c, Operation::GetRealOutputDerivatives, |i| {
        i.inst.unsupported(
            Operation::GetRealOutputDerivatives,
            "output derivatives (maxOutputDerivativeOrder = 0)",
        )
    })
}

/// `fmi2DoStep` (synchronous).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: Fmi2Component,
    current_communication_point: f64,
    communication_step_size: f64,
    _no_set_fmu_state_prior: Fmi2Boolean,
) -> Fmi2Status {
    status(c, Operation::DoStep, |i| {
        i.inst
            .do_step(current_communication_point, communication_step_size)
    })
}

/// `fmi2CancelStep`: steps are synchronous, so there is never a step to cancel.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
    status(c, Operation::CancelStep, |i| i.inst.cancel_step())
}

/// A status query: `answer` turns the instance's answer into the value written to `out`.
fn status_query<T>(
    inner: &mut Inner,
    ty: StatusType,
    kind: c_int,
    out: *mut T,
    answer: impl FnOnce(StatusAnswer) -> Option<T>,
) -> Status {
    let func = ty.function();
    let a = match inner.inst.query_status(kind, ty) {
        Ok(a) => a,
        Err(s) => return s,
    };
    if out.is_null() {
        return null_arg(inner, func, "value");
    }
    match answer(a) {
        Some(v) => {
            // SAFETY: non-null pointer to the master's variable.
            unsafe { *out = v };
            Status::Ok
        }
        None => inner
            .inst
            .error(&format!("{func}: internal error (answer of another type)")),
    }
}

/// `fmi2GetStatus`: fmi2DoStepStatus is never available (steps are synchronous): fmi2Discard.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Status,
) -> Fmi2Status {
    status(c, Operation::GetStatus, |i| {
        status_query(i, StatusType::Status, kind, value, |_| None)
    })
}

/// `fmi2GetRealStatus`: fmi2LastSuccessfulTime.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut f64,
) -> Fmi2Status {
    status(c, Operation::GetRealStatus, |i| {
        status_query(i, StatusType::Real, kind, value, |a| match a {
            StatusAnswer::Real(t) => Some(t),
            StatusAnswer::Boolean(_) => None,
        })
    })
}

/// `fmi2GetIntegerStatus`: FMI 2.0 defines no Integer status kind, so every kind is refused.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut c_int,
) -> Fmi2Status {
    status(c, Operation::GetIntegerStatus, |i| {
        status_query(i, StatusType::Integer, kind, value, |_| None)
    })
}

/// `fmi2GetBooleanStatus`: fmi2Terminated (always false: the FMU never asks to stop).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    status(c, Operation::GetBooleanStatus, |i| {
        status_query(i, StatusType::Boolean, kind, value, |a| match a {
            StatusAnswer::Boolean(b) => Some(b as Fmi2Boolean),
            StatusAnswer::Real(_) => None,
        })
    })
}

/// `fmi2GetStringStatus`: fmi2PendingStatus is never available (fmi2Discard).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut *const c_char,
) -> Fmi2Status {
    status(c, Operation::GetStringStatus, |i| {
        status_query(i, StatusType::String, kind, value, |_| None)
    })
}
