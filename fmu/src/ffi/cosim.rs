//! Co-simulation: fmi2DoStep, fmi2CancelStep and the status queries; and the capabilities this
//! FMU does not have (directional derivatives, input derivatives), answered with fmi2Error.

use super::*;

use crate::state::Phase::*;

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
    status(c, "fmi2GetDirectionalDerivative", |i| {
        i.inst.unsupported(
            "fmi2GetDirectionalDerivative",
            &[InitializationMode, StepComplete, Terminated, Error],
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
    status(c, "fmi2SetRealInputDerivatives", |i| {
        i.inst.unsupported(
            "fmi2SetRealInputDerivatives",
            &[Instantiated, InitializationMode, StepComplete],
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
    status(c, "fmi2GetRealOutputDerivatives", |i| {
        i.inst.unsupported(
            "fmi2GetRealOutputDerivatives",
            &[StepComplete, Terminated, Error],
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
    status(c, "fmi2DoStep", |i| {
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
    status(c, "fmi2CancelStep", |i| {
        i.inst.error(
            "fmi2CancelStep: Illegal call sequence (no asynchronous step is in progress; canRunAsynchronuously = false)",
        )
    })
}

fn status_query<T>(
    inner: &mut Inner,
    func: &str,
    kind: c_int,
    out: *mut T,
    answer: impl FnOnce(&Instance, c_int) -> Option<T>,
) -> Status {
    if let Err(s) = inner.inst.check_status_query(func) {
        return s;
    }
    if out.is_null() {
        return null_arg(inner, func, "value");
    }
    match answer(&inner.inst, kind) {
        Some(v) => {
            // SAFETY: non-null pointer to the master's variable.
            unsafe { *out = v };
            Status::Ok
        }
        None => {
            inner.inst.warn(&format!(
                "{func}: status kind {kind} is not available (fmi2Discard)"
            ));
            Status::Discard
        }
    }
}

/// `fmi2GetStatus`: only meaningful for asynchronous steps; answers fmi2Discard.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Status,
) -> Fmi2Status {
    status(c, "fmi2GetStatus", |i| {
        status_query(i, "fmi2GetStatus", kind, value, |_, _| None)
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
    status(c, "fmi2GetRealStatus", |i| {
        status_query(i, "fmi2GetRealStatus", kind, value, |inst, k| {
            (k == 2).then(|| inst.last_successful_time())
        })
    })
}

/// `fmi2GetIntegerStatus`: no integer status kinds exist in FMI 2.0 (fmi2Discard).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut c_int,
) -> Fmi2Status {
    status(c, "fmi2GetIntegerStatus", |i| {
        status_query(i, "fmi2GetIntegerStatus", kind, value, |_, _| None)
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
    status(c, "fmi2GetBooleanStatus", |i| {
        status_query(i, "fmi2GetBooleanStatus", kind, value, |_, k| {
            (k == 3).then_some(0)
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
    status(c, "fmi2GetStringStatus", |i| {
        status_query(i, "fmi2GetStringStatus", kind, value, |_, _| None)
    })
}
