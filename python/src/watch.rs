//! A study run on a Rust thread with the GIL released, watched from the calling thread: every
//! 50 ms it runs Python's signal handlers (Ctrl-C raises `KeyboardInterrupt` there and sets the
//! study's cancel flag, so a Monte Carlo stops starting runs and folds the finished ones) and
//! calls the progress callback with `(done, total)`.

use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

/// What the study and the watcher share.
pub struct Watch {
    /// Finished so far.
    pub done: AtomicU64,
    /// To do in all.
    pub total: AtomicU64,
    /// Set by Ctrl-C or a failing callback; the study reads it between runs. Leaked, one byte
    /// per study, because the core reads it through a `'static` reference.
    pub cancel: &'static AtomicBool,
}

impl Watch {
    /// A progress step of the study layer, recorded for the watcher.
    pub fn record(&self, step: entrynav_studies::progress::Step<'_>) {
        self.total.store(step.total, Ordering::Relaxed);
        self.done.store(step.done, Ordering::Relaxed);
    }
}

/// Run `job` watched, `total` steps to do (the callback's second argument until the study says
/// otherwise); returns its result and the Python error that stopped it early (Ctrl-C, or the
/// callback's own exception), if any. A panic in `job` is a `RuntimeError`.
pub fn run_watched<R: Send>(
    py: Python<'_>,
    progress: Option<&Py<PyAny>>,
    total: u64,
    job: impl FnOnce(&Watch) -> R + Send,
) -> PyResult<(R, Option<PyErr>)> {
    let watch = Watch {
        done: AtomicU64::new(0),
        total: AtomicU64::new(total),
        cancel: Box::leak(Box::new(AtomicBool::new(false))),
    };
    let mut stopped: Option<PyErr> = None;
    let result = std::thread::scope(|s| {
        let worker = s.spawn(|| job(&watch));
        let mut shown = u64::MAX;
        while !worker.is_finished() {
            py.detach(|| {
                let until = std::time::Instant::now() + Duration::from_millis(50);
                while !worker.is_finished() && std::time::Instant::now() < until {
                    std::thread::sleep(Duration::from_millis(2));
                }
            });
            if stopped.is_some() {
                continue;
            }
            if let Err(e) = py.check_signals() {
                watch.cancel.store(true, Ordering::Relaxed);
                stopped = Some(e);
                continue;
            }
            let d = watch.done.load(Ordering::Relaxed);
            if let Some(cb) = progress
                && d != shown
            {
                shown = d;
                let total = watch.total.load(Ordering::Relaxed);
                if let Err(e) = cb.call1(py, (d, total)) {
                    watch.cancel.store(true, Ordering::Relaxed);
                    stopped = Some(e);
                }
            }
        }
        worker.join()
    });
    let result = result.map_err(|_| {
        pyo3::exceptions::PyRuntimeError::new_err("the study panicked (internal error)")
    })?;
    if let (Some(cb), None) = (progress, &stopped) {
        let total = watch.total.load(Ordering::Relaxed);
        cb.call1(py, (watch.done.load(Ordering::Relaxed), total))?;
    }
    Ok((result, stopped))
}
