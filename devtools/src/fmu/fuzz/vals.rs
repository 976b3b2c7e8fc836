//! [`Vals`]: the values a getter wrote, by value type.

use std::ffi::c_char;

/// The values a getter wrote.
pub(super) enum Vals {
    F64(Vec<f64>),
    I32(Vec<i32>),
    I64(Vec<i64>),
    U64(Vec<u64>),
    /// Booleans as integers (the version's C Boolean widened: a byte or an `int`).
    Bool(Vec<i64>),
    Str(Vec<*const c_char>),
}

impl Vals {
    /// Value `k` of an integer read (Int32 or Int64).
    pub(super) fn integer(&self, k: usize) -> Option<i64> {
        match self {
            Vals::I32(x) => x.get(k).map(|&x| x as i64),
            Vals::I64(x) => x.get(k).copied(),
            _ => None,
        }
    }
}
