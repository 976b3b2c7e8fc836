//! Reading a file we were pointed at, bounded: only a regular file (a FIFO would block the read
//! forever, `/dev/zero` would grow until memory runs out), at most [`MAX_FILE_BYTES`].

use std::io::Read;
use std::path::Path;

/// Largest file entrynav reads (a scenario, an atmosphere table, a network, a grid, a
/// summary): 256 MiB. The largest we ship is under 1 MB.
pub const MAX_FILE_BYTES: u64 = 256 << 20;

fn refused(why: String) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidInput, why)
}

/// The text of the regular file `path`, refused (before it is opened) when it is a FIFO, a
/// device, a socket or a folder, and refused when it holds more than [`MAX_FILE_BYTES`] or is
/// not UTF-8. Errors are `io::Error`s for the caller to name the path.
pub fn read_text(path: impl AsRef<Path>) -> std::io::Result<String> {
    let bytes = read_bytes(path.as_ref())?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("not UTF-8 text (invalid byte at offset {at})"),
        )
    })
}

/// The bytes of the regular file `path`, bounded as [`read_text`].
pub fn read_bytes(path: &Path) -> std::io::Result<Vec<u8>> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        let what = if meta.is_dir() {
            "a folder"
        } else {
            "not a regular file (a FIFO, a device or a socket)"
        };
        return Err(refused(format!(
            "{what}; entrynav reads only regular files"
        )));
    }
    let too_big = |n: u64| {
        refused(format!(
            "{n} bytes or more, more than the {} MiB entrynav reads",
            MAX_FILE_BYTES >> 20
        ))
    };
    if meta.len() > MAX_FILE_BYTES {
        return Err(too_big(meta.len()));
    }
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // The file may grow between the size check and the read: never read past the cap.
    file.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_big(MAX_FILE_BYTES + 1));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_regular_file_is_read_and_anything_else_is_refused_at_once() {
        let dir = std::env::temp_dir().join(format!("entrynav-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.toml");
        std::fs::write(&file, "name = \"x\"\n").unwrap();
        assert_eq!(read_text(&file).unwrap(), "name = \"x\"\n");
        let err = read_text(&dir).unwrap_err().to_string();
        assert!(err.contains("a folder"), "{err}");
        // /dev/zero is endless: refused before a byte is read.
        let err = read_text(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(err.contains("not a regular file"), "{err}");
        std::fs::write(&file, [b'a', 0xff, b'b']).unwrap();
        let err = read_text(&file).unwrap_err().to_string();
        assert!(
            err.contains("not UTF-8") && err.contains("offset 1"),
            "{err}"
        );
    }
}
