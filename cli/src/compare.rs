//! `entrynav trade compare A.json B.json`: per filter present in both trade summaries, the
//! difference B − A of every RMSE, of the ANEES and of the bad-run fraction, with a 95 % Monte
//! Carlo interval (the study: `entrynav_studies::compare`). This file reads the inputs, prints
//! the table (`compare_table.rs`) and writes the JSON.

use crate::preflight::{check_output_file, is_stdout};
use anyhow::{Context, Result};
use entrynav_studies::compare::input::SummaryIn;
use entrynav_studies::compare::paired::FinalErrors;
use entrynav_studies::compare::study::compare_summaries;
use std::path::{Path, PathBuf};

/// Arguments of `entrynav trade compare`.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// Trade summary A (written by `trade --json`), the reference.
    pub a: PathBuf,
    /// Trade summary B; differences are B − A.
    pub b: PathBuf,
    /// Write the comparison as JSON (`-`: to standard output, and no table).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Accepted for older scripts: different scenarios (a moved beacon, a tuned file) are
    /// compared, and what differs between them is printed.
    #[arg(long, hide = true)]
    pub allow_different_scenarios: bool,
    /// The per-run final errors of A and B (`{scenario}_final_errors.csv` from the same
    /// studies' `--csv-dir`): adds `rmse_final_paired` rows, paired by run index, with sample
    /// variances and covariance instead of the Gaussian approximation.
    #[arg(long, num_args = 2, value_names = ["A.csv", "B.csv"])]
    pub final_errors: Vec<PathBuf>,
}

/// Run the command.
pub fn run(args: &CompareArgs) -> Result<()> {
    if let Some(p) = &args.json {
        check_output_file(p, "--json")?;
    }
    let a = read(&args.a, "A")?;
    let b = read(&args.b, "B")?;
    let finals = match args.final_errors.as_slice() {
        [fa, fb] => Some([read_final_errors(fa)?, read_final_errors(fb)?]),
        _ => None,
    };
    let label = |p: &Path| p.display().to_string();
    let labels = args
        .final_errors
        .iter()
        .map(|p| label(p))
        .collect::<Vec<_>>();
    let paired = finals
        .as_ref()
        .map(|[fa, fb]| [(labels[0].as_str(), fa), (labels[1].as_str(), fb)]);
    let (la, lb) = (label(&args.a), label(&args.b));
    let cmp = compare_summaries((&la, &a), (&lb, &b), paired);
    let to_stdout = args.json.as_deref().is_some_and(is_stdout);
    if !to_stdout {
        crate::compare_table::print(&cmp);
    }
    if let Some(p) = &args.json {
        let text = serde_json::to_string_pretty(&cmp)? + "\n";
        if to_stdout {
            print!("{text}");
        } else {
            entrynav_studies::output::atomic_file::write(p, text)?;
            println!("wrote {}", p.display());
        }
    }
    Ok(())
}

/// Read the trade summary `path` (argument `name`, A or B); anything else is a usage error (exit
/// code 2) naming it.
fn read(path: &Path, name: &str) -> Result<SummaryIn> {
    let text = entrynav_studies::input::read_text(path, &format!("summary {name}"))?;
    Ok(SummaryIn::parse(&text).map_err(|e| e.context(path.display()))?)
}

/// Read the final-errors CSV `path` (`--final-errors`).
fn read_final_errors(path: &Path) -> Result<FinalErrors> {
    let text = entrynav_loader::read_text(path)
        .with_context(|| format!("--final-errors {}: cannot read", path.display()))?;
    let flag = format!("--final-errors {}", path.display());
    Ok(FinalErrors::parse(&text).map_err(|e| e.context(flag))?)
}
