//! The master's logger as the C layer calls it ([`CLogger`]): FMI 2.0 (printf-like, `%`
//! escaped) or FMI 3.0 (plain text, in FMI 3.0 terms).

use super::fmi3::terms::in_fmi3_terms;
use super::types::{Logger3Fn, LoggerFn};
use crate::instance::Status;
use std::ffi::{CString, c_int, c_void};

/// The master's logger: FMI 2.0 (printf-like) or FMI 3.0.
#[derive(Clone, Copy)]
pub(super) enum LogFn {
    V2(LoggerFn),
    V3(Logger3Fn),
}

/// The logger callback with its environment.
pub(super) struct CLogger {
    pub(super) f: Option<LogFn>,
    pub(super) env: *mut c_void,
    pub(super) name: CString,
}

// SAFETY: the FMI standard lets the FMU call the logger, with the environment pointer, from any
// thread that is inside a call on the instance; the pointer is only passed back, never
// dereferenced here.
unsafe impl Send for CLogger {}
// SAFETY: as for Send: `log` only reads the fields and calls the master's callback. Two threads
// can log at once only when the master calls one instance from two threads (which FMI forbids
// and which the second thread is told about through this logger).
unsafe impl Sync for CLogger {}

pub(super) fn c_text(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

impl CLogger {
    pub(super) fn log(&self, status: Status, category: &str, msg: &str) {
        self.emit(status, category, msg, true);
    }

    /// [`CLogger::log`] without the FMI 3.0 renaming (a message that names both interfaces).
    pub(super) fn log_verbatim(&self, status: Status, category: &str, msg: &str) {
        self.emit(status, category, msg, false);
    }

    fn emit(&self, status: Status, category: &str, msg: &str, rename: bool) {
        let cat = c_text(category);
        match self.f {
            None => {}
            Some(LogFn::V2(f)) => {
                let text = c_text(&msg.replace('%', "%%"));
                // SAFETY: `f` is the master's logger; all strings are valid NUL-terminated C
                // strings that outlive the call, and the message contains no unescaped format
                // directives.
                unsafe {
                    f(
                        self.env,
                        self.name.as_ptr(),
                        status as c_int,
                        cat.as_ptr(),
                        text.as_ptr(),
                    )
                };
            }
            Some(LogFn::V3(f)) => {
                let text = c_text(&if rename {
                    in_fmi3_terms(msg)
                } else {
                    msg.to_string()
                });
                // SAFETY: `f` is the master's fmi3LogMessageCallback; the strings are valid
                // NUL-terminated C strings that outlive the call (the message is not a format).
                unsafe { f(self.env, status as c_int, cat.as_ptr(), text.as_ptr()) };
            }
        }
    }
}
