//! `entrynav fmu pack`: the flags of the study layer's FMU packer (`entrynav_studies::fmu_pack`)
//! and the line it prints per packed FMU and SSP package.

use anyhow::Result;
use clap::Args;
use entrynav_studies::ScenarioInput;
use entrynav_studies::fmu_pack::{PackOptions, Search, pack_fmus};
use std::path::PathBuf;

/// Arguments of `entrynav fmu pack`.
#[derive(Args)]
pub(super) struct PackArgs {
    /// Output folder.
    #[arg(long, default_value = "target/fmu")]
    out: PathBuf,
    /// The FMU shared library (build it with `cargo build --release -p entrynav-fmu`). Default:
    /// $ENTRYNAV_FMU_LIB, else libentrynav_fmu.so next to this executable, in ../lib, or in
    /// the target folder it was built in.
    #[arg(long, visible_alias = "library")]
    lib: Option<PathBuf>,
    /// Pack the combined model specific to this scenario (a built-in name or a TOML file) instead
    /// of the five generic FMUs.
    #[arg(long)]
    scenario: Option<String>,
    /// Default filter of the scenario-specific FMU (default: dcifaif if it fits the scenario,
    /// else the first filter that does).
    #[arg(long, requires = "scenario")]
    filter: Option<String>,
    /// Also write SSP 1.0 packages of the generic FMUs: `MarsEntrySplit.ssp` (truth -> filter,
    /// the filter one step late), `MarsEntryNav.ssp` (the combined FMU) and `MarsEntryGuided.ssp`
    /// (truth -> filter -> guidance -> truth bank on msl-guided.toml), each with its parameters
    /// in an .ssv. FMI 2.0 only (refused with `--fmi 3`): the packages are SSP 1.0, whose
    /// connector types (Real, Integer, Boolean, String, Enumeration, Binary) describe FMI 1.0/2.0
    /// variables only; FMI 3.0 components (Float64, Int64, UInt64, arrays, structural parameters)
    /// need SSP 2.0, which OMSimulator 3 does not read.
    #[arg(long, conflicts_with = "scenario")]
    ssp: bool,
    /// FMI version of the packed FMUs: 2 (FMI 2.0, `<id>.fmu`) or 3 (FMI 3.0, `<id>-fmi3.fmu`:
    /// the same variables and value references, plus `time`; with `--arrays` also the arrays).
    /// The library is the same and exports both interfaces.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
    fmi: u8,
    /// FMI 3.0 only: also declare the arrays `est_x`, `est_sigma` and `est_covariance`, sized by
    /// the structural parameter `n_state_slots`. Off by default because OMSimulator 3.0 cannot
    /// load an FMU with a structural parameter and reads arrays as scalars
    /// (OpenModelica/OMSimulator#1310, #1418); fmpy and fmusim read them.
    #[arg(long)]
    arrays: bool,
    /// Ship the library with its symbols and debug information (by default it is stripped with
    /// binutils' `strip --strip-all`).
    #[arg(long)]
    keep_symbols: bool,
}

/// Run the command.
pub(super) fn pack(a: &PackArgs) -> Result<()> {
    let options = PackOptions {
        filter: a.filter.clone(),
        ssp: a.ssp,
        fmi: a.fmi,
        arrays: a.arrays,
        keep_symbols: a.keep_symbols,
    };
    options.validate()?;
    crate::preflight::check_output_dir(&a.out, "--out")?;
    let lib = Search::of_process(a.lib.as_deref()).find()?;
    let input = a
        .scenario
        .as_deref()
        .map(|s| ScenarioInput::resolve(s, &[]))
        .transpose()?;
    let packed = pack_fmus(&lib, &a.out, input.as_ref(), &options)?;
    for f in &packed.fmus {
        println!(
            "{}  FMI {}.0  {}  {}  library {:.2} MiB{}",
            f.path.display(),
            f.fmi,
            f.identifier,
            f.guid,
            f.library_bytes as f64 / (1024.0 * 1024.0),
            if a.keep_symbols {
                " (symbols kept)"
            } else {
                " (stripped)"
            }
        );
    }
    for path in &packed.ssps {
        println!("{}  SSP 1.0 system", path.display());
    }
    Ok(())
}
