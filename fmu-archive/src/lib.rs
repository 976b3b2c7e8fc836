//! Reading back one of our packed `.fmu` files (FMI 2.0 or 3.0) without loading its library:
//! the archive is extracted to a temporary folder, its model description must be what this
//! build generates for the model its library is bound to, and a generic FMU must ship every
//! built-in scenario in `resources/`.
//!
//! `entrynav fmu pack` reads every FMU it writes back through [`open`]; the developer host
//! (`entrynav-fmi-host`, used by `entrynav-dev`) opens an FMU the same way and then loads its
//! library. Loading a library (libloading) is the host's alone, so the shipped `entrynav`
//! command carries none.
//!
//! Modules: `archive` ([`Archive`], [`open`]), `description` (the attributes read from a model
//! description), `uri` ([`file_uri`]) and `error` ([`ArchiveError`]).
#![warn(missing_docs)]

mod archive;
mod description;
mod error;
mod uri;

pub use archive::{Archive, open};
pub use error::ArchiveError;
pub use uri::file_uri;
