//! The live instances: what an `fmi2Component` stands for, how an entry point reaches its
//! instance, and how `fmi2FreeInstance` frees one while another thread may be calling it.
//!
//! An `fmi2Component` handed to the master is a *token*: a number, never reused, that keys the
//! process-wide registry of live instances ([`LIVE`]); it is never dereferenced. The registry
//! holds an `Arc<Handle>` per instance, and an entry point holds its own clone of that `Arc` for
//! the whole call. Hence the invariant:
//!
//! * **A handle's memory lives as long as the registry or a call holds it.** `fmi2FreeInstance`
//!   removes the entry and drops the registry's `Arc`; a call that found the handle before keeps
//!   it alive until it returns, and the last holder frees it. No thread ever reads a freed
//!   handle, whatever the master does.
//! * **Once `fmi2FreeInstance` has removed the entry, every later entry point refuses the token**
//!   (`fmi2Error` for calls that return a status, nothing for `fmi2FreeInstance`): the lookup
//!   does not find it, and a call that looked it up just before the removal sees the handle's
//!   `freed` mark once it holds the instance's lock and refuses without calling the master's
//!   logger (whose environment the master may already have released).
//! * A call that is *inside* the instance when it is freed (it held the lock first) finishes as
//!   if the free had come after it; the instance is dropped when it returns. FMI 2.0 allows one
//!   call at a time per instance, so this only happens to a master that breaks that rule, and
//!   then it is memory-safe and leaks nothing.
//! * The same token can never name another instance later (tokens are not addresses, so an
//!   address reused by the allocator cannot make a stale token valid again).
//!
//! The registry's lock is held only to insert, remove or clone an `Arc`, never while the
//! instance runs or the logger is called, so instances on different threads do not wait on each
//! other.

use super::inner::Inner;
use super::logger::CLogger;
use super::panic_hook;
use super::types::{Fmi2Component, Fmi2Status};
use crate::instance::Status;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError, RwLock, TryLockError};

/// One live instance.
pub(super) struct Handle {
    /// The master's logger, outside the lock so a refused concurrent call can still log.
    log: Arc<CLogger>,
    inner: Mutex<Inner>,
    /// Set by `fmi2FreeInstance` after it removed the handle from the registry.
    freed: AtomicBool,
    /// Created by `fmi3InstantiateCoSimulation`: only fmi3 functions may use it (and only fmi2
    /// functions an instance of `fmi2Instantiate`).
    fmi3: bool,
}

/// Live instances by token.
static LIVE: RwLock<BTreeMap<usize, Arc<Handle>>> = RwLock::new(BTreeMap::new());
/// The next token (multiples of 16, so a token looks like an aligned pointer and is never null).
static NEXT: AtomicUsize = AtomicUsize::new(16);

/// Register a new instance; its token is the `fmi2Component` handed to the master.
pub(super) fn register(log: Arc<CLogger>, fmi3: bool, inner: Inner) -> Fmi2Component {
    let token = NEXT.fetch_add(16, Ordering::Relaxed);
    let handle = Arc::new(Handle {
        log,
        inner: Mutex::new(inner),
        freed: AtomicBool::new(false),
        fmi3,
    });
    LIVE.write()
        .unwrap_or_else(PoisonError::into_inner)
        .insert(token, handle);
    std::ptr::without_provenance_mut(token)
}

/// The live instance of `c`, if any (null, foreign and freed tokens have none).
fn lookup(c: Fmi2Component) -> Option<Arc<Handle>> {
    LIVE.read()
        .unwrap_or_else(PoisonError::into_inner)
        .get(&c.addr())
        .cloned()
}

/// `fmi2FreeInstance`: unregister `c` and mark it freed; its memory goes with the last call
/// still inside it, or now. Null, foreign and already freed tokens are ignored.
pub(super) fn free(c: Fmi2Component) {
    let removed = LIVE
        .write()
        .unwrap_or_else(PoisonError::into_inner)
        .remove(&c.addr());
    if let Some(handle) = removed {
        handle.freed.store(true, Ordering::Release);
        drop(handle);
    }
}

/// Run `f` on the instance behind `c`; null, freed or foreign tokens, concurrent calls and
/// panics give `fail`.
pub(super) fn with_inst<T>(
    c: Fmi2Component,
    func: impl std::fmt::Display,
    fail: T,
    f: impl FnOnce(&mut Inner) -> T,
) -> T {
    let Some(handle) = lookup(c) else {
        return fail;
    };
    // An instance answers only the interface that created it.
    let name = func.to_string();
    let other = match name.get(..4) {
        Some("fmi2") => handle.fmi3,
        Some("fmi3") => !handle.fmi3,
        _ => false,
    };
    if other {
        let (made, use_) = if handle.fmi3 {
            ("fmi3InstantiateCoSimulation (FMI 3.0)", "fmi3")
        } else {
            ("fmi2Instantiate (FMI 2.0)", "fmi2")
        };
        let log = &handle.log;
        let _ = panic_hook::guarded(|| {
            log.log_verbatim(
                Status::Error,
                "logStatusError",
                &format!("{name}: this instance was created by {made}; call the {use_} functions on it; nothing was done"),
            )
        });
        return fail;
    }
    let result = call(&handle, func, fail, f);
    // The last holder drops the instance: this call, when the instance was freed during it.
    let _ = panic_hook::guarded(move || drop(handle));
    result
}

/// [`with_inst`] on a live handle.
fn call<T>(
    handle: &Handle,
    func: impl std::fmt::Display,
    fail: T,
    f: impl FnOnce(&mut Inner) -> T,
) -> T {
    let mut guard = match handle.inner.try_lock() {
        Ok(g) => g,
        Err(TryLockError::Poisoned(p)) => p.into_inner(),
        Err(TryLockError::WouldBlock) => {
            let log = &handle.log;
            let _ = panic_hook::guarded(|| {
                log.log(
                    Status::Error,
                    "logStatusError",
                    &format!(
                        "{func}: the instance is busy: another thread is inside a call on it (FMI 2.0 allows one call at a time per instance); nothing was done"
                    ),
                )
            });
            return fail;
        }
    };
    if handle.freed.load(Ordering::Acquire) {
        return fail;
    }
    match panic_hook::guarded(|| f(&mut guard)) {
        Ok(v) => v,
        Err(msg) => {
            let msg = format!("{func}: internal error (caught panic: {msg})");
            let _ = panic_hook::guarded(|| guard.inst.poison(&msg));
            fail
        }
    }
}

/// [`with_inst`] for the calls that return an fmi2Status.
pub(super) fn status(
    c: Fmi2Component,
    func: impl std::fmt::Display,
    f: impl FnOnce(&mut Inner) -> Status,
) -> Fmi2Status {
    with_inst(c, func, Status::Error, f) as Fmi2Status
}

/// The number of live instances of this library in the process: instantiated and not yet freed
/// (an instance freed during a call on it counts no more, though its memory goes when the call
/// returns).
pub fn live_instances() -> usize {
    LIVE.read().unwrap_or_else(PoisonError::into_inner).len()
}
