//! `entrynav fmu`: build the FMI 2.0 and FMI 3.0 co-simulation FMUs (`pack`, also
//! scenario-specific ones and SSP packages). Every packed FMU is read back (its model
//! description, binding and resources) without loading its library (`entrynav-fmu-archive`).
//!
//! The test tools that drive an FMU through our own FMI host — `check`, `fuzz`, `run`,
//! `cross-check` — are `entrynav-dev fmu …` (the developer crate `devtools/`): the host loads
//! libraries with libloading, which this command does not ship. Users check an FMU with the FMI
//! tools (fmpy, fmusim, fmuCheck).

mod pack;

use anyhow::Result;
use clap::{Args, Subcommand};
use pack::{PackArgs, pack};

/// Arguments of `entrynav fmu`.
#[derive(Args)]
pub struct FmuArgs {
    #[command(subcommand)]
    action: FmuAction,
}

#[derive(Subcommand)]
enum FmuAction {
    /// Build MarsEntryNav.fmu, MarsEntryNavFilter.fmu, MarsEntryTruth.fmu, MarsEntryGuidance.fmu
    /// and MarsEntryNavGuided.fmu (or, with --scenario, the combined model specific to one
    /// scenario), each with a stripped library bound to its model.
    Pack(PackArgs),
}

/// Run the command.
pub fn run(args: &FmuArgs) -> Result<()> {
    match &args.action {
        FmuAction::Pack(a) => pack(a),
    }
}
