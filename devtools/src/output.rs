//! Files the tools write, whole or absent: the bytes go to a temporary file beside the target,
//! which is synced and renamed over it (a rename within one folder is atomic), as the `entrynav`
//! command writes its outputs.

use std::io::Write;
use std::path::{Path, PathBuf};

/// A write to an output file failed: the target, what was being done, the cause.
#[derive(Debug, thiserror::Error)]
#[error("{action} {}: {source}", path.display())]
pub struct OutputError {
    /// The file asked for (not the temporary file).
    pub path: PathBuf,
    /// "cannot create", "writing", "cannot replace" …
    pub action: &'static str,
    /// The operating system's error.
    #[source]
    pub source: std::io::Error,
}

/// Write `bytes` to `path` whole or not at all, creating its folder.
pub fn write(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), OutputError> {
    let fail = |action, source| OutputError {
        path: path.to_path_buf(),
        action,
        source,
    };
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|e| fail("cannot create the folder of", e))?;
    }
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    let temp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let written = std::fs::File::create(&temp)
        .map_err(|e| fail("cannot create", e))
        .and_then(|mut f| {
            f.write_all(bytes.as_ref())
                .and_then(|()| f.sync_all())
                .map_err(|e| fail("writing", e))
        })
        .and_then(|()| std::fs::rename(&temp, path).map_err(|e| fail("cannot replace", e)));
    if written.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_replaced_whole_and_a_failed_write_leaves_no_temporary_file() {
        let dir = std::env::temp_dir().join(format!("entrynav-dev-output-{}", std::process::id()));
        let path = dir.join("sub/out.csv");
        write(&path, "a\n").unwrap();
        write(&path, "b\n").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "b\n");
        // A folder where the file should be: the rename fails, the folder and nothing else stays.
        let blocked = dir.join("blocked");
        std::fs::create_dir_all(blocked.join("x")).unwrap();
        let e = write(&blocked, "c").unwrap_err();
        assert_eq!(e.action, "cannot replace");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().collect();
        assert_eq!(left.len(), 2, "{left:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
