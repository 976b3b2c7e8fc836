//! The checks a command runs before any work, so a study never fails at its end on something it
//! could have refused at its start: output paths (the study layer's checks, which Python shares)
//! and the warnings for values no Mars entry has (allowed with `allow_implausible`).

use std::path::Path;

/// Warn on standard error about every value of `cfg` no Mars entry has (a speed in km/s, a
/// flight-path angle in radians: `ScenarioConfig::implausible`); validation refuses them unless
/// the scenario sets `allow_implausible = true`, so this speaks only for an allowed one.
pub fn warn_implausible(cfg: &entrynav::scenario::ScenarioConfig) {
    for w in cfg.implausible() {
        eprintln!("warning: {w}");
    }
}

pub use entrynav_studies::output::is_stdout;

/// Refuse, before any run, an output file that cannot be written (the study layer's check, which
/// Python shares).
pub fn check_output_file(path: &Path, flag: &str) -> anyhow::Result<()> {
    Ok(entrynav_studies::output::check_output_file(path, flag)?)
}

/// Refuse, before any run, every output file that is given and cannot be written (`-` is
/// standard output), naming its flag.
pub fn check_output_files(files: &[(Option<&Path>, &str)]) -> anyhow::Result<()> {
    for (path, flag) in files {
        if let Some(p) = path {
            check_output_file(p, flag)?;
        }
    }
    Ok(())
}

/// Refuse, before any run, an output directory that cannot be created or written into.
pub fn check_output_dir(dir: &Path, flag: &str) -> anyhow::Result<()> {
    Ok(entrynav_studies::output::check_output_dir(dir, flag)?)
}
