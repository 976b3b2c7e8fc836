//! The CSV series of a trade (`trade --csv-dir`): per filter its statistics per epoch, the final
//! errors of every run, the PCRLB per epoch. Each is written into a `csv::Writer` the caller
//! opens (the command line's is a file written whole or not at all).

use entrynav::sim::{FilterReport, PcrlbReport, TradeReport};
use std::io::Write;

/// A value as the CSV files write it: Rust's shortest round-trip `Display` (`0.1`, `0.0000001`,
/// `NaN`), an empty field when absent.
pub fn opt(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

/// One CSV file of the series: its name's suffix (`{scenario}_{suffix}.csv`) and what it holds.
pub enum SeriesFile<'a> {
    /// `pcrlb`: the bound per epoch.
    Pcrlb(&'a PcrlbReport),
    /// `final_errors`: one row per run and filter.
    FinalErrors,
    /// `{filter}`: one filter's statistics per epoch.
    Filter(&'a FilterReport),
}

impl SeriesFile<'_> {
    /// The file name's suffix.
    pub fn suffix(&self) -> &str {
        match self {
            SeriesFile::Pcrlb(_) => "pcrlb",
            SeriesFile::FinalErrors => "final_errors",
            SeriesFile::Filter(f) => &f.name,
        }
    }

    /// Write the file's rows.
    pub fn write<W: Write>(&self, w: &mut csv::Writer<W>, report: &TradeReport) -> csv::Result<()> {
        match self {
            SeriesFile::Pcrlb(b) => write_pcrlb(w, b),
            SeriesFile::FinalErrors => write_final_errors(w, report),
            SeriesFile::Filter(f) => write_series(w, &report.states, f),
        }
    }
}

/// The files of `report`, in the order they are written: the PCRLB (when the bound is
/// available), the final errors, one per filter.
pub fn series_files(report: &TradeReport) -> Vec<SeriesFile<'_>> {
    let mut out = Vec::new();
    if let Some(b) = report.pcrlb.as_ref().filter(|b| b.available) {
        out.push(SeriesFile::Pcrlb(b));
    }
    out.push(SeriesFile::FinalErrors);
    out.extend(report.filters.iter().map(SeriesFile::Filter));
    out
}

/// The PCRLB per epoch: `t_s`, then `pcrlb_<series>` per series.
fn write_pcrlb<W: Write>(w: &mut csv::Writer<W>, b: &PcrlbReport) -> csv::Result<()> {
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
fn write_final_errors<W: Write>(w: &mut csv::Writer<W>, report: &TradeReport) -> csv::Result<()> {
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
fn write_series<W: Write>(
    w: &mut csv::Writer<W>,
    states: &[String],
    f: &FilterReport,
) -> csv::Result<()> {
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
