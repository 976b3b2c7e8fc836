//! What an output path points at, judged before anything opens it. Opening a FIFO for writing
//! blocks until a reader comes (forever, for a study's `--json` nobody reads), a block device
//! or a terminal is not a result file, and a name longer than the file system's limit fails
//! only at the end of the work. So every output is refused at once, by name, unless it is a
//! regular file (existing or not) or the null device (`/dev/null`, the usual way to discard an
//! output; it is written in place, see [`super::atomic_file`]).

use std::path::Path;

/// Longest single name (one path component) Linux file systems take: `NAME_MAX`.
pub const MAX_NAME_BYTES: usize = 255;

/// Longest path the kernel takes: `PATH_MAX` (4096, the terminating NUL included).
pub const MAX_PATH_BYTES: usize = 4095;

/// `path` as a message shows it: whole up to 120 characters, else its start and end around
/// `…` with its length, so a 10 000-character name does not flood the terminal.
pub fn shown(path: &Path) -> String {
    let text = path.display().to_string();
    let chars: Vec<char> = text.chars().collect();
    if chars.len() <= 120 {
        return text;
    }
    let head: String = chars[..60].iter().collect();
    let tail: String = chars[chars.len() - 40..].iter().collect();
    format!("{head}…{tail} ({} characters)", chars.len())
}

/// Why `path` is too long for the file system, if it is.
pub fn too_long(path: &Path) -> Option<String> {
    use std::os::unix::ffi::OsStrExt;
    let total = path.as_os_str().as_bytes().len();
    if total > MAX_PATH_BYTES {
        return Some(format!(
            "the path is {total} bytes long, more than the {MAX_PATH_BYTES} the system allows"
        ));
    }
    let longest = path
        .components()
        .map(|c| c.as_os_str().as_bytes().len())
        .max()
        .unwrap_or(0);
    (longest > MAX_NAME_BYTES).then(|| {
        format!(
            "a name in it is {longest} bytes long, more than the {MAX_NAME_BYTES} a file name may have"
        )
    })
}

/// Whether `meta` is the null device (character device 1:3 on Linux).
fn is_null_device(meta: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::{FileTypeExt, MetadataExt};
    meta.file_type().is_char_device() && meta.rdev() == null_device_number()
}

fn null_device_number() -> u64 {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata("/dev/null").map_or(u64::MAX, |m| m.rdev())
}

/// Whether an existing `path` is a character device that is the null device: written in place.
pub fn is_null(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| is_null_device(&m))
}

/// Why `path` cannot be an output file, if it cannot: too long, a folder, a FIFO, a socket, a
/// device other than `/dev/null`. A path that does not exist yet is fine here (whether its
/// folder can be written is the caller's check).
pub fn refusal(path: &Path) -> Option<String> {
    use std::os::unix::fs::FileTypeExt;
    if let Some(why) = too_long(path) {
        return Some(why);
    }
    let meta = std::fs::metadata(path).ok()?;
    let kind = meta.file_type();
    let what = if kind.is_file() || is_null_device(&meta) {
        return None;
    } else if kind.is_dir() {
        "a folder"
    } else if kind.is_fifo() {
        "a FIFO (named pipe)"
    } else if kind.is_socket() {
        "a socket"
    } else if kind.is_block_device() {
        "a block device"
    } else if kind.is_char_device() {
        "a character device"
    } else {
        "not a regular file"
    };
    Some(format!(
        "it is {what}; entrynav writes only regular files (or /dev/null)"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_new_paths_and_the_null_device_are_outputs_nothing_else_is() {
        let d = std::env::temp_dir().join(format!("entrynav-target-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let file = d.join("a.json");
        assert_eq!(refusal(&file), None, "a new file");
        std::fs::write(&file, "{}").unwrap();
        assert_eq!(refusal(&file), None, "an existing file");
        assert_eq!(refusal(Path::new("/dev/null")), None);
        assert!(refusal(&d).unwrap().contains("a folder"));
        let fifo = d.join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            assert!(refusal(&fifo).unwrap().contains("FIFO"));
        }
        assert!(
            refusal(Path::new("/dev/zero"))
                .unwrap()
                .contains("character device")
        );
        let long = d.join("x".repeat(300));
        assert!(refusal(&long).unwrap().contains("300 bytes"));
        let deep = Path::new("/tmp").join("d/".repeat(2100));
        assert!(refusal(&deep).unwrap().contains("the path is"));
    }

    #[test]
    fn a_long_path_is_shown_by_its_ends() {
        let p = Path::new("/tmp").join("x".repeat(10_240));
        let s = shown(&p);
        assert!(
            s.starts_with("/tmp/xxx") && s.ends_with("(10245 characters)"),
            "{s}"
        );
        assert!(s.chars().count() < 130);
        assert_eq!(shown(Path::new("a.json")), "a.json");
    }
}
