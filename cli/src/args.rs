//! The argument groups every command shares (scenario and `--set`), and the parsers of numeric
//! flags, which hand the value to the study layer's bounds (`entrynav_studies::options`) so that
//! the command line and Python refuse the same value with the same message.

use clap::Args;
use entrynav_studies::options;

/// What `--quiet` means in every command that has it: standard output is the same with or
/// without it; standard error loses the progress and keeps warnings, notes and errors.
pub const QUIET_HELP: &str = "Print no progress (bars, per-run, per-epoch and per-cell logs); results \
(tables, `wrote FILE` lines) still print on standard output, unchanged, and warnings, notes and \
errors on standard error";

/// `--scenario NAME|FILE` and its `--set PATH=VALUE` overrides.
#[derive(Args, Clone, Debug)]
pub struct ScenarioArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    pub scenario: String,
    /// Override a scenario field: PATH=VALUE in TOML syntax (repeatable), e.g.
    /// `--set truth.density_bias=0.095`.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub sets: Vec<String>,
}

/// A whole number as typed (a negative or huge one included), or a message naming `option`.
fn whole(option: &str, text: &str) -> Result<i128, String> {
    text.trim()
        .parse::<i128>()
        .map_err(|_| format!("{option} = '{text}' is not a whole number"))
}

/// `--threads N`: 1 to `MAX_THREADS`.
pub fn threads(text: &str) -> Result<usize, String> {
    let n = whole("threads", text)?;
    options::threads(Some(n))
        .map(|t| t.unwrap_or(1))
        .map_err(|e| e.to_string())
}

/// A seed: 0 to 2^64 - 1.
pub fn seed(text: &str) -> Result<u64, String> {
    options::seed("seed", whole("seed", text)?).map_err(|e| e.to_string())
}

/// Run-count flags, each naming itself: 1 to `MAX_RUNS`.
macro_rules! run_count {
    ($($name:ident),*) => {$(
        #[doc = concat!("`--", stringify!($name), "`: a run count, 1 to `MAX_RUNS`.")]
        pub fn $name(text: &str) -> Result<usize, String> {
            options::runs(stringify!($name), whole(stringify!($name), text)?)
                .map_err(|e| e.to_string())
        }
    )*};
}

run_count!(runs, validation_runs, check_runs);
