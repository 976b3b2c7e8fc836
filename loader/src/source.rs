//! Where a scenario comes from ([`Origin`]: a built-in or a file), where relative paths start
//! ([`Base`]), and the resolved, unbuilt scenario ([`ScenarioSource`]).

use entrynav::scenario::ScenarioConfig;
use std::path::Path;
use std::path::PathBuf;

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
