//! Writing a study's results: files that are whole or absent ([`atomic_file`]) and output paths
//! refused before any work ([`paths`]). Both front ends write through here, so they refuse and
//! fail on the same paths with the same messages.

pub mod atomic_file;
pub mod paths;
pub mod target;

pub use atomic_file::{AtomicFile, OutputError, write};
pub use paths::{check_output_dir, check_output_file, is_stdout};
