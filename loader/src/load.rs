//! Building a resolved scenario: the loader of the files it refers to, read relative to the
//! scenario file's folder ([`file_loader`]), [`build`], and [`load`] (resolve, override, build).

use crate::error::LoadError;
use crate::overrides::apply_overrides;
use crate::read::read_text;
use crate::resolve::resolve;
use crate::source::Base;
use entrynav::files::FileError;
use entrynav::scenario::Scenario;
use entrynav::scenario::ScenarioConfig;
use std::path::Path;
use std::path::PathBuf;

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
