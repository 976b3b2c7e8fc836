//! Reading the master's arguments: C arrays with their lengths bounded before they are touched,
//! C strings read no further than their bound, and the error a null or over-long one gets.

use super::inner::Inner;
use crate::instance::{Operation, Status};
use std::ffi::c_char;

/// Borrow a C array of `n` elements; null is allowed only for length 0, and `n` must be at most
/// `max` (checked before the array is touched).
///
/// # Safety
/// `p` must point to `n` valid elements when non-null.
pub(super) unsafe fn slice<'a, T>(p: *const T, n: usize, max: usize) -> Option<&'a [T]> {
    if n == 0 {
        return Some(&[]);
    }
    if p.is_null() || n > max || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: guaranteed by the caller (the master passes arrays of `n` elements).
    Some(unsafe { std::slice::from_raw_parts(p, n) })
}

/// # Safety
/// As [`slice`], for writing.
pub(super) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, max: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        return Some(&mut []);
    }
    if p.is_null() || n > max || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: guaranteed by the caller.
    Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// Why a C string argument is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum TextError {
    Null,
    TooLong(usize),
    NotUtf8,
}

impl TextError {
    pub(super) fn describe(self, what: &str) -> String {
        match self {
            TextError::Null => format!("{what} is a null pointer"),
            TextError::TooLong(max) => format!("{what} is longer than {max} bytes"),
            TextError::NotUtf8 => format!("{what} is not UTF-8"),
        }
    }
}

/// A NUL-terminated string of at most `max` bytes, read without looking past its terminator or
/// past `max + 1` bytes.
///
/// # Safety
/// `p` is null or a NUL-terminated string.
pub(super) unsafe fn text<'a>(p: *const c_char, max: usize) -> Result<&'a str, TextError> {
    if p.is_null() {
        return Err(TextError::Null);
    }
    let mut n = 0usize;
    loop {
        // SAFETY: the string is NUL-terminated and no byte after the terminator is read.
        if unsafe { *p.add(n) } == 0 {
            break;
        }
        if n == max {
            return Err(TextError::TooLong(max));
        }
        n += 1;
    }
    // SAFETY: the `n` bytes before the terminator were just read.
    let bytes = unsafe { std::slice::from_raw_parts(p as *const u8, n) };
    std::str::from_utf8(bytes).map_err(|_| TextError::NotUtf8)
}

pub(super) fn null_arg(inner: &Inner, func: Operation, what: &str) -> Status {
    inner.inst.error(&format!(
        "{func}: {what} is a null pointer, or its length is over the limit ({} elements)",
        crate::limits::MAX_VALUE_REFS
    ))
}
