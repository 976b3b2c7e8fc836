//! The library's own binding block, read at run time (see [`crate::binding`]).

use crate::binding::{BINDING, BINDING_CAPACITY, Binding, BindingBlock, BindingError};

/// The binding of this library: `None` for the unbound build.
pub(super) fn current() -> Result<Option<Binding>, BindingError> {
    // SAFETY: BINDING is an immutable static of plain bytes, valid for the whole program; a
    // volatile read keeps the compiler from using its initial (unbound) contents, since
    // `entrynav fmu pack` rewrites them in the library file.
    let block: BindingBlock = unsafe { std::ptr::read_volatile(&BINDING) };
    let data: &[u8; BINDING_CAPACITY] = &block.data;
    Binding::decode(block.len, data)
}
