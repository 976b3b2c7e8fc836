//! `entrynav scenarios`: one line per built-in ([`entrynav_loader::summary`]).

use anyhow::Result;
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use entrynav_loader::summary::summary;

/// Print the built-ins.
pub fn list() -> Result<()> {
    for name in BUILTIN_NAMES {
        let cfg = ScenarioConfig::builtin(name)?;
        let sc = Scenario::build(cfg, &entrynav::files::no_files)?;
        println!("{name:<26} {}", summary(&sc));
    }
    Ok(())
}
