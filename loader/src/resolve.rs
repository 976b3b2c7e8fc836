//! [`resolve`]: a built-in scenario name, or a TOML file (absolute, or relative to a base folder).

use crate::error::LoadError;
use crate::read::read_text;
use crate::source::Base;
use crate::source::Origin;
use crate::source::ScenarioSource;
use entrynav::scenario::BUILTIN_NAMES;
use entrynav::scenario::ScenarioConfig;
use std::path::Path;
use std::path::PathBuf;

pub(super) fn builtins() -> String {
    BUILTIN_NAMES.join(", ")
}

/// `; did you mean 'NAME'?` when `name` is a near miss of a built-in's name (at most a quarter
/// of its letters, and at least 2, edited: `msl-airdta`, `ground-beacon-3`), else empty.
pub fn suggestion(name: &str) -> String {
    let lower = name.to_lowercase();
    BUILTIN_NAMES
        .iter()
        .map(|b| (strsim::damerau_levenshtein(&lower, b), *b))
        .filter(|(d, b)| *d > 0 || lower != *b)
        .min()
        .filter(|(d, b)| *d <= (b.len() / 4).max(2))
        .map_or_else(String::new, |(_, b)| format!("; did you mean '{b}'?"))
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
                suggestion: suggestion(name),
                name: name.to_string(),
                builtins: builtins(),
            });
        }
    };
    let text = read_text(&path).map_err(|source| LoadError::NotFound {
        suggestion: if path.exists() {
            String::new()
        } else {
            suggestion(name)
        },
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
