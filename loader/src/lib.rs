//! The one scenario loader of entrynav, shared by the command line, the optimizer commands and
//! the FMUs (the core does no I/O, so reading files happens here).
//!
//! * [`resolve`]: a built-in scenario name, or a TOML file (absolute, or relative to a base
//!   folder: the current directory for the CLI, the FMU's `resources/` folder for an FMU);
//! * [`apply_overrides`]: `--set PATH=VALUE` edits in TOML syntax, re-validated;
//! * [`file_loader`] / [`build`]: the files a scenario refers to (tabulated atmospheres) are read
//!   relative to the scenario file's folder.

mod error;
mod load;
mod overrides;
mod read;
mod resolve;
mod source;
pub mod summary;
#[cfg(test)]
mod tests;

pub use error::LoadError;
pub use load::{build, file_loader, load};
pub use overrides::apply_overrides;
pub use read::{MAX_FILE_BYTES, read_bytes, read_text};
pub use resolve::{resolve, suggestion};
pub use source::{Base, Origin, ScenarioSource};
