//! The files of `entrynav trade`: the JSON summary (and the `resume` block read back from it),
//! and the CSV series of `--csv-dir` (per filter, the final errors per run, the PCRLB).

use crate::csv_file::{self, FileWriter, opt};
use crate::exit::{check_output_dir, check_output_file, is_stdout};
use crate::provenance::{Provenance, Summary, Timing};
use anyhow::{Context, Result};
use entrynav::sim::guided::delivery_shard::DeliveryShard;
use entrynav::sim::{FilterReport, PcrlbReport, ShardResult, TradeReport};
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

/// Write a trade summary: provenance, the statistics, then the wall-clock `timing`.
pub fn write_summary(
    path: &Path,
    provenance: &Provenance,
    report: &TradeReport,
    resume: Option<&ShardResult>,
    wall_s: f64,
) -> Result<()> {
    write_summary_with(path, provenance, report, resume, wall_s, Extras::default())
}

/// The optional blocks of a study's summary.
#[derive(Default, Clone, Copy)]
pub struct Extras<'a> {
    /// `trade --method both`: LinCov beside the Monte Carlo.
    pub lincov: Option<&'a serde_json::Value>,
    /// A scenario with `[guidance]`: delivery at deployment.
    pub delivery: Option<&'a entrynav::sim::guided::delivery::DeliveryReport>,
}

/// [`write_summary`] with the optional blocks (`lincov`, `delivery`).
pub fn write_summary_with(
    path: &Path,
    provenance: &Provenance,
    report: &TradeReport,
    resume: Option<&ShardResult>,
    wall_s: f64,
    extras: Extras<'_>,
) -> Result<()> {
    let summary = Summary {
        provenance,
        report,
        resume,
        resume_checksum: resume.map(resume_checksum),
        lincov: extras.lincov,
        delivery: extras.delivery,
        timing: Timing::of(report, wall_s),
    };
    write_file(path, |w| {
        serde_json::to_writer_pretty(&mut *w, &summary)?;
        writeln!(w)?;
        Ok(())
    })
}

/// The block sums stored in the partial summary `path` (`--resume`), refused unless they match
/// the `resume_checksum` written beside them (an edited or corrupt block would otherwise move the
/// resumed statistics silently).
pub fn read_resume(path: &Path) -> Result<ShardResult> {
    let usage = |m: String| crate::exit::Usage(format!("--resume {}: {m}", path.display()));
    let text = entrynav_loader::read_text(path)
        .with_context(|| format!("--resume {}: cannot read", path.display()))?;
    let mut v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| usage(format!("not JSON: {e}")))?;
    let block = v
        .get_mut("resume")
        .map(serde_json::Value::take)
        .ok_or_else(|| {
            usage("no `resume` block: not the summary of an interrupted trade".into())
        })?;
    let stored = v
        .get("resume_checksum")
        .and_then(serde_json::Value::as_str)
        .map(str::to_owned);
    let block: ShardResult =
        serde_json::from_value(block).map_err(|e| usage(format!("corrupt `resume` block: {e}")))?;
    let Some(stored) = stored else {
        return Err(usage(
            "the `resume` block has no `resume_checksum` (written by an older entrynav, or \
             edited); run the study again"
                .into(),
        )
        .into());
    };
    let actual = resume_checksum(&block);
    if stored != actual {
        return Err(usage(format!(
            "the `resume` block does not match its checksum (resume_checksum {stored}, block \
             {actual}): it was edited, corrupted or copied from another file; refusing to \
             continue from it"
        ))
        .into());
    }
    Ok(block)
}

/// What a shard file says of its study beyond the shard's sums: the `--set` overrides and the
/// truth atmosphere source, which the merged summary's provenance keeps.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StudyProvenance {
    /// The `--set PATH=VALUE` overrides, in the order given.
    pub overrides: Vec<String>,
    /// The truth atmosphere source ([`Provenance::atmosphere`]).
    pub atmosphere: Option<serde_json::Value>,
}

impl StudyProvenance {
    /// The part of `p` that every shard of one study shares.
    pub fn of(p: &Provenance) -> StudyProvenance {
        StudyProvenance {
            overrides: p.overrides.clone(),
            atmosphere: p.atmosphere.clone(),
        }
    }
}

/// A shard file as written by `trade --shard I/N --json FILE`: the shard's sums and its study's
/// provenance.
#[derive(serde::Serialize)]
pub struct ShardFile<'a> {
    /// The sums.
    #[serde(flatten)]
    pub shard: &'a ShardResult,
    /// Overrides and atmosphere source.
    pub provenance: StudyProvenance,
    /// Wall time of the shard's runs \[s\] (`trade merge` reports their sum).
    pub wall_s: f64,
    /// A scenario with `[guidance]`: the delivery runs of the shard's blocks.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delivery: Option<&'a DeliveryShard>,
}

/// What `trade merge` reads from its shard files.
pub struct ReadShards {
    /// The shards' sums.
    pub parts: Vec<ShardResult>,
    /// The provenance they share.
    pub provenance: StudyProvenance,
    /// The sum of their wall times \[s\].
    pub wall_s: f64,
    /// Each shard's deliveries (`None`: the shard has none — no `[guidance]`, or an older file).
    pub deliveries: Vec<Option<DeliveryShard>>,
}

/// Read the shard files of `trade merge`: their sums, and the provenance they share. Refuses a
/// file that is not a shard, one without provenance (an older entrynav), and shards whose
/// overrides or atmosphere source differ (exit code 2, naming both files). Also the sum of the
/// shards' wall times (0 for a shard file without one) and their deliveries.
pub fn read_shards(paths: &[std::path::PathBuf]) -> Result<ReadShards> {
    let mut parts = Vec::new();
    let mut deliveries = Vec::new();
    let mut wall_s = 0.0;
    let mut shared: Option<(StudyProvenance, &Path)> = None;
    for p in paths {
        let usage = |m: String| crate::exit::Usage(format!("shard {}: {m}", p.display()));
        let text = entrynav_loader::read_text(p)
            .with_context(|| format!("cannot read shard {}", p.display()))?;
        let mut v: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| usage(format!("not a shard file (not JSON: {e})")))?;
        let provenance = v
            .get_mut("provenance")
            .map(serde_json::Value::take)
            .ok_or_else(|| {
                usage("no `provenance` (written by an older entrynav); run the shard again".into())
            })?;
        let provenance: StudyProvenance = serde_json::from_value(provenance)
            .map_err(|e| usage(format!("corrupt `provenance`: {e}")))?;
        if let Some(w) = v
            .as_object_mut()
            .and_then(|o| o.remove("wall_s"))
            .and_then(|w| w.as_f64())
            .filter(|w| w.is_finite() && *w >= 0.0)
        {
            wall_s += w;
        }
        let delivery = match v.as_object_mut().and_then(|o| o.remove("delivery")) {
            Some(d) => Some(
                serde_json::from_value::<DeliveryShard>(d)
                    .map_err(|e| usage(format!("corrupt `delivery`: {e}")))?,
            ),
            None => None,
        };
        deliveries.push(delivery);
        let part: ShardResult =
            serde_json::from_value(v).map_err(|e| usage(format!("not a shard file: {e}")))?;
        match &shared {
            None => shared = Some((provenance, p)),
            Some((first, first_path)) if *first != provenance => {
                return Err(crate::exit::Usage(format!(
                    "cannot merge shards of different studies: {} has overrides {:?} and \
                     atmosphere {}, {} has overrides {:?} and atmosphere {}",
                    first_path.display(),
                    first.overrides,
                    json_or_null(&first.atmosphere),
                    p.display(),
                    provenance.overrides,
                    json_or_null(&provenance.atmosphere),
                ))
                .into());
            }
            Some(_) => {}
        }
        parts.push(part);
    }
    let provenance = shared
        .map(|(p, _)| p)
        .ok_or_else(|| crate::exit::Usage("trade merge: no shard file given".into()))?;
    Ok(ReadShards {
        parts,
        provenance,
        wall_s,
        deliveries,
    })
}

fn json_or_null(v: &Option<serde_json::Value>) -> String {
    v.as_ref().map_or_else(|| "null".into(), |v| v.to_string())
}

/// The checksum of a `resume` block: `fnv1a64:` and 16 hex digits of FNV-1a 64 over the block's
/// compact JSON, which round-trips exactly (floats are written in their shortest exact form and
/// read back exactly, serde_json's `float_roundtrip`). It catches a hand-edited, corrupt or
/// pasted-in block; it is not a signature against a deliberate forger.
pub fn resume_checksum(block: &ShardResult) -> String {
    let text = serde_json::to_vec(block).unwrap_or_default();
    format!(
        "fnv1a64:{:016x}",
        entrynav::sim::monte_carlo::shard::fnv1a64(text)
    )
}

/// Write `path` (`-`: standard output), creating its directory.
pub fn write_file(path: &Path, body: impl FnOnce(&mut dyn Write) -> Result<()>) -> Result<()> {
    if is_stdout(path) {
        let mut w = std::io::BufWriter::new(std::io::stdout().lock());
        body(&mut w).context("writing standard output")?;
        w.flush()?;
        return Ok(());
    }
    let mut w = crate::atomic_file::AtomicFile::create(path)?;
    body(&mut w)
        .and_then(|()| Ok(w.flush()?))
        .map_err(|e| crate::exit::Runtime(format!("writing {}: {e:#}", path.display())))?;
    Ok(w.commit()?)
}

/// Write the `--csv-dir` files of `report`: `{scenario}_pcrlb.csv` (when the bound is
/// available), `{scenario}_final_errors.csv` and one `{scenario}_{filter}.csv` per filter.
pub fn write_csv_dir(dir: &Path, report: &TradeReport) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let file = |suffix: &str| dir.join(format!("{}_{suffix}.csv", report.scenario));
    if let Some(b) = report.pcrlb.as_ref().filter(|b| b.available) {
        csv_file::write(&file("pcrlb"), |w| write_pcrlb(w, b))?;
    }
    csv_file::write(&file("final_errors"), |w| write_final_errors(w, report))?;
    for f in &report.filters {
        csv_file::write(&file(&f.name), |w| write_series(w, &report.states, f))?;
    }
    Ok(())
}

/// The PCRLB per epoch: `t_s`, then `pcrlb_<series>` per series.
fn write_pcrlb(w: &mut FileWriter, b: &PcrlbReport) -> Result<()> {
    let names: Vec<&String> = b.series.keys().collect();
    let mut header = vec!["t_s".to_string()];
    header.extend(names.iter().map(|n| format!("pcrlb_{n}")));
    w.write_record(&header)?;
    for (k, t) in b.times_s.iter().enumerate() {
        let mut row = vec![t.to_string()];
        row.extend(names.iter().map(|n| b.series[*n][k].to_string()));
        w.write_record(&row)?;
    }
    Ok(())
}

/// One row per run and filter: run, filter, status, the final error per state, position and
/// velocity error, NEES.
fn write_final_errors(w: &mut FileWriter, report: &TradeReport) -> Result<()> {
    let mut header = vec!["run".to_string(), "filter".into(), "status".into()];
    header.extend(report.states.iter().map(|s| format!("err_{s}")));
    header.extend(["pos_m", "vel_mps", "nees"].map(String::from));
    w.write_record(&header)?;
    for f in &report.filters {
        for r in &f.final_errors {
            let mut row = vec![r.run.to_string(), f.name.clone(), r.status.clone()];
            row.extend((0..report.states.len()).map(|i| opt(r.err.get(i).copied().flatten())));
            row.extend([opt(r.pos_m), opt(r.vel_mps), opt(r.nees)]);
            w.write_record(&row)?;
        }
    }
    Ok(())
}

/// A filter's statistics per epoch: RMSE, mean σ and bias per state, position/velocity RMSE,
/// mean NEES, density errors, mean weights.
fn write_series(w: &mut FileWriter, states: &[String], f: &FilterReport) -> Result<()> {
    let s = &f.series;
    let mut header = vec!["t_s".to_string()];
    for st in states {
        header.push(format!("rmse_{st}"));
        header.push(format!("sigma_mean_{st}"));
        header.push(format!("bias_{st}"));
    }
    header.extend(
        [
            "rmse_pos_m",
            "rmse_vel_mps",
            "nees_mean",
            "density_rms_pct",
            "density_mean_pct",
            "density_at_estimate_rms_pct",
        ]
        .map(String::from),
    );
    let nw = s.weights_mean.iter().map(|w| w.len()).max().unwrap_or(0);
    header.extend((0..nw).map(|j| format!("weight_{j}")));
    w.write_record(&header)?;
    for (k, t) in s.times_s.iter().enumerate() {
        let mut row = vec![t.to_string()];
        for i in 0..states.len() {
            row.push(opt(s.rmse[k][i]));
            row.push(opt(s.sigma_mean[k][i]));
            row.push(opt(s.bias[k][i]));
        }
        row.extend([
            opt(s.pos_rmse_m[k]),
            opt(s.vel_rmse_mps[k]),
            opt(s.nees_mean[k]),
            opt(s.density_rms_pct[k]),
            opt(s.density_mean_pct[k]),
            opt(s.density_at_estimate_rms_pct[k]),
        ]);
        row.extend((0..nw).map(|j| opt(s.weights_mean[k].get(j).copied())));
        w.write_record(&row)?;
    }
    Ok(())
}
