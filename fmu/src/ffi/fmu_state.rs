//! FMU states: get, set, free, serialise and deserialise (snapshots owned by the instance).

use super::args::{null_arg, slice, slice_mut};
use super::inner::Inner;
use super::registry::status;
use super::types::{Fmi2Component, Fmi2State, Fmi2Status};
use crate::instance::{Operation, Status};
use crate::limits::{MAX_SNAPSHOTS, MAX_STATE_BYTES};
use crate::state::Snapshot;

/// A snapshot pointer owned by this instance (null, foreign and freed pointers are rejected).
fn known(inner: &Inner, p: Fmi2State) -> bool {
    !p.is_null() && inner.snapshots.contains_key(&(p as usize))
}

/// Store `snap` in `*slot` (a state of this instance, overwritten) or in a new state; refused
/// when the instance already holds [`MAX_SNAPSHOTS`] states.
fn store_snapshot(
    inner: &mut Inner,
    func: Operation,
    slot: &mut Fmi2State,
    snap: Snapshot,
) -> Status {
    if known(inner, *slot) {
        if let Some(b) = inner.snapshots.get_mut(&(*slot as usize)) {
            **b = snap;
        }
    } else {
        if inner.snapshots.len() >= MAX_SNAPSHOTS {
            return inner.inst.error(&format!(
                "{func}: this instance holds {MAX_SNAPSHOTS} FMU states, the limit; free one with fmi2FreeFMUstate or pass one to overwrite"
            ));
        }
        let mut b = Box::new(snap);
        let p = &mut *b as *mut Snapshot as Fmi2State;
        inner.snapshots.insert(p as usize, b);
        *slot = p;
    }
    Status::Ok
}

/// `fmi2GetFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Fmi2Component, state: *mut Fmi2State) -> Fmi2Status {
    // SAFETY: the same contract.
    unsafe { get_fmu_state("fmi2GetFMUstate", c, state) }
}

/// The body of `fmi2GetFMUstate` (and of its FMI 3.0 namesake) on behalf of the function `name`.
///
/// # Safety
/// FMI 2.0 / 3.0 calling conventions.
pub(super) unsafe fn get_fmu_state(
    name: &'static str,
    c: Fmi2Component,
    state: *mut Fmi2State,
) -> Fmi2Status {
    status(c, name, |i| {
        if state.is_null() {
            return null_arg(i, Operation::GetFMUstate, "FMUstate");
        }
        // SAFETY: non-null pointer to the master's fmi2FMUstate variable.
        let slot = unsafe { &mut *state };
        if !slot.is_null() && !known(i, *slot) {
            return i
                .inst
                .error("fmi2GetFMUstate: *FMUstate is neither NULL nor a state of this instance");
        }
        match i.inst.get_state() {
            Ok(snap) => store_snapshot(i, Operation::GetFMUstate, slot, snap),
            Err(s) => s,
        }
    })
}

/// `fmi2SetFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, state: Fmi2State) -> Fmi2Status {
    // SAFETY: the same contract.
    unsafe { set_fmu_state("fmi2SetFMUstate", c, state) }
}

/// The body of `fmi2SetFMUstate` (and of its FMI 3.0 namesake) on behalf of the function `name`.
///
/// # Safety
/// FMI 2.0 / 3.0 calling conventions.
pub(super) unsafe fn set_fmu_state(
    name: &'static str,
    c: Fmi2Component,
    state: Fmi2State,
) -> Fmi2Status {
    status(c, name, |i| {
        if !known(i, state) {
            return i
                .inst
                .error("fmi2SetFMUstate: FMUstate is not a state of this instance (null, freed or foreign)");
        }
        let snap = (*i.snapshots[&(state as usize)]).clone();
        i.inst.set_state(&snap)
    })
}

/// `fmi2FreeFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Fmi2Component, state: *mut Fmi2State) -> Fmi2Status {
    // SAFETY: the same contract.
    unsafe { free_fmu_state("fmi2FreeFMUstate", c, state) }
}

/// The body of `fmi2FreeFMUstate` (and of its FMI 3.0 namesake) on behalf of the function `name`.
///
/// # Safety
/// FMI 2.0 / 3.0 calling conventions.
pub(super) unsafe fn free_fmu_state(
    name: &'static str,
    c: Fmi2Component,
    state: *mut Fmi2State,
) -> Fmi2Status {
    status(c, name, |i| {
        if let Err(s) = i.inst.check(Operation::FreeFMUstate) {
            return s;
        }
        if state.is_null() {
            return null_arg(i, Operation::FreeFMUstate, "FMUstate");
        }
        // SAFETY: non-null pointer to the master's fmi2FMUstate variable.
        let slot = unsafe { &mut *state };
        if slot.is_null() {
            return Status::Ok;
        }
        if i.snapshots.remove(&(*slot as usize)).is_none() {
            return i
                .inst
                .error("fmi2FreeFMUstate: FMUstate is not a state of this instance");
        }
        *slot = std::ptr::null_mut();
        Status::Ok
    })
}

/// `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    state: Fmi2State,
    size: *mut usize,
) -> Fmi2Status {
    // SAFETY: the same contract.
    unsafe { serialized_size("fmi2SerializedFMUstateSize", c, state, size) }
}

/// The body of `fmi2SerializedFMUstateSize` (and of its FMI 3.0 namesake) on behalf of the function `name`.
///
/// # Safety
/// FMI 2.0 / 3.0 calling conventions.
pub(super) unsafe fn serialized_size(
    name: &'static str,
    c: Fmi2Component,
    state: Fmi2State,
    size: *mut usize,
) -> Fmi2Status {
    status(c, name, |i| {
        if let Err(s) = i.inst.check(Operation::SerializedFMUstateSize) {
            return s;
        }
        if size.is_null() {
            return null_arg(i, Operation::SerializedFMUstateSize, "size");
        }
        if !known(i, state) {
            return i
                .inst
                .error("fmi2SerializedFMUstateSize: FMUstate is not a state of this instance");
        }
        let n = i.snapshots[&(state as usize)].to_bytes().len();
        // SAFETY: non-null pointer to the master's size_t.
        unsafe { *size = n };
        Status::Ok
    })
}

/// `fmi2SerializeFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    state: Fmi2State,
    bytes: *mut u8,
    size: usize,
) -> Fmi2Status {
    // SAFETY: the same contract.
    unsafe { serialize("fmi2SerializeFMUstate", c, state, bytes, size) }
}

/// The body of `fmi2SerializeFMUstate` (and of its FMI 3.0 namesake) on behalf of the function `name`.
///
/// # Safety
/// FMI 2.0 / 3.0 calling conventions.
pub(super) unsafe fn serialize(
    name: &'static str,
    c: Fmi2Component,
    state: Fmi2State,
    bytes: *mut u8,
    size: usize,
) -> Fmi2Status {
    status(c, name, |i| {
        if let Err(s) = i.inst.check(Operation::SerializeFMUstate) {
            return s;
        }
        if !known(i, state) {
            return i
                .inst
                .error("fmi2SerializeFMUstate: FMUstate is not a state of this instance");
        }
        let data = i.snapshots[&(state as usize)].to_bytes();
        if size < data.len() {
            return i.inst.error(&format!(
                "fmi2SerializeFMUstate: buffer of {size} bytes is smaller than the state ({} bytes; ask fmi2SerializedFMUstateSize)",
                data.len()
            ));
        }
        // SAFETY: the master provides `size` writable bytes; only the state's length is touched.
        let Some(out) = (unsafe { slice_mut(bytes, data.len(), MAX_STATE_BYTES) }) else {
            return null_arg(i, Operation::SerializeFMUstate, "serializedState");
        };
        out[..data.len()].copy_from_slice(&data);
        Status::Ok
    })
}

/// `fmi2DeSerializeFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    bytes: *const u8,
    size: usize,
    state: *mut Fmi2State,
) -> Fmi2Status {
    // SAFETY: the same contract.
    unsafe { deserialize("fmi2DeSerializeFMUstate", c, bytes, size, state) }
}

/// The body of `fmi2DeSerializeFMUstate` (and of its FMI 3.0 namesake) on behalf of the function `name`.
///
/// # Safety
/// FMI 2.0 / 3.0 calling conventions.
pub(super) unsafe fn deserialize(
    name: &'static str,
    c: Fmi2Component,
    bytes: *const u8,
    size: usize,
    state: *mut Fmi2State,
) -> Fmi2Status {
    status(c, name, |i| {
        if let Err(s) = i.inst.check(Operation::DeSerializeFMUstate) {
            return s;
        }
        if size > MAX_STATE_BYTES {
            return i.inst.error(&format!(
                "fmi2DeSerializeFMUstate: {size} bytes; an FMU state of this FMU is at most {MAX_STATE_BYTES} bytes"
            ));
        }
        // SAFETY: the master passes `size` readable bytes (bounded above).
        let Some(data) = (unsafe { slice(bytes, size, MAX_STATE_BYTES) }) else {
            return null_arg(i, Operation::DeSerializeFMUstate, "serializedState");
        };
        if state.is_null() {
            return null_arg(i, Operation::DeSerializeFMUstate, "FMUstate");
        }
        // SAFETY: non-null pointer to the master's fmi2FMUstate variable.
        let slot = unsafe { &mut *state };
        if !slot.is_null() && !known(i, *slot) {
            return i.inst.error(
                "fmi2DeSerializeFMUstate: *FMUstate is neither NULL nor a state of this instance",
            );
        }
        let snap = match Snapshot::from_bytes(data) {
            Ok(s) => s,
            Err(e) => return i.inst.error(&format!("fmi2DeSerializeFMUstate: {e}")),
        };
        if let Err(s) = i.inst.check_snapshot(Operation::DeSerializeFMUstate, &snap) {
            return s;
        }
        store_snapshot(i, Operation::DeSerializeFMUstate, slot, snap)
    })
}
