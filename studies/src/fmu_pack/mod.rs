//! The FMU packages: the co-simulation FMUs (FMI 2.0 and 3.0) of the `entrynav-fmu` library,
//! generic or specific to one scenario ([`pack`]), where the library is found ([`library`]), and
//! the SSP 1.0 systems of the generic FMUs ([`ssp`]). Every packed FMU is read back without
//! loading its library (`entrynav-fmu-archive`).

pub mod archive_error;
pub mod library;
pub mod options;
pub mod pack;
pub mod ssp;

pub use library::{LIB_ENV, LIB_NAME, Search};
pub use options::PackOptions;
pub use pack::{Packed, PackedFmu, pack_fmus};
pub use ssp::SSP_FMI3_REFUSAL;
