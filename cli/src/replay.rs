//! `entrynav trade --replay-run K --csv-dir DIR`: run K of a study replayed in full, one CSV per
//! filter (truth, estimate, σ, error, NEES, per-channel innovation and NIS, weights; the rows are
//! the study layer's, `entrynav_studies::trade::replay`), and a line per filter.

use anyhow::{Context, Result};
use entrynav_studies::trade::options::TradeOptions;
use entrynav_studies::trade::replay::replay_trade_run;
use entrynav_studies::trade::setup::TradeSetup;
use std::path::Path;

/// Replay run `run` of the study of `setup` and write `DIR/<scenario>_run<K>_<filter>.csv`.
pub fn write_replay(
    setup: &TradeSetup,
    options: &TradeOptions,
    run: usize,
    dir: &Path,
) -> Result<()> {
    let replayed = replay_trade_run(setup, options, run)?;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for r in &replayed.replays {
        let path = dir.join(format!(
            "{}_run{run}_{}.csv",
            setup.scenario.config.name, r.filter
        ));
        crate::csv_file::write_with_comment(&path, |w| Ok(replayed.write_csv(w, r)?))?;
        let last = r.epochs.last();
        println!(
            "run {run} {}: {} epochs{}; final NEES {}, position error {} m -> {}",
            r.filter,
            r.epochs.len(),
            r.failure
                .as_ref()
                .map(|(t, why)| format!(", failed at t = {t} s: {why}"))
                .unwrap_or_default(),
            last.and_then(|e| e.nees)
                .map(|(v, dof)| format!("{v:.4} ({dof} dof)"))
                .unwrap_or_else(|| "-".into()),
            last.map(|e| format!("{:.2}", e.pos_vel_err.0))
                .unwrap_or_else(|| "-".into()),
            path.display()
        );
    }
    Ok(())
}
