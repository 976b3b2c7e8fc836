//! Output paths checked before any work, so a study never fails at its end on something it could
//! have refused at its start: a path that is too long, a folder, a FIFO or a device other than
//! `/dev/null` is refused by name before anything opens it ([`super::target`]); then the folder
//! is created and the file opened for appending (which leaves an existing file's content alone);
//! a file this check created is removed again.

use super::target::{refusal, shown, too_long};
use crate::error::StudyError;
use std::path::Path;

/// Whether `path` is `-` (standard output, for a front end that has one).
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Refuse an output file that cannot be written, naming `option` (`--json`, `json`) and the path.
/// `-` (standard output) is always fine.
pub fn check_output_file(path: &Path, option: &str) -> Result<(), StudyError> {
    if is_stdout(path) {
        return Ok(());
    }
    let fail = |e: std::io::Error| {
        StudyError::Refused(format!("{option} {}: cannot write there: {e}", shown(path)))
    };
    if let Some(why) = refusal(path) {
        return Err(StudyError::Refused(format!(
            "{option} {}: {why}",
            shown(path)
        )));
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(fail)?;
    }
    let existed = path.exists();
    if super::target::is_null(path) {
        return Ok(());
    }
    std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(path)
        .map_err(fail)?;
    if !existed {
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}

/// Refuse an output folder that cannot be created or written into.
pub fn check_output_dir(dir: &Path, option: &str) -> Result<(), StudyError> {
    let fail = |e: std::io::Error| {
        StudyError::Refused(format!("{option} {}: cannot write there: {e}", shown(dir)))
    };
    if let Some(why) = too_long(dir) {
        return Err(StudyError::Refused(format!(
            "{option} {}: {why}",
            shown(dir)
        )));
    }
    if dir.exists() && !dir.is_dir() {
        return Err(StudyError::Refused(format!(
            "{option} {}: it is not a folder",
            shown(dir)
        )));
    }
    std::fs::create_dir_all(dir).map_err(fail)?;
    let probe = dir.join(format!(".entrynav-write-check-{}", std::process::id()));
    std::fs::File::create(&probe).map_err(fail)?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}
