//! `fmuResourceLocation` URIs to paths.

use std::path::PathBuf;

/// The directory a `file:` URI names: `file:///abs/path`, `file://localhost/abs/path`,
/// `file:/abs/path`, with percent-encoded bytes decoded (`%20` → space). A plain absolute path is
/// accepted too. A trailing slash is allowed.
pub fn resource_dir(uri: &str) -> Result<PathBuf, String> {
    let lower = uri.get(..5).map(|s| s.to_ascii_lowercase());
    let path = if lower.as_deref() == Some("file:") {
        let rest = &uri[5..];
        if let Some(after) = rest.strip_prefix("//") {
            if after.starts_with('/') {
                after
            } else if let Some(p) = after.strip_prefix("localhost") {
                if !p.starts_with('/') {
                    return Err(format!("resource URI '{uri}' has no absolute path"));
                }
                p
            } else {
                return Err(format!(
                    "resource URI '{uri}' names a remote host; only local file: URIs are supported"
                ));
            }
        } else if rest.starts_with('/') {
            rest
        } else {
            return Err(format!("resource URI '{uri}' has no absolute path"));
        }
    } else if uri.starts_with('/') {
        uri
    } else {
        return Err(format!(
            "resource location '{uri}' is not a file: URI (expected file:///path/to/resources)"
        ));
    };
    Ok(PathBuf::from(percent_decode(path)?))
}

fn percent_decode(s: &str) -> Result<String, String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("bad percent escape in resource URI path '{s}'"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("resource URI path '{s}' is not UTF-8"))
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
