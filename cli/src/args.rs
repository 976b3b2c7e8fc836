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

/// `cmd` with every option that takes a value accepting a negative number after a space
/// (clap otherwise reads `-34` as an unknown flag); in every subcommand.
pub fn negative_numbers_everywhere(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    })
    .mut_subcommands(negative_numbers_everywhere)
}

/// `--set PATH=VALUE`: the overrides of a scenario field, the same in every command.
#[derive(Args, Clone, Debug, Default)]
pub struct SetArgs {
    /// Override a scenario field: PATH=VALUE in TOML syntax (repeatable), e.g.
    /// `--set truth.density_bias=0.095`.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub sets: Vec<String>,
}

/// `--scenario NAME|FILE` and its `--set PATH=VALUE` overrides.
#[derive(Args, Clone, Debug)]
pub struct ScenarioArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    pub scenario: String,
    /// The overrides.
    #[command(flatten)]
    pub overrides: SetArgs,
}

/// `--threads N`: the worker pool of a study (its results never depend on it).
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct ThreadsArg {
    /// Worker threads (default: all cores).
    #[arg(long, allow_hyphen_values = true, value_parser = threads)]
    pub threads: Option<usize>,
}

/// A whole number as typed (a negative or huge one included), or the message of the bound it
/// would be checked against (`check` with an out-of-range value), so a non-number gets the same
/// range as any other bad value.
fn whole<T>(
    option: &str,
    text: &str,
    check: impl Fn(i128) -> Result<T, options::OptionError>,
) -> Result<i128, String> {
    text.trim().parse::<i128>().map_err(|_| {
        let allowed = check(i128::MIN)
            .err()
            .map(|e| e.allowed)
            .unwrap_or_default();
        format!("{option} = '{text}' is not a whole number: must be {allowed}")
    })
}

/// `--threads N`: 1 to `MAX_THREADS`.
pub fn threads(text: &str) -> Result<usize, String> {
    let n = whole("threads", text, |n| options::threads(Some(n)))?;
    options::threads(Some(n))
        .map(|t| t.unwrap_or(1))
        .map_err(|e| e.to_string())
}

/// A seed: 0 to 2^64 - 1.
pub fn seed(text: &str) -> Result<u64, String> {
    let n = whole("seed", text, |n| options::seed("seed", n))?;
    options::seed("seed", n).map_err(|e| e.to_string())
}

/// Run-count flags, each naming itself: 1 to `MAX_RUNS`.
macro_rules! run_count {
    ($($name:ident),*) => {$(
        #[doc = concat!("`--", stringify!($name), "`: a run count, 1 to `MAX_RUNS`.")]
        pub fn $name(text: &str) -> Result<usize, String> {
            let check = |n| options::runs(stringify!($name), n);
            let n = whole(stringify!($name), text, check)?;
            check(n).map_err(|e| e.to_string())
        }
    )*};
}

run_count!(runs, validation_runs, check_runs, evaluate);
