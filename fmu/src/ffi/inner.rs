//! [`Inner`]: what the C layer keeps of one instance.

use crate::instance::Instance;
use crate::state::Snapshot;
use std::collections::HashMap;
use std::ffi::CString;

/// An instance as the C layer holds it: the safe instance, the strings it handed out (valid
/// until the next fmi2GetString) and the FMU states it handed out, by address.
pub(super) struct Inner {
    pub(super) inst: Instance,
    pub(super) strings: Vec<CString>,
    pub(super) snapshots: HashMap<usize, Box<Snapshot>>,
}
