//! [`FmiInstance`]: the calls both FMI versions' co-simulation instances answer in the same way
//! ([`crate::Slave`] for FMI 2.0, [`crate::Slave3`] for FMI 3.0), so that a tool written against
//! it (the developer fuzzer) drives either interface.
//!
//! What differs between the versions stays with each slave: instantiation (its arguments differ),
//! FMI 2.0's separate `fmi2SetupExperiment` and status queries, FMI 3.0's other value types,
//! arrays, clocks and functions of capabilities an FMU may lack.
//!
//! The value and FMU-state calls pass the master's arrays and pointers through unchanged (a
//! tool that checks an FMU must be able to pass a null array, a count past its buffer or a
//! foreign state, which the FMU must refuse unread), so they are `unsafe` with the C function's
//! contract. `n_values` is FMI 3.0's `nValues`, the number of values the references hold (an
//! array holds several); FMI 2.0 has one value per reference, and its functions are called with
//! `nvr` alone.

use std::ffi::{c_char, c_void};

/// One message an instance logged.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Message {
    /// Its status (`fmi2Status` / `fmi3Status`).
    pub status: i32,
    /// Its log category.
    pub category: String,
    /// The text (FMI 2.0: with `%%` read as `%`, the logger being printf-like).
    pub text: String,
}

/// An FMU state handed out by an instance (`fmi2FMUstate`, `fmi3FMUState`).
pub type FmuState = *mut c_void;

/// What a `DoStep` call answered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepAnswer {
    /// The status.
    pub status: i32,
    /// FMI 3.0's `eventHandlingNeeded`, `terminateSimulation` and `earlyReturn` as the FMU left
    /// them (each is set to 0xAA before the call, so a byte the FMU did not write shows); `None`
    /// when they were not asked for, and for FMI 2.0, which has none.
    pub flags: Option<[u8; 3]>,
    /// FMI 3.0's `lastSuccessfulTime` as the FMU left it (NaN before the call); `None` for FMI
    /// 2.0, whose master asks `fmi2GetRealStatus` instead.
    pub last_successful_time: Option<f64>,
}

/// One co-simulation instance of a loaded FMU, FMI 2.0 or 3.0.
///
/// Every method returns the FMI status the FMU answered (0 OK, 1 Warning, 2 Discard, 3 Error,
/// 4 Fatal) and never fails on the host's side.
pub trait FmiInstance {
    /// The prefix of the version's function names: `fmi2` or `fmi3`.
    const PREFIX: &'static str;
    /// The version's C Boolean: `fmi2Boolean` (an `int`) or `fmi3Boolean` (one byte).
    type Boolean: Copy + Default + From<u8> + Into<i64>;

    /// The instance handle the FMU returned (null: the instantiation was refused; after
    /// [`FmiInstance::free`], the freed handle, which the FMU must refuse).
    fn handle(&self) -> *mut c_void;
    /// The messages logged since the last call of this method, taken.
    fn take_messages(&self) -> Vec<Message>;
    /// Free the instance (once; the handle stays, for calls on a freed instance).
    fn free(&mut self);

    /// Set up the experiment and enter Initialization Mode: `fmi3EnterInitializationMode`, or
    /// `fmi2SetupExperiment` then (if it answered OK) `fmi2EnterInitializationMode`; the first
    /// status that is not OK, else OK.
    fn enter_initialization_mode(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> i32;
    /// Leave Initialization Mode.
    fn exit_initialization_mode(&self) -> i32;
    /// One communication step from `t` of `h`; `flags`: pass FMI 3.0's output flags (else null
    /// pointers, which an FMI 3.0 FMU must accept).
    fn do_step(&self, t: f64, h: f64, no_set_fmu_state_prior: bool, flags: bool) -> StepAnswer;
    /// Terminate.
    fn terminate(&self) -> i32;
    /// Reset to the state after instantiation.
    fn reset(&self) -> i32;

    /// Set debug logging and its categories.
    ///
    /// # Safety
    /// `categories` is null or points to `n` C strings (the FMU must refuse a null array with a
    /// non-zero count unread).
    unsafe fn set_debug_logging(
        &self,
        on: Self::Boolean,
        n: usize,
        categories: *const *const c_char,
    ) -> i32;

    /// Read Float64 (FMI 2.0: Real) values.
    ///
    /// # Safety
    /// `vrs` points to `nvr` references and `values` to room for `n_values` values (FMI 2.0:
    /// `n_values == nvr`), except where the FMU must refuse the call unread (a null array with a
    /// non-zero count, a count over its bound, a wrong `n_values`).
    unsafe fn get_float64(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut f64,
        n_values: usize,
    ) -> i32;
    /// Write Float64 (FMI 2.0: Real) values.
    ///
    /// # Safety
    /// As [`FmiInstance::get_float64`], `values` holding `n_values` values.
    unsafe fn set_float64(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const f64,
        n_values: usize,
    ) -> i32;
    /// Read Int32 (FMI 2.0: Integer) values.
    ///
    /// # Safety
    /// As [`FmiInstance::get_float64`].
    unsafe fn get_int32(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut i32,
        n_values: usize,
    ) -> i32;
    /// Write Int32 (FMI 2.0: Integer) values.
    ///
    /// # Safety
    /// As [`FmiInstance::set_float64`].
    unsafe fn set_int32(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const i32,
        n_values: usize,
    ) -> i32;
    /// Read Boolean values.
    ///
    /// # Safety
    /// As [`FmiInstance::get_float64`].
    unsafe fn get_boolean(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut Self::Boolean,
        n_values: usize,
    ) -> i32;
    /// Write Boolean values.
    ///
    /// # Safety
    /// As [`FmiInstance::set_float64`].
    unsafe fn set_boolean(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const Self::Boolean,
        n_values: usize,
    ) -> i32;
    /// Read String values (valid until the next call on the instance).
    ///
    /// # Safety
    /// As [`FmiInstance::get_float64`].
    unsafe fn get_string(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut *const c_char,
        n_values: usize,
    ) -> i32;
    /// Write String values.
    ///
    /// # Safety
    /// As [`FmiInstance::set_float64`], each value null (refused) or a C string.
    unsafe fn set_string(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const *const c_char,
        n_values: usize,
    ) -> i32;

    /// Save the instance's state into `*state` (null: a new state; a state of this instance:
    /// overwritten).
    ///
    /// # Safety
    /// `state` is null (refused) or points to a state handle, null or not (a foreign one must be
    /// refused unread).
    unsafe fn get_fmu_state(&self, state: *mut FmuState) -> i32;
    /// Restore a state.
    ///
    /// # Safety
    /// `state` is any value: one the instance did not hand out must be refused unread.
    unsafe fn set_fmu_state(&self, state: FmuState) -> i32;
    /// Free `*state` and set it to null.
    ///
    /// # Safety
    /// As [`FmiInstance::get_fmu_state`].
    unsafe fn free_fmu_state(&self, state: *mut FmuState) -> i32;
    /// The size of `state` serialised.
    ///
    /// # Safety
    /// `size` points to a `usize`; `state` as in [`FmiInstance::set_fmu_state`].
    unsafe fn serialized_fmu_state_size(&self, state: FmuState, size: *mut usize) -> i32;
    /// Serialise `state` into `bytes` of `size` bytes.
    ///
    /// # Safety
    /// `bytes` has room for `size` bytes; `state` as in [`FmiInstance::set_fmu_state`].
    unsafe fn serialize_fmu_state(&self, state: FmuState, bytes: *mut u8, size: usize) -> i32;
    /// A new state from `size` serialised bytes, into `*state`.
    ///
    /// # Safety
    /// `bytes` holds `size` bytes (a size over the FMU's bound must be refused unread); `state`
    /// points to a state handle.
    unsafe fn deserialize_fmu_state(
        &self,
        bytes: *const u8,
        size: usize,
        state: *mut FmuState,
    ) -> i32;
}
