//! Outputs that are whole or absent. Every file a study's front end writes (JSON, CSV, reports,
//! plots, written scenarios and networks, FMUs) goes to a temporary file in the target's own
//! folder (`.{name}.XXXXXX.tmp`, created exclusively by the `tempfile` crate), is flushed and
//! synced to disk, and only then renamed over the target (`tempfile`'s `persist`). A rename
//! within one file system is atomic (POSIX `rename(2)`), so:
//!
//! * a SIGKILL, a power loss, a second Ctrl-C or a full disk during the write leaves the previous
//!   file (or no file) in place, never a truncated one; the error names the path;
//! * two processes writing one path each rename a whole file of their own: the last one stays,
//!   never one summary followed by the other's tail;
//! * a temporary file that is not committed (an error, a panic) is removed when dropped; one left
//!   by a killed process keeps its `.tmp` name beside the target and is never mistaken for it;
//! * the null device (`--out /dev/null`) is written in place: a rename over it would replace
//!   the device with a regular file (as root, `/dev/null` itself); any other special file (a
//!   FIFO, a folder, another device) and an over-long path are refused before anything is
//!   opened ([`super::target::refusal`]).
//!
//! `tempfile` replaces the hand-written exclusive creation, naming and clean-up this file had; it
//! is a well-kept crate already in the build (criterion, proptest). What stays ours: the sync of
//! the data and of the folder, and an error that names the file the user asked for.

use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// A write to an output file failed: the target, what was being done, the cause.
#[derive(Debug, thiserror::Error)]
#[error("{action} {}: {source}", path.display())]
pub struct OutputError {
    /// The file the user asked for (not the temporary file).
    pub path: PathBuf,
    /// "cannot create", "writing", "cannot replace" …
    pub action: &'static str,
    #[source]
    pub source: std::io::Error,
}

/// A file being written: bytes go to a temporary file beside `path`; [`AtomicFile::commit`]
/// renames it into place, dropping it uncommitted removes it.
pub struct AtomicFile {
    path: PathBuf,
    out: Option<Sink>,
}

/// Where the bytes go: a temporary file renamed over the target, or the null device written in
/// place — renaming over a device would replace it.
enum Sink {
    Temp(BufWriter<NamedTempFile>),
    Device(BufWriter<std::fs::File>),
}

impl AtomicFile {
    /// Start writing `path`, creating its folder.
    pub fn create(path: &Path) -> Result<AtomicFile, OutputError> {
        let fail = |action, source| OutputError {
            path: path.to_path_buf(),
            action,
            source,
        };
        if let Some(why) = super::target::refusal(path) {
            return Err(OutputError {
                path: PathBuf::from(super::target::shown(path)),
                action: "cannot write",
                source: std::io::Error::new(std::io::ErrorKind::InvalidInput, why),
            });
        }
        if super::target::is_null(path) {
            let device = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(|e| fail("cannot open", e))?;
            return Ok(AtomicFile {
                path: path.to_path_buf(),
                out: Some(Sink::Device(BufWriter::new(device))),
            });
        }
        let parent = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(|e| fail("cannot create the folder of", e))?;
        let name = path
            .file_name()
            .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
        let temp = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".tmp")
            .tempfile_in(parent)
            .map_err(|e| fail("cannot create", e))?;
        Ok(AtomicFile {
            path: path.to_path_buf(),
            out: Some(Sink::Temp(BufWriter::new(temp))),
        })
    }

    fn fail(&self, action: &'static str, source: std::io::Error) -> OutputError {
        OutputError {
            path: self.path.clone(),
            action,
            source,
        }
    }

    /// Flush, sync and rename into place. On error the target is untouched and the temporary
    /// file is removed.
    pub fn commit(mut self) -> Result<(), OutputError> {
        let out = match self.out.take().expect("an AtomicFile is committed once") {
            Sink::Temp(out) => out,
            Sink::Device(mut device) => {
                return device.flush().map_err(|e| self.fail("writing", e));
            }
        };
        let temp = out
            .into_inner()
            .map_err(|e| self.fail("writing", e.into_error()))?;
        temp.as_file()
            .sync_all()
            .map_err(|e| self.fail("writing", e))?;
        temp.persist(&self.path)
            .map_err(|e| self.fail("cannot replace", e.error))?;
        // The rename itself is durable once the folder is synced (best effort: not every file
        // system lets a folder be opened for sync).
        if let Some(dir) = self.path.parent().filter(|p| !p.as_os_str().is_empty()) {
            let _ = std::fs::File::open(dir).and_then(|d| d.sync_all());
        }
        Ok(())
    }

    fn sink(&mut self) -> &mut Sink {
        self.out
            .as_mut()
            .expect("an AtomicFile is written before commit")
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self.sink() {
            Sink::Temp(w) => w.write(buf),
            Sink::Device(w) => w.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self.sink() {
            Sink::Temp(w) => w.flush(),
            Sink::Device(w) => w.flush(),
        }
    }
}

impl Seek for AtomicFile {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        match self.sink() {
            Sink::Temp(w) => w.seek(pos),
            Sink::Device(w) => w.seek(pos),
        }
    }
}

/// Write `bytes` to `path` whole or not at all.
pub fn write(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), OutputError> {
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes.as_ref())
        .map_err(|e| f.fail("writing", e))?;
    f.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("entrynav-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_committed_file_replaces_the_old_one_and_leaves_no_temporary() {
        let d = folder("commit");
        let p = d.join("o.json");
        write(&p, "old").unwrap();
        write(&p, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
        assert_eq!(entries(&d), ["o.json"]);
    }

    #[test]
    fn an_uncommitted_file_leaves_the_old_one_intact() {
        let d = folder("drop");
        let p = d.join("o.json");
        write(&p, "{\"good\": true}").unwrap();
        {
            let mut f = AtomicFile::create(&p).unwrap();
            f.write_all(b"{\"half").unwrap();
            f.flush().unwrap();
            // The target still holds the old file while the new one is written.
            assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\"good\": true}");
        } // dropped without commit: an error or a panic while writing
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\"good\": true}");
        assert_eq!(entries(&d), ["o.json"]);
    }

    #[test]
    fn a_commit_that_cannot_rename_names_the_target_and_leaves_the_old_file() {
        // The folder is replaced while the file is written: the rename finds no temporary file.
        // (A full disk, a write error, is tested end to end in cli/tests/outputs.rs.)
        let d = folder("rename");
        let p = d.join("sub").join("o.json");
        write(&p, "keep").unwrap();
        let mut f = AtomicFile::create(&p).unwrap();
        f.write_all(b"new").unwrap();
        std::fs::rename(d.join("sub"), d.join("moved")).unwrap();
        std::fs::create_dir(d.join("sub")).unwrap();
        let err = f.commit().unwrap_err();
        assert!(err.to_string().contains("o.json"), "{err}");
        assert!(!d.join("sub").join("o.json").exists());
        let kept = std::fs::read_to_string(d.join("moved").join("o.json")).unwrap();
        assert_eq!(kept, "keep");
    }

    #[test]
    fn concurrent_writers_never_leave_a_mixed_file() {
        let d = folder("race");
        let p = d.join("o.txt");
        let bodies: Vec<String> = (0..8)
            .map(|i| {
                char::from(b'a' + i)
                    .to_string()
                    .repeat(200_000 + 1000 * i as usize)
            })
            .collect();
        std::thread::scope(|s| {
            for b in &bodies {
                let p = &p;
                s.spawn(move || {
                    for _ in 0..5 {
                        write(p, b).unwrap();
                    }
                });
            }
        });
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(
            bodies.contains(&text),
            "a mixed file of {} bytes",
            text.len()
        );
        assert_eq!(entries(&d), ["o.txt"]);
    }

    #[test]
    fn a_fifo_is_refused_before_it_is_opened() {
        let d = folder("fifo");
        let p = d.join("pipe.json");
        let made = std::process::Command::new("mkfifo").arg(&p).status();
        if made.is_ok_and(|s| s.success()) {
            let err = write(&p, "x").unwrap_err().to_string();
            assert!(err.contains("pipe.json") && err.contains("FIFO"), "{err}");
        }
    }

    #[test]
    fn the_null_device_is_written_in_place_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        write(Path::new("/dev/null"), "discarded").unwrap();
        let kind = std::fs::metadata("/dev/null").unwrap().file_type();
        assert!(kind.is_char_device(), "/dev/null is no longer a device");
    }
}
