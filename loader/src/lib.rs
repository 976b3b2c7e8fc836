//! The one scenario loader of entrynav, shared by the command line, the optimizer commands and
//! the FMUs (the core does no I/O, so reading files happens here).
//!
//! * [`resolve`]: a built-in scenario name, or a TOML file (absolute, or relative to a base
//!   folder: the current directory for the CLI, the FMU's `resources/` folder for an FMU);
//! * [`apply_overrides`]: `--set PATH=VALUE` edits in TOML syntax, re-validated;
//! * [`file_loader`] / [`build`]: the files a scenario refers to (tabulated atmospheres) are read
//!   relative to the scenario file's folder.

use entrynav::files::FileError;
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig, ScenarioError};
use std::path::{Path, PathBuf};
use thiserror::Error;

mod read;
pub mod summary;
pub use read::{MAX_FILE_BYTES, read_bytes, read_text};

/// Why a scenario could not be loaded.
#[derive(Debug, Error)]
pub enum LoadError {
    /// Neither a built-in nor a readable file.
    #[error(
        "scenario '{name}' is neither a built-in ({builtins}) nor a readable file ({})",
        path.display()
    )]
    NotFound {
        /// What was asked for.
        name: String,
        /// Where it was looked for.
        path: PathBuf,
        /// Comma-separated built-in names.
        builtins: String,
        /// Why the file could not be read.
        #[source]
        source: std::io::Error,
    },
    /// A relative file name with no folder to resolve it against.
    #[error(
        "scenario '{name}' is not a built-in ({builtins}) and there is no folder to find it in"
    )]
    NoFolder {
        /// What was asked for.
        name: String,
        /// Comma-separated built-in names.
        builtins: String,
    },
    /// The scenario text or a value in it is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// A `--set` override that cannot be applied.
    #[error("--set '{set}': {reason}")]
    Override {
        /// The override as given.
        set: String,
        /// What is wrong.
        reason: String,
    },
    /// The scenario's canonical TOML did not read back as a table (a bug, not a user error).
    #[error("--set {sets}: the scenario's canonical TOML does not read back")]
    OverrideParse {
        /// The overrides as given, space-separated.
        sets: String,
        /// The TOML parser's error.
        #[source]
        source: toml::de::Error,
    },
    /// The edited scenario could not be written as TOML again.
    #[error("--set {sets}: the edited scenario cannot be written as TOML")]
    OverrideWrite {
        /// The overrides as given, space-separated.
        sets: String,
        /// The TOML writer's error.
        #[source]
        source: toml::ser::Error,
    },
}

/// Where a scenario came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Origin {
    /// A built-in scenario.
    Builtin(String),
    /// A TOML file.
    File(PathBuf),
}

/// Where a relative scenario file name is looked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Base<'a> {
    /// The process's current directory (the command line): the name is used as given.
    CurrentDir,
    /// A folder (an FMU's `resources/`).
    Folder(&'a Path),
    /// Nowhere: only built-ins and absolute paths resolve.
    Nowhere,
}

/// A scenario configuration with the folder its relative file names resolve against.
#[derive(Debug, Clone)]
pub struct ScenarioSource {
    /// The parsed, validated configuration.
    pub config: ScenarioConfig,
    /// Folder of the scenario file (the base folder for a built-in).
    pub dir: PathBuf,
    /// Built-in or file.
    pub origin: Origin,
}

impl ScenarioSource {
    /// The configuration and the folder its relative file names resolve against.
    pub fn into_parts(self) -> (ScenarioConfig, PathBuf) {
        (self.config, self.dir)
    }
}

fn builtins() -> String {
    BUILTIN_NAMES.join(", ")
}

/// Resolve `name_or_file`: a built-in name, else a TOML file, absolute or relative to `base`.
pub fn resolve(name_or_file: &str, base: Base<'_>) -> Result<ScenarioSource, LoadError> {
    let name = name_or_file.trim();
    if BUILTIN_NAMES.contains(&name) {
        return Ok(ScenarioSource {
            config: ScenarioConfig::builtin(name)?,
            dir: match base {
                Base::Folder(dir) => dir.to_path_buf(),
                Base::CurrentDir | Base::Nowhere => PathBuf::from("."),
            },
            origin: Origin::Builtin(name.to_string()),
        });
    }
    let path = match base {
        _ if Path::new(name).is_absolute() => PathBuf::from(name),
        Base::CurrentDir => PathBuf::from(name),
        Base::Folder(dir) => dir.join(name),
        Base::Nowhere => {
            return Err(LoadError::NoFolder {
                name: name.to_string(),
                builtins: builtins(),
            });
        }
    };
    let text = read_text(&path).map_err(|source| LoadError::NotFound {
        name: name.to_string(),
        path: path.clone(),
        builtins: builtins(),
        source,
    })?;
    let config = ScenarioConfig::from_toml_str(&text, &path.display().to_string())?;
    let dir = path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    Ok(ScenarioSource {
        config,
        dir,
        origin: Origin::File(path),
    })
}

/// Apply `--set path=value` overrides (TOML dotted path, TOML value syntax) to a scenario and
/// re-validate it, e.g. `truth.density_bias=0.095` or `dispersions.density_bias=0`; a numeric
/// key indexes an array: `beacons.0.lat_deg=3.0`, `filter.q_diag.3=1e-6`. A value that
/// is not valid TOML is taken as a string.
pub fn apply_overrides(cfg: ScenarioConfig, sets: &[String]) -> Result<ScenarioConfig, LoadError> {
    if sets.is_empty() {
        return Ok(cfg);
    }
    let mut doc: toml::Table =
        toml::from_str(&cfg.to_toml_string()).map_err(|source| LoadError::OverrideParse {
            sets: sets.join(" "),
            source,
        })?;
    for set in sets {
        let bad = |reason: String| LoadError::Override {
            set: set.clone(),
            reason,
        };
        let (path, value) = set
            .split_once('=')
            .ok_or_else(|| bad("expected PATH=VALUE, e.g. truth.density_bias=0.095".to_string()))?;
        let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {value}")) {
            Ok(mut t) => t
                .remove("v")
                .unwrap_or(toml::Value::String(value.to_string())),
            Err(_) => toml::Value::String(value.to_string()),
        };
        let keys: Vec<&str> = path.trim().split('.').collect();
        let (last, parents) = keys
            .split_last()
            .ok_or_else(|| bad("empty path".to_string()))?;
        // A numeric key indexes an array (`beacons.0.lat_deg`, `filter.q_diag.3`).
        if let Some((first, rest)) = parents.split_first() {
            let mut slot: &mut toml::Value = doc
                .entry(first.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            for k in rest.iter().chain(std::iter::once(last)) {
                slot = match slot {
                    toml::Value::Array(items) => {
                        let n = items.len();
                        let i: usize = k.parse().map_err(|_| {
                            bad(format!("'{k}' is not an index of an array of {n} entries"))
                        })?;
                        items.get_mut(i).ok_or_else(|| {
                            bad(format!(
                                "index {i} is past the array's {n} entries (0 to {})",
                                n.saturating_sub(1)
                            ))
                        })?
                    }
                    toml::Value::Table(t) => t
                        .entry(k.to_string())
                        .or_insert_with(|| toml::Value::Table(toml::Table::new())),
                    _ => return Err(bad(format!("cannot reach '{k}': its parent is a value"))),
                };
            }
            *slot = value;
        } else {
            doc.insert(last.to_string(), value);
        }
        // A value of the wrong type or an unknown field is this argument's fault: say so, not
        // "line 96, column 16" of a document the user never wrote.
        if let Err(e) = toml::Value::Table(doc.clone()).try_into::<ScenarioConfig>() {
            return Err(bad(e.message().trim_end().to_string()));
        }
    }
    let text = toml::to_string(&doc).map_err(|source| LoadError::OverrideWrite {
        sets: sets.join(" "),
        source,
    })?;
    Ok(ScenarioConfig::from_toml_str(
        &text,
        "scenario with --set overrides",
    )?)
}

/// A loader for the files a scenario refers to: absolute paths as they are, relative ones
/// against `dir`.
pub fn file_loader(dir: &Path) -> impl Fn(&str) -> Result<String, FileError> + use<> {
    let dir = dir.to_path_buf();
    move |p: &str| {
        let path = if Path::new(p).is_absolute() {
            PathBuf::from(p)
        } else {
            dir.join(p)
        };
        read_text(&path).map_err(|e| FileError::new(path.display().to_string(), e.to_string()))
    }
}

/// Build a runnable scenario, reading referenced files relative to `dir`.
pub fn build(cfg: ScenarioConfig, dir: &Path) -> Result<Scenario, LoadError> {
    Ok(Scenario::build(cfg, &file_loader(dir))?)
}

/// Everything at once: resolve `name_or_file` against `base`, apply `sets`, build.
pub fn load(name_or_file: &str, sets: &[String], base: Base<'_>) -> Result<Scenario, LoadError> {
    let src = resolve(name_or_file, base)?;
    let cfg = apply_overrides(src.config, sets)?;
    build(cfg, &src.dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtins_files_and_overrides() {
        let s = load("four-beacon-fusion", &[], Base::Nowhere).unwrap();
        assert_eq!(s.config.name, "four-beacon-fusion");
        let dir = std::env::temp_dir().join(format!("entrynav-loader-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let text = entrynav::scenario::builtin_toml("msl-pressure").unwrap();
        std::fs::write(dir.join("mine.toml"), text).unwrap();
        let src = resolve("mine.toml", Base::Folder(&dir)).unwrap();
        assert_eq!(src.origin, Origin::File(dir.join("mine.toml")));
        assert_eq!(src.dir, dir);
        let cfg = apply_overrides(src.config, &["truth.density_bias=0.05".into()]).unwrap();
        assert_eq!(cfg.truth.density_bias, 0.05);
        // Errors name what was asked for and why.
        let e = resolve("nope.toml", Base::Folder(&dir))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("nope.toml") && e.contains("four-beacon-fusion"),
            "{e}"
        );
        let e = resolve("nope.toml", Base::Nowhere).unwrap_err().to_string();
        assert!(e.contains("no folder"), "{e}");
        let e = apply_overrides(cfg.clone(), &["truth.density_bias".into()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("PATH=VALUE"), "{e}");
        let e = apply_overrides(cfg, &["truth.density_bias=11".into()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("truth.density_bias"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_unreadable_file_keeps_the_operating_systems_error_as_its_source() {
        let dir = std::env::temp_dir().join(format!("entrynav-loader-src-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = resolve("missing.toml", Base::Folder(&dir)).unwrap_err();
        let io = std::error::Error::source(&e)
            .and_then(|s| s.downcast_ref::<std::io::Error>())
            .expect("the io::Error is the source");
        assert_eq!(io.kind(), std::io::ErrorKind::NotFound);
        // The message names the path; the reason is the source's, not repeated in the message.
        let text = e.to_string();
        assert!(
            text.contains(&dir.join("missing.toml").display().to_string()),
            "{text}"
        );
        assert!(!text.contains(&io.to_string()), "{text}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn numeric_keys_index_arrays() {
        let cfg = ScenarioConfig::builtin("ground-beacons-3").unwrap();
        let sets = [
            "beacons.1.lat_deg=-28.0".to_string(),
            "filter.q_diag.3=2e-7".to_string(),
        ];
        let out = apply_overrides(cfg, &sets).unwrap();
        assert_eq!(out.filter.q_diag[3], 2e-7);
        let text = out.to_toml_string();
        assert!(text.contains("lat_deg = -28.0"), "{text}");
        let cfg = ScenarioConfig::builtin("ground-beacons-3").unwrap();
        let err = apply_overrides(cfg, &["beacons.3.lat_deg=1".to_string()])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("index 3 is past the array's 3 entries"),
            "{err}"
        );
    }
}
