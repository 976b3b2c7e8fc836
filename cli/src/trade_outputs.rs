//! The files of `entrynav trade`: the output paths checked before the first run, a summary or
//! shard file written (or sent to standard output), the `resume` block read back, and the CSV
//! series of `--csv-dir` (their rows are the study layer's, `entrynav_studies::trade::csv_series`).

use crate::preflight::{check_output_dir, check_output_file, is_stdout};
use anyhow::{Context, Result};
use entrynav::sim::{ShardResult, TradeReport};
use entrynav_studies::trade::csv_series::series_files;
use entrynav_studies::trade::resume::read_resume;
use std::io::Write;
use std::path::Path;

/// Check every output path of a study before its first run (exit code 2 naming the path).
pub fn check_outputs(
    json: Option<&Path>,
    csv_dir: Option<&Path>,
    plots: Option<&Path>,
) -> Result<()> {
    if let Some(p) = json {
        check_output_file(p, "--json")?;
    }
    if let Some(d) = csv_dir {
        check_output_dir(d, "--csv-dir")?;
    }
    if let Some(d) = plots {
        check_output_dir(d, "--plots")?;
    }
    Ok(())
}

/// The block sums stored in the partial summary `path` (`--resume`), checked against their
/// checksum.
pub fn read_resume_file(path: &Path) -> Result<ShardResult> {
    let text = entrynav_loader::read_text(path)
        .with_context(|| format!("--resume {}: cannot read", path.display()))?;
    Ok(read_resume(&text).map_err(|e| e.context(format!("--resume {}", path.display())))?)
}

/// Write `text` to `path` (`-`: standard output).
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_file(path, |w| Ok(w.write_all(text.as_bytes())?))
}

/// Write `path` (`-`: standard output), creating its directory.
pub fn write_file(path: &Path, body: impl FnOnce(&mut dyn Write) -> Result<()>) -> Result<()> {
    if is_stdout(path) {
        let mut w = std::io::BufWriter::new(std::io::stdout().lock());
        body(&mut w).context("writing standard output")?;
        w.flush()?;
        return Ok(());
    }
    let mut w = entrynav_studies::output::atomic_file::AtomicFile::create(path)?;
    body(&mut w)
        .and_then(|()| Ok(w.flush()?))
        .map_err(|e| crate::exit_code::Runtime(format!("writing {}: {e:#}", path.display())))?;
    Ok(w.commit()?)
}

/// Write the `--csv-dir` files of `report`: `{scenario}_pcrlb.csv` (when the bound is
/// available), `{scenario}_final_errors.csv` and one `{scenario}_{filter}.csv` per filter.
pub fn write_csv_dir(dir: &Path, report: &TradeReport) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for file in series_files(report) {
        let path = dir.join(format!("{}_{}.csv", report.scenario, file.suffix()));
        crate::csv_file::write(&path, |w| Ok(file.write(w, report)?))?;
    }
    Ok(())
}

/// The outputs of a study: what was written (its note) and what failed.
#[derive(Default)]
pub(crate) struct Outputs {
    notes: Vec<String>,
    failures: Vec<anyhow::Error>,
}

impl Outputs {
    pub(crate) fn record(&mut self, done: Result<Option<String>>) {
        match done {
            Ok(note) => self.notes.extend(note),
            Err(e) => self.failures.push(e),
        }
    }

    /// Print the notes (to standard error when standard output carries the JSON); fail with
    /// every failed output named.
    pub(crate) fn finish(self, to_stdout: bool) -> Result<()> {
        for n in &self.notes {
            if to_stdout {
                eprintln!("{n}");
            } else {
                println!("{n}");
            }
        }
        let mut failures = self.failures;
        match failures.len() {
            0 => Ok(()),
            // The work is done: a failure to write it is a runtime failure (exit code 1).
            1 if crate::exit_code::code(&failures[0]) == 1 => Err(failures.remove(0)),
            _ => {
                let all: Vec<String> = failures.iter().map(|e| format!("{e:#}")).collect();
                Err(crate::exit_code::Runtime(all.join("; also: ")).into())
            }
        }
    }
}

/// The command line as given, for the provenance block.
pub(crate) fn command_line() -> Vec<String> {
    std::env::args().collect()
}
