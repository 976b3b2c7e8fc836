//! [`LoadError`]: why a scenario could not be loaded.

use entrynav::scenario::ScenarioError;
use std::path::PathBuf;
use thiserror::Error;

/// Why a scenario could not be loaded.
#[derive(Debug, Error)]
pub enum LoadError {
    /// Neither a built-in nor a readable file.
    #[error(
        "scenario '{name}' is neither a built-in ({builtins}) nor a readable file ({}){suggestion}",
        path.display()
    )]
    NotFound {
        /// What was asked for.
        name: String,
        /// `; did you mean 'msl-airdata'?` for a near miss of a built-in's name, else empty.
        suggestion: String,
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
        "scenario '{name}' is not a built-in ({builtins}) and there is no folder to find it in{suggestion}"
    )]
    NoFolder {
        /// What was asked for.
        name: String,
        /// `; did you mean 'msl-airdata'?` for a near miss of a built-in's name, else empty.
        suggestion: String,
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
