//! A scenario as a study receives it: the validated configuration (overrides applied), the folder
//! its relative file names resolve against, the text its user wrote (a study that writes the
//! scenario back, `tune`, keeps its comments and layout) and the overrides (for provenance).
//! Both front ends make one: the command line from a built-in name or a file and `--set`
//! strings, Python from a `Scenario`'s TOML text and folder.

use crate::error::{StudyError, StudyResult};
use entrynav::scenario::{Scenario, ScenarioConfig, builtin_toml};
use entrynav_loader as load;
use std::path::{Path, PathBuf};

/// A scenario for a study.
#[derive(Debug, Clone)]
pub struct ScenarioInput {
    /// The validated configuration, overrides applied.
    pub config: ScenarioConfig,
    /// The folder its relative file names resolve against.
    pub dir: PathBuf,
    /// The built-in's name or the file's path as given; `None` for a scenario given as text.
    pub name: Option<String>,
    /// The text before the overrides: the built-in's text, the file's, or the given text.
    pub source_text: String,
    /// The `--set PATH=VALUE` overrides, in the order applied.
    pub overrides: Vec<String>,
    /// The truth atmosphere file that replaced the scenario's truth atmosphere, if any.
    pub atmosphere_file: Option<PathBuf>,
}

impl ScenarioInput {
    /// A built-in name, or a TOML file relative to the working directory, with `sets` applied.
    pub fn resolve(name_or_file: &str, sets: &[String]) -> StudyResult<ScenarioInput> {
        let src = load::resolve(name_or_file, load::Base::CurrentDir)?;
        let source_text = match &src.origin {
            load::Origin::Builtin(name) => {
                builtin_toml(name).map(str::to_string).ok_or_else(|| {
                    StudyError::Failed(format!("no text for built-in scenario {name}"))
                })?
            }
            load::Origin::File(path) => load::read_text(path)
                .map_err(|e| StudyError::Refused(format!("cannot read {}: {e}", path.display())))?,
        };
        let (config, dir) = src.into_parts();
        Ok(ScenarioInput {
            config: load::apply_overrides(config, sets)?,
            dir,
            name: Some(name_or_file.to_string()),
            source_text,
            overrides: sets.to_vec(),
            atmosphere_file: None,
        })
    }

    /// A scenario given as TOML text whose relative file names resolve against `dir`, with
    /// `sets` applied.
    pub fn from_toml(text: &str, dir: &Path, sets: &[String]) -> StudyResult<ScenarioInput> {
        let config = ScenarioConfig::from_toml_str(text, "scenario")?;
        Ok(ScenarioInput {
            config: load::apply_overrides(config, sets)?,
            dir: dir.to_path_buf(),
            name: None,
            source_text: text.to_string(),
            overrides: sets.to_vec(),
            atmosphere_file: None,
        })
    }

    /// The runnable scenario (its referenced files read relative to [`ScenarioInput::dir`]).
    pub fn build(&self) -> StudyResult<Scenario> {
        Ok(load::build(self.config.clone(), &self.dir)?)
    }

    /// What a provenance block says of the scenario's name: as given, else its own `name`.
    pub fn label(&self) -> &str {
        self.name.as_deref().unwrap_or(&self.config.name)
    }
}
