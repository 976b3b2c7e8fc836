//! [`file_uri`]: the `file://` URI of a folder, as an FMI 2.0 resource location.

use std::path::Path;

/// The `file://` URI of a folder, percent-encoded.
pub fn file_uri(dir: &Path) -> String {
    let mut s = String::from("file://");
    for b in dir.to_string_lossy().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => {
                s.push(b as char)
            }
            _ => s.push_str(&format!("%{b:02X}")),
        }
    }
    s
}
