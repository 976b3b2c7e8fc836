//! Reading a file an option points at, with an error that names the option and the path (as the
//! user typed it, shortened when it is very long): `atmosphere_file /tmp/x: cannot read: not a
//! regular file (a FIFO, a device or a socket); entrynav reads only regular files`. The bounds
//! (regular files only, at most 256 MiB) are the loader's ([`entrynav_loader::read_text`]).

use crate::error::{StudyError, StudyResult};
use crate::output::target::{shown, too_long};
use std::path::Path;

/// The text of the file `path` given to option `option` (`atmosphere_file`, `--compare`, `A`).
pub fn read_text(path: &Path, option: &str) -> StudyResult<String> {
    if let Some(why) = too_long(path) {
        return Err(StudyError::Refused(format!(
            "{option} {}: cannot read: {why}",
            shown(path)
        )));
    }
    entrynav_loader::read_text(path)
        .map_err(|e| StudyError::Refused(format!("{option} {}: cannot read: {e}", shown(path))))
}

/// Refuse, before any work, a file given to option `option` that [`read_text`] would refuse (too
/// long a path, missing, not a regular file, too big), without reading it.
pub fn check_file(path: &Path, option: &str) -> StudyResult<()> {
    let fail =
        |why: String| StudyError::Refused(format!("{option} {}: cannot read: {why}", shown(path)));
    if let Some(why) = too_long(path) {
        return Err(fail(why));
    }
    let meta = std::fs::metadata(path).map_err(|e| fail(e.to_string()))?;
    if meta.is_dir() {
        return Err(fail("a folder; entrynav reads only regular files".into()));
    }
    if !meta.is_file() {
        return Err(fail(
            "not a regular file (a FIFO, a device or a socket); entrynav reads only regular files"
                .into(),
        ));
    }
    if meta.len() > entrynav_loader::MAX_FILE_BYTES {
        return Err(fail(format!(
            "{} bytes, more than the {} MiB entrynav reads",
            meta.len(),
            entrynav_loader::MAX_FILE_BYTES >> 20
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_read_error_names_the_option_and_the_path() {
        let err = read_text(Path::new("/dev/zero"), "atmosphere_file").unwrap_err();
        let text = err.to_string();
        assert!(
            text.starts_with("atmosphere_file /dev/zero: cannot read: not a regular file"),
            "{text}"
        );
        let long = Path::new("/tmp").join("x".repeat(10_000));
        let text = read_text(&long, "compare").unwrap_err().to_string();
        assert!(
            text.starts_with("compare /tmp/xxx") && text.contains("characters)"),
            "{text}"
        );
        assert!(text.len() < 300, "{text}");
        let text = check_file(Path::new("/tmp"), "FILE")
            .unwrap_err()
            .to_string();
        assert!(
            text.starts_with("FILE /tmp: cannot read: a folder"),
            "{text}"
        );
        assert!(check_file(Path::new("/dev/zero"), "FILE").is_err());
    }
}
