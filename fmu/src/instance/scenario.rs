//! Where an instance's scenario comes from, and what an error about a scenario file may say.
//!
//! The `scenario` parameter is a built-in name (no file is read) or a file in the FMU's
//! `resources/` folder: a relative name of plain components, resolved (symbolic links included)
//! to a regular file inside that folder. A file anywhere else — an absolute path, `..`, a link
//! out of the folder — is read only when the importer sets `allow_external_files = true`. The
//! files a scenario refers to (tabulated atmospheres) obey the same rule, and every file is
//! size-checked before it is read ([`MAX_SCENARIO_BYTES`], [`MAX_TABLE_BYTES`]). Files are read by
//! the one scenario loader (`entrynav-loader`).
//!
//! An error about a file names the file and, for a TOML syntax error, the line and column; it
//! never quotes the file. For a file outside `resources/` it says only which kind of problem and
//! where (a host file a parameter names must not be disclosed through the log); for a file inside
//! `resources/` (part of the FMU) it also gives the parser's or the validator's explanation.

use crate::limits::{MAX_SCENARIO_BYTES, MAX_TABLE_BYTES};
use crate::uri::UriError;
use entrynav::atmosphere::AtmosphereError;
use entrynav::files::FileError;
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioError};
use entrynav_loader::{Base, LoadError};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;
use thiserror::Error;

/// Why the scenario cannot be loaded.
#[derive(Debug, Error)]
pub enum ScenarioFileError {
    /// A name that is neither a built-in nor a file the rules allow.
    #[error(
        "scenario '{name}' is neither a built-in ({builtins}) nor a file in the FMU's resources folder{hint}"
    )]
    NotAllowed {
        /// The parameter.
        name: String,
        /// Comma-separated built-in names.
        builtins: String,
        /// What would allow it.
        hint: &'static str,
    },
    /// A file name with no usable resources folder to find it in.
    #[error(
        "scenario '{name}' is not a built-in ({builtins}) and the resources folder is unusable: {reason}"
    )]
    NoResources {
        /// The parameter.
        name: String,
        /// Comma-separated built-in names.
        builtins: String,
        /// Why the resources folder is unusable.
        reason: UriError,
    },
    /// The file does not exist or cannot be opened.
    #[error("scenario file '{name}' cannot be read: {reason}")]
    Unreadable {
        /// The file as named.
        name: String,
        /// The operating system's reason.
        reason: String,
    },
    /// Not a regular file (a directory, a device, a pipe).
    #[error("scenario file '{name}' is not a regular file")]
    NotRegular {
        /// The file as named.
        name: String,
    },
    /// Larger than a scenario file may be.
    #[error("scenario file '{name}' is {size} bytes; the limit is {MAX_SCENARIO_BYTES}")]
    TooLarge {
        /// The file as named.
        name: String,
        /// Its size.
        size: u64,
    },
    /// The file is not a valid scenario.
    #[error("scenario file '{name}': {what}")]
    Invalid {
        /// The file as named.
        name: String,
        /// What is wrong and where, without the file's content.
        what: String,
    },
}

const EXTERNAL_HINT: &str = "; a file elsewhere needs the parameter allow_external_files = true";

fn builtins() -> String {
    BUILTIN_NAMES.join(", ")
}

fn io_reason(e: &std::io::Error) -> String {
    e.kind().to_string()
}

/// The scenario the `scenario` parameter `name` names, under the rules of the module
/// documentation; `resources` is the FMU's resources folder (or why it is unusable).
pub(super) fn load_parameter_scenario(
    name: &str,
    resources: &Result<PathBuf, UriError>,
    allow_external: bool,
) -> Result<Arc<Scenario>, ScenarioFileError> {
    let name = name.trim();
    if BUILTIN_NAMES.contains(&name) {
        return entrynav_loader::load(name, &[], Base::Nowhere)
            .map(Arc::new)
            .map_err(|e| ScenarioFileError::Invalid {
                name: name.to_string(),
                what: e.to_string(),
            });
    }
    let plain = Path::new(name)
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    if !allow_external && (!plain || name.is_empty()) {
        return Err(ScenarioFileError::NotAllowed {
            name: name.to_string(),
            builtins: builtins(),
            hint: EXTERNAL_HINT,
        });
    }
    let dir = match resources {
        Ok(d) => Some(d.as_path()),
        Err(_) if allow_external && Path::new(name).is_absolute() => None,
        Err(reason) => {
            return Err(ScenarioFileError::NoResources {
                name: name.to_string(),
                builtins: builtins(),
                reason: reason.clone(),
            });
        }
    };
    let path = match dir {
        Some(d) => d.join(name),
        None => PathBuf::from(name),
    };
    load_file(name, &path, dir, allow_external)
}

/// The embedded scenario `file` of a specific FMU, in its resources folder `dir` (the name must be
/// a plain file name inside the folder).
pub fn load_resource_scenario(dir: &Path, file: &str) -> Result<Arc<Scenario>, ScenarioFileError> {
    let plain = Path::new(file)
        .components()
        .all(|c| matches!(c, Component::Normal(_)));
    if !plain || file.is_empty() {
        return Err(ScenarioFileError::NotAllowed {
            name: file.to_string(),
            builtins: builtins(),
            hint: "",
        });
    }
    load_file(file, &dir.join(file), Some(dir), false)
}

/// Canonical `path` and whether it lies inside the canonical `dir`.
fn locate(
    name: &str,
    path: &Path,
    dir: Option<&Path>,
) -> Result<(PathBuf, bool), ScenarioFileError> {
    let canonical = path.canonicalize().map_err(|e| {
        let reason = if e.kind() == std::io::ErrorKind::NotFound {
            // Most often a mistyped built-in: list them, and the nearest one.
            format!(
                "no such file, and no built-in of that name ({}){}",
                builtins(),
                entrynav_loader::suggestion(name)
            )
        } else {
            io_reason(&e)
        };
        ScenarioFileError::Unreadable {
            name: name.to_string(),
            reason,
        }
    })?;
    let inside = dir
        .and_then(|d| d.canonicalize().ok())
        .is_some_and(|d| canonical.starts_with(d));
    Ok((canonical, inside))
}

fn load_file(
    name: &str,
    path: &Path,
    dir: Option<&Path>,
    allow_external: bool,
) -> Result<Arc<Scenario>, ScenarioFileError> {
    let (canonical, inside) = locate(name, path, dir)?;
    if !inside && !allow_external {
        return Err(ScenarioFileError::NotAllowed {
            name: name.to_string(),
            builtins: builtins(),
            hint: EXTERNAL_HINT,
        });
    }
    let meta = std::fs::metadata(&canonical).map_err(|e| ScenarioFileError::Unreadable {
        name: name.to_string(),
        reason: io_reason(&e),
    })?;
    if !meta.is_file() {
        return Err(ScenarioFileError::NotRegular {
            name: name.to_string(),
        });
    }
    if meta.len() > MAX_SCENARIO_BYTES {
        return Err(ScenarioFileError::TooLarge {
            name: name.to_string(),
            size: meta.len(),
        });
    }
    let invalid = |e: &ScenarioError| ScenarioFileError::Invalid {
        name: name.to_string(),
        what: describe(e, inside),
    };
    let text_path = canonical.to_string_lossy().into_owned();
    let src = entrynav_loader::resolve(&text_path, Base::Nowhere).map_err(|e| match e {
        LoadError::Scenario(e) => invalid(&e),
        LoadError::NotFound { source, .. } => ScenarioFileError::Unreadable {
            name: name.to_string(),
            reason: source.to_string(),
        },
        other => ScenarioFileError::Invalid {
            name: name.to_string(),
            what: other.to_string(),
        },
    })?;
    let resources = dir.and_then(|d| d.canonicalize().ok());
    let referenced = confined_loader(src.dir.clone(), resources, allow_external);
    Scenario::build(src.config, &referenced)
        .map(Arc::new)
        .map_err(|e| invalid(&e))
}

/// The loader of the files a scenario refers to: the same rules as for the scenario file (inside
/// `resources` unless `allow_external`, a regular file of at most [`MAX_TABLE_BYTES`]), then the
/// scenario loader's own file loader.
fn confined_loader(
    dir: PathBuf,
    resources: Option<PathBuf>,
    allow_external: bool,
) -> impl Fn(&str) -> Result<String, FileError> {
    let read = entrynav_loader::file_loader(&dir);
    move |p: &str| {
        let path = if Path::new(p).is_absolute() {
            PathBuf::from(p)
        } else {
            dir.join(p)
        };
        let canonical = path
            .canonicalize()
            .map_err(|e| FileError::new(p, io_reason(&e)))?;
        let inside = resources.as_ref().is_some_and(|r| canonical.starts_with(r));
        if !inside && !allow_external {
            return Err(FileError::new(
                p,
                "outside the FMU's resources folder (allow_external_files is false)",
            ));
        }
        let meta = std::fs::metadata(&canonical).map_err(|e| FileError::new(p, io_reason(&e)))?;
        if !meta.is_file() || meta.len() > MAX_TABLE_BYTES {
            return Err(FileError::new(
                p,
                format!("not a regular file of at most {MAX_TABLE_BYTES} bytes"),
            ));
        }
        read(&canonical.to_string_lossy())
    }
}

/// A TOML parser message without the quoted source lines: the position line, and (`explain`) the
/// parser's explanation after the caret line.
fn parse_position(message: &str, explain: bool) -> String {
    let mut lines = message.lines();
    let first = lines.next().unwrap_or_default();
    let position = first
        .strip_prefix("TOML parse error at ")
        .map(|p| format!("TOML parse error at {p}"))
        .unwrap_or_else(|| "TOML parse error".to_string());
    let explanation: Vec<&str> = message
        .lines()
        .skip_while(|l| !l.trim_start().starts_with('|') || !l.contains('^'))
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .collect();
    if explain && !explanation.is_empty() {
        format!("{position}: {}", explanation.join("; "))
    } else {
        format!("{position} (the file's content is not shown)")
    }
}

/// What is wrong with a scenario file, without quoting it; with the validator's details only for
/// a file inside the FMU's resources folder.
fn describe(e: &ScenarioError, inside: bool) -> String {
    const HIDDEN: &str = "details of files outside the FMU's resources folder are not shown";
    match e {
        ScenarioError::Parse { message, .. } => parse_position(message, inside),
        _ if inside => e.to_string(),
        ScenarioError::OutOfRange { field, allowed, .. } => {
            format!("{field} is out of range: {allowed} ({HIDDEN})")
        }
        ScenarioError::Invalid { field, .. } => format!("{field} is invalid ({HIDDEN})"),
        ScenarioError::Atmosphere(a @ AtmosphereError::LoadFailed { .. }) => a.to_string(),
        ScenarioError::Atmosphere(_) => format!("the atmosphere description is invalid ({HIDDEN})"),
        ScenarioError::Beacon(_) => format!("a beacon description is invalid ({HIDDEN})"),
        ScenarioError::Sensor(_) => format!("a sensor description is invalid ({HIDDEN})"),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_errors_keep_the_position_and_drop_the_source_line() {
        let e = entrynav::scenario::ScenarioConfig::from_toml_str(
            "root:x:0:0:root:/root:/bin/bash\n",
            "/etc/passwd",
        )
        .unwrap_err();
        let full = e.to_string();
        assert!(full.contains("root:x:0:0"), "{full}");
        for inside in [false, true] {
            let d = describe(&e, inside);
            assert!(d.contains("line 1, column"), "{d}");
            assert!(!d.contains("root"), "{d}");
        }
        assert!(describe(&e, false).contains("not shown"));
    }
}
