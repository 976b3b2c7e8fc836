//! `fmuResourceLocation` URIs to paths.

use std::path::PathBuf;
use thiserror::Error;

/// Why a resource location cannot be used.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum UriError {
    /// The importer gave no `fmuResourceLocation`.
    #[error("no fmuResourceLocation was given")]
    Missing,
    /// A `file:` URI without an absolute path.
    #[error("resource URI '{0}' has no absolute path")]
    NoAbsolutePath(String),
    /// A `file:` URI naming another host.
    #[error("resource URI '{0}' names a remote host; only local file: URIs are supported")]
    RemoteHost(String),
    /// Not a `file:` URI.
    #[error("resource location '{0}' is not a file: URI (expected file:///path/to/resources)")]
    NotFileUri(String),
    /// A `%` not followed by two hex digits.
    #[error("bad percent escape in resource URI path '{0}'")]
    BadEscape(String),
    /// The decoded path is not UTF-8.
    #[error("resource URI path '{0}' is not UTF-8")]
    NotUtf8(String),
}

/// The directory a `file:` URI names: `file:///abs/path`, `file://localhost/abs/path`,
/// `file:/abs/path`, with percent-encoded bytes decoded (`%20` → space). A plain absolute path is
/// accepted too. A trailing slash is allowed.
pub fn resource_dir(uri: &str) -> Result<PathBuf, UriError> {
    let lower = uri.get(..5).map(|s| s.to_ascii_lowercase());
    let path = if lower.as_deref() == Some("file:") {
        let rest = &uri[5..];
        if let Some(after) = rest.strip_prefix("//") {
            if after.starts_with('/') {
                after
            } else if let Some(p) = after.strip_prefix("localhost") {
                if !p.starts_with('/') {
                    return Err(UriError::NoAbsolutePath(uri.to_string()));
                }
                p
            } else {
                return Err(UriError::RemoteHost(uri.to_string()));
            }
        } else if rest.starts_with('/') {
            rest
        } else {
            return Err(UriError::NoAbsolutePath(uri.to_string()));
        }
    } else if uri.starts_with('/') {
        uri
    } else {
        return Err(UriError::NotFileUri(uri.to_string()));
    };
    Ok(PathBuf::from(percent_decode(path)?))
}

fn percent_decode(s: &str) -> Result<String, UriError> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| UriError::BadEscape(s.to_string()))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| UriError::NotUtf8(s.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forms() {
        let p = |s: &str| resource_dir(s).map(|p| p.display().to_string());
        assert_eq!(p("file:///tmp/a b/res").unwrap(), "/tmp/a b/res");
        assert_eq!(p("file:///tmp/a%20b/res/").unwrap(), "/tmp/a b/res/");
        assert_eq!(p("file:/tmp/x%2Fy").unwrap(), "/tmp/x/y");
        assert_eq!(p("FILE://localhost/tmp/r").unwrap(), "/tmp/r");
        assert_eq!(p("/tmp/r").unwrap(), "/tmp/r");
        assert!(p("file://server/share").is_err());
        assert!(p("http://x/y").is_err());
        assert!(p("file:///tmp/%zz").is_err());
        assert!(p("file:///tmp/%2").is_err());
        assert!(p("file:relative").is_err());
        assert!(p("").is_err());
    }
}
