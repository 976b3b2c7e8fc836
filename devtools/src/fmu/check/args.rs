//! [`CheckArgs`]: the options of `entrynav-dev fmu check`.

use clap::Args;
use std::path::PathBuf;

/// Arguments of `entrynav-dev fmu check`.
#[derive(Args)]
pub(crate) struct CheckArgs {
    /// The .fmu file.
    pub(super) file: PathBuf,
    /// Scenario parameter (built-in name or a file in the FMU's resources). Default:
    /// four-beacon-fusion, or msl-guided.toml for MarsEntryGuidance (whose inputs come from the
    /// in-process guided loop on it, the EKF in the loop, run 0 of --seed) and for
    /// MarsEntryNavGuided.
    #[arg(long)]
    pub(super) scenario: Option<String>,
    /// Filter parameter (default: the FMU's: dcifaif for the generic FMUs, ekf for
    /// MarsEntryNavGuided).
    #[arg(long)]
    pub(super) filter: Option<String>,
    /// Seed parameter.
    #[arg(long, default_value_t = 1)]
    pub(super) seed: i32,
    /// Nominal truth instead of a dispersed one.
    #[arg(long)]
    pub(super) nominal: bool,
    #[arg(
        long,
        help = "Communication step [s] (default: the fastest sensor period of the scenario)"
    )]
    pub(super) step: Option<f64>,
    /// Also time doStep through the host against the in-process engine.
    #[arg(long)]
    pub(super) bench: bool,
    /// Repetitions of the benchmark.
    #[arg(long, default_value_t = 15)]
    pub(super) reps: usize,
}
