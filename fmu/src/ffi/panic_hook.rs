//! Panics inside an FMI call reach the instance's logger, never stderr.
//!
//! Rust's default panic hook prints to stderr before unwinding starts, so catching the panic
//! (`catch_unwind`) is not enough. The library installs its own hook, once per process
//! (`std::sync::Once`), the first time an fmi2 function runs. The hook needs to know whether the
//! panicking thread is inside an FMI call: [`guarded`] marks the calling thread for the duration
//! of the call (a thread-local counter) and collects the hook's message (a thread-local slot);
//! the caller then logs that message, with its source location, through the instance's logger.
//!
//! A panic on a thread that is *not* inside an FMI call is passed to the hook that was installed
//! before ours (Rust's default one, or the importer's when the library is linked into a Rust
//! program), so the library never swallows its host's panics. The process-wide state is the hook
//! itself and its `Once`; the per-call state is thread-local and lives only during a call, so
//! instances stay independent.

use std::cell::{Cell, RefCell};
use std::panic::{AssertUnwindSafe, PanicHookInfo, catch_unwind};
use std::sync::Once;

thread_local! {
    /// How many guarded calls the thread is inside (nested: an FMI call made from a logger).
    static DEPTH: Cell<usize> = const { Cell::new(0) };
    /// The message of the last panic on this thread inside a guarded call.
    static CAUGHT: RefCell<Option<String>> = const { RefCell::new(None) };
}

static INSTALL: Once = Once::new();

/// A panic caught inside a guarded FMI call: its message and source location.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct CaughtPanic(pub String);

fn describe(info: &PanicHookInfo<'_>) -> String {
    let payload = info.payload();
    let what = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("a panic without a message");
    match info.location() {
        Some(l) => format!("{what} at {}:{}:{}", l.file(), l.line(), l.column()),
        None => what.to_string(),
    }
}

/// Install the hook (once per process).
fn install() {
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let inside = DEPTH.try_with(Cell::get).unwrap_or(0) > 0;
            if inside {
                let msg = describe(info);
                let _ = CAUGHT.try_with(|c| *c.borrow_mut() = Some(msg));
            } else {
                previous(info);
            }
        }));
    });
}

/// Run `f` with panics caught: `Err` holds the panic's message and location.
pub fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, CaughtPanic> {
    install();
    DEPTH.with(|d| d.set(d.get() + 1));
    let r = catch_unwind(AssertUnwindSafe(f));
    DEPTH.with(|d| d.set(d.get().saturating_sub(1)));
    r.map_err(|payload| {
        CAUGHT
            .with(|c| c.borrow_mut().take())
            .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .map_or_else(
                || CaughtPanic("a panic without a message".into()),
                CaughtPanic,
            )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_guarded_panic_is_caught_with_its_location() {
        let r: Result<(), CaughtPanic> = guarded(|| {
            let v: Vec<u8> = Vec::new();
            let i = v.len() + 3;
            let _ = v[i];
        });
        let msg = r.unwrap_err().to_string();
        assert!(msg.contains("index out of bounds"), "{msg}");
        assert!(msg.contains("panic_hook.rs"), "{msg}");
        assert_eq!(guarded(|| 5), Ok(5));
        // Outside a guarded call the previous hook still sees panics.
        let outside = std::thread::spawn(|| panic!("outside")).join();
        assert!(outside.is_err());
    }
}
