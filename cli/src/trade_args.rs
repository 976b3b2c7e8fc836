//! The arguments of `entrynav trade` and its subcommands `merge` and `compare`, and the study
//! options they give.

use clap::{Args, ValueEnum};
use entrynav_studies::scenario::TruthAtmosphere;
use entrynav_studies::trade::options::{self as trade_options, TradeOptions};
use std::path::PathBuf;

/// Arguments of `entrynav trade`.
#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct TradeArgs {
    /// Merge shard files or compare summaries instead of running.
    #[command(subcommand)]
    pub action: Option<TradeAction>,
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long, required_unless_present = "grid")]
    pub scenario: Option<String>,
    /// The `--set` overrides.
    #[command(flatten)]
    pub overrides: crate::args::SetArgs,
    /// Comma-separated filters: ekf, ukf, ci, dcifaif, mmae, mmae-moe, ukf-cm, ukf-ac, uskf-nn.
    #[arg(long, visible_alias = "filter", default_value = "ekf")]
    pub filters: String,
    /// Monte Carlo runs (default: the scenario's monte_carlo.runs).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::runs)]
    pub runs: Option<usize>,
    /// Master seed; the same seed gives the same statistics on any thread count.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = crate::args::seed)]
    pub seed: u64,
    /// The worker pool.
    #[command(flatten)]
    pub workers: crate::args::ThreadsArg,
    /// Write the summary as JSON (`-`: to standard output, and no tables). Every output path is
    /// checked before the first run.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write per-filter time series (RMSE, mean σ, NEES, …) as CSV files into this directory.
    #[arg(long)]
    pub csv_dir: Option<PathBuf>,
    /// Write SVG plots (RMSE vs time, errors with 3σ envelopes, NEES) into this directory.
    #[arg(long)]
    pub plots: Option<PathBuf>,
    /// Write one self-contained HTML report (inline SVG and CSS, nothing from the network):
    /// consistency verdicts, RMSE and PCRLB, errors with ±3σ, NEES/NIS, weights, dispersion,
    /// provenance. With --grid, the grid's report. Checked before the first run.
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<PathBuf>,
    #[arg(long, help = crate::args::QUIET_HELP)]
    pub quiet: bool,
    /// List every failed or diverged run (run, time, reason) under its filter's table; without
    /// it the tables give the counts only (the runs are in --json's `failures` either way).
    #[arg(long)]
    pub list_runs: bool,
    /// The truth atmosphere file and how to read it.
    #[command(flatten)]
    pub atmosphere: crate::atmosphere_file::AtmosphereFileArgs,
    /// Fly every run in the unperturbed truth mean atmosphere (no per-run perturbation).
    #[arg(long)]
    pub no_perturbation: bool,
    /// Run a grid of scenarios × variations × filters (see `docs/tutorial.md`); the report
    /// (Markdown, CSV, JSON, SVG plots) goes to --out-dir.
    #[arg(long, value_name = "FILE.toml", conflicts_with_all = ["shard"])]
    pub grid: Option<PathBuf>,
    /// Output directory of a --grid report.
    #[arg(long, default_value = "out/grid")]
    pub out_dir: PathBuf,
    /// Run only shard I of N (contiguous blocks of runs) and write the shard file to --json;
    /// `entrynav trade merge` combines the shards into exactly the single-process result.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Replay run K of this study (same scenario, --set overrides, seed and filters) and write
    /// its full series per filter to --csv-dir: truth, estimate, σ, error, NEES, innovation and
    /// NIS per channel, weights. Use it on a run listed under `failures`.
    #[arg(long, value_name = "K", requires = "csv_dir", conflicts_with_all = ["shard", "grid"])]
    pub replay_run: Option<usize>,
    /// Continue the interrupted study whose partial summary (`complete: false`) is FILE: give
    /// the same scenario, overrides, filters, runs and seed; the result is exactly that of an
    /// uninterrupted run.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["shard", "grid", "replay_run"])]
    pub resume: Option<PathBuf>,
    /// Write the study's resumable partial summary to --json before the first run and then
    /// every S seconds (default 60; 0: never), atomically, so a study killed outright (SIGKILL,
    /// power loss) loses at most S seconds of runs: `--resume FILE` continues it. Needs --json
    /// FILE.
    #[arg(long, value_name = "S", allow_negative_numbers = true, value_parser = checkpoint_every, conflicts_with_all = ["shard", "grid", "replay_run"])]
    pub checkpoint_every: Option<f64>,
    /// Skip the posterior Cramér–Rao lower bound (on by default: the `pcrlb` block of the
    /// summary, each filter's RMSE/PCRLB efficiency, the dashed PCRLB curve in the RMSE plots;
    /// it costs about one EKF's worth of work per run).
    #[arg(long)]
    pub no_pcrlb: bool,
    /// How the statistics are computed: mc (Monte Carlo of --runs runs), lincov (LinCov of each
    /// filter along the nominal trajectory, one pass; ekf, ukf as its EKF equivalent, ci and
    /// dcifaif), or both (the Monte Carlo with LinCov / MC for every headline figure and a warning
    /// where they differ beyond the Monte Carlo's 95 % interval).
    #[arg(long, value_enum, default_value_t = Method::Mc)]
    pub method: Method,
}

/// How `trade` computes its statistics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Default)]
pub enum Method {
    /// Monte Carlo of `--runs` dispersed runs.
    #[default]
    Mc,
    /// LinCov of each filter along the nominal trajectory (one pass, no runs).
    Lincov,
    /// Both, with LinCov / Monte Carlo for every headline figure.
    Both,
}

/// `--checkpoint-every S`: 0 (off) or within the study's bounds.
fn checkpoint_every(text: &str) -> Result<f64, String> {
    let s: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("checkpoint_every = '{text}' is not a number"))?;
    trade_options::check_checkpoint_every(s).map_err(|e| e.to_string())
}

impl TradeArgs {
    /// The study's options.
    pub fn options(&self) -> TradeOptions {
        TradeOptions {
            filters: self.filters.clone(),
            runs: self.runs,
            seed: self.seed,
            threads: self.workers.threads,
            pcrlb: !self.no_pcrlb,
            method: match self.method {
                Method::Mc => trade_options::Method::Mc,
                Method::Lincov => trade_options::Method::Lincov,
                Method::Both => trade_options::Method::Both,
            },
            checkpoint_every: self.checkpoint_every,
        }
    }

    /// The truth atmosphere file and how to read it.
    pub fn truth_atmosphere(&self) -> TruthAtmosphere {
        self.atmosphere.to_study()
    }
}

/// `entrynav trade merge`, `entrynav trade compare`.
#[derive(clap::Subcommand)]
pub enum TradeAction {
    /// Compare two trade summaries (`trade --json`): per filter in both, B − A of every RMSE and
    /// ANEES with a 95 % Monte Carlo interval; of two different scenarios it lists what differs.
    Compare(crate::compare::CompareArgs),
    /// Combine shard files written by `trade --shard I/N --json FILE` into the study's report.
    Merge {
        /// Shard files (all N shards of one study).
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        /// Write the merged summary as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write per-filter time series as CSV into this directory.
        #[arg(long)]
        csv_dir: Option<PathBuf>,
        /// Write SVG plots into this directory.
        #[arg(long)]
        plots: Option<PathBuf>,
        /// Accepted as `trade` accepts it (a merge shows no progress to silence).
        #[arg(long, help = crate::args::QUIET_HELP)]
        quiet: bool,
        /// List every failed or diverged run under its filter's table, as `trade --list-runs`.
        #[arg(long)]
        list_runs: bool,
    },
}
