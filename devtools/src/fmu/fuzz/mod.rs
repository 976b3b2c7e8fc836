//! `entrynav-dev fmu fuzz`: random FMI call sequences through our host against a model of what
//! the FMU must answer. One fuzzer serves both FMI versions: it is generic over [`Version`]
//! (in `fuzzer`; FMI 2.0 in [`fmi2`], FMI 3.0 in [`fmi3`]), whose instances implement the host's shared
//! interface (`entrynav_fmi_host::FmiInstance`), and the model ([`model`]: the state machine, the
//! parameters and inputs given, the expected answers) is the same for both.
//!
//! Every call is checked: an illegal call or a refused request must be answered with an error, a
//! logged reason and the instance as it was, a legal call must succeed, a failing one must put
//! the instance in the error state; every log message must be non-empty, in the version's terms
//! and disclose no host file. The values cover huge and tiny intervals and step sizes, every
//! size-like argument below and above its bound (value-reference counts, string lengths,
//! category counts, serialized-state sizes, numbers of FMU states, measurement times), unknown
//! and mistyped references, null arrays, foreign and corrupted FMU states, calls on freed and
//! null instances and instantiations the FMU must refuse; FMI 3.0 adds `nValues` against the
//! arrays, the arrays against the scalars, the flags of fmi3DoStep and every function of a
//! capability the FMU lacks. CI runs 100,000 calls per FMU; `--calls 5000000` is the long mode.

mod answers;
mod bounds;
mod fmi2;
mod fmi3;
mod fuzzer;
mod model;
mod ops;
mod scenarios;
mod sequence;
mod setters;
mod state;
mod stats;
mod vals;
mod values;
mod variables;

#[cfg(test)]
mod tests;

use anyhow::{Result, ensure};
use clap::Args;
use entrynav_fmi_host::{Api3, file_uri, unpack};
use entrynav_fmu::vars::Model;
use fmi2::Fmi2;
use fmi3::Fmi3;
use fuzzer::{Fuzzer, Version};
use rand::RngExt;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// Arguments of `entrynav-dev fmu fuzz`.
#[derive(Args)]
pub(super) struct FuzzArgs {
    /// The .fmu file.
    file: PathBuf,
    /// FMI calls in all (fmi2, or fmi3 for an FMI 3.0 FMU; CI: 100,000 per FMU; the long mode:
    /// 5,000,000).
    #[arg(long, default_value_t = 100_000)]
    calls: usize,
    /// Longest call sequence on one instance.
    #[arg(long, default_value_t = 80)]
    max_sequence: usize,
    /// Seed of the random sequences.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

/// Run sequences of at most `max_sequence` calls until `calls` calls are made, then the calls
/// on a null instance; returns the report line. Fails at the first answer the model does not
/// predict.
fn run<V: Version>(f: &mut Fuzzer<V>, calls: usize, max_sequence: usize) -> Result<String> {
    let clock = Instant::now();
    while f.stats.calls < calls {
        let len = f.rng.random_range(1..=max_sequence.max(1));
        f.sequence(len)?;
    }
    f.null_instance()?;
    let report = V::report(f, clock.elapsed().as_secs_f64());
    ensure!(f.stats.statuses[4] == 0, "a Fatal status: {report}");
    Ok(report)
}

pub(super) fn fuzz(a: &FuzzArgs) -> Result<()> {
    super::bounds::input(&a.file, "FILE")?;
    super::bounds::count("calls", a.calls, super::bounds::MAX_CALLS)?;
    super::bounds::count("max_sequence", a.max_sequence, super::bounds::MAX_SEQUENCE)?;
    let u = unpack(&a.file)?;
    ensure!(
        u.model != Model::Guidance,
        "fmu fuzz has no model of MarsEntryGuidance's statuses yet (its refusals depend on the estimate it is given); fuzz MarsEntryNav, MarsEntryNavFilter or MarsEntryTruth"
    );
    let (spec, bound) = (Arc::clone(&u.spec), u.binding.is_some());
    let resources = u.dir.join("resources");
    let report = match u.fmi_version {
        3 => {
            let v = Fmi3::load(Api3::load(&u.library)?, spec.guid(), &resources)?;
            run(
                &mut Fuzzer::new(v, spec, bound, a.seed)?,
                a.calls,
                a.max_sequence,
            )?
        }
        _ => {
            let v = Fmi2 {
                api: Arc::clone(&u.api),
                guid: spec.guid().to_string(),
                uri: file_uri(&resources),
            };
            run(
                &mut Fuzzer::new(v, spec, bound, a.seed)?,
                a.calls,
                a.max_sequence,
            )?
        }
    };
    println!("{report}");
    Ok(())
}
