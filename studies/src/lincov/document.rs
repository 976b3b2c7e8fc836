//! What LinCov writes: the JSON document (`entrynav lincov --json`, the `lincov` block of a
//! `trade --method both` summary) and each filter's per-epoch CSV series.

use crate::lincov::analysis::{Analysed, mean_error_nees};
use entrynav::scenario::Scenario;
use entrynav::sim::TradeReport;
use entrynav::sim::lincov::{EntryLinCov, EntryLinCovEpoch};
use serde_json::{Map, Value, json};

/// The Monte Carlo summary's per-state and pos/vel RMSE keys, predicted.
fn rmse_map(l: &EntryLinCov, at: impl Fn(&[f64]) -> f64, pos: f64, vel: f64) -> Map<String, Value> {
    let mut m = Map::new();
    for (i, name) in l.states.iter().enumerate() {
        let v = at(&l.epochs.iter().map(|e| e.rmse[i]).collect::<Vec<_>>());
        m.insert(name.clone(), finite(v));
    }
    m.insert("pos_m".into(), finite(pos));
    m.insert("vel_mps".into(), finite(vel));
    m
}

fn finite(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

/// The JSON `entrynav lincov --json` writes: `lincov` (the predictions), and `monte_carlo` beside
/// them when one was run (`mc`: its report and wall time).
pub fn to_json(
    scenario: &Scenario,
    analysed: &[Analysed],
    mc: Option<&(TradeReport, f64)>,
) -> Value {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let last = |v: &[f64]| v.last().copied().unwrap_or(f64::NAN);
    let filters: Vec<Value> = analysed
        .iter()
        .map(|a| {
            let l = &a.lincov;
            let e = |f: fn(&EntryLinCovEpoch) -> f64| (l.time_avg(f), l.final_value(f));
            let (pos, pos_f) = e(|x| x.pos_m);
            let (vel, vel_f) = e(|x| x.vel_mps);
            let (ps, ps_f) = e(|x| x.pos_sigma_m);
            let (vs, vs_f) = e(|x| x.vel_sigma_mps);
            let dof = l.epochs.last().map_or(0, |x| x.nees_dof);
            let (bias, bias_f) = mean_error_nees(l, None);
            json!({
                "name": l.filter,
                "epochs": l.epochs.len(),
                "rmse_time_avg": rmse_map(l, mean, pos, vel),
                "rmse_final": rmse_map(l, last, pos_f, vel_f),
                "sigma_time_avg": {"pos_m": finite(ps), "vel_mps": finite(vs)},
                "sigma_final": {"pos_m": finite(ps_f), "vel_mps": finite(vs_f)},
                "anees": finite(l.time_avg(|x| x.nees)),
                "nees_dof": dof,
                "anees_kinematic": finite(l.time_avg(|x| x.nees_kinematic)),
                "nees_ratio_time_avg": finite(l.nees_ratio_time_avg()),
                "nees_ratio_final": finite(l.final_value(EntryLinCovEpoch::nees_per_dof)),
                "mean_error_nees_ratio_time_avg": finite(bias),
                "mean_error_nees_ratio_final": finite(bias_f),
                "parameters": l.parameters,
                "notes": l.notes,
                "wall_s": a.seconds,
            })
        })
        .collect();
    let mut top = json!({
        "lincov": {
            "scenario": scenario.config.name,
            "states": analysed.first().map(|a| a.lincov.states.clone()).unwrap_or_default(),
            "filters": filters,
        }
    });
    if let Some((report, seconds)) = mc {
        let per: Vec<Value> = report
            .filters
            .iter()
            .map(|f| {
                let c = &f.consistency;
                let bias = analysed
                    .iter()
                    .find(|a| a.lincov.filter == f.name)
                    .map(|a| mean_error_nees(&a.lincov, Some(f)));
                json!({
                    "name": f.name,
                    "mean_error_nees_ratio_time_avg": bias.map(|b| finite(b.0)),
                    "mean_error_nees_ratio_final": bias.map(|b| finite(b.1)),
                    "rmse_time_avg": f.rmse_time_avg,
                    "rmse_final": f.rmse_final,
                    "anees": c.anees,
                    "nees_dof": c.nees_dof,
                    "failed": f.failed,
                    "diverged": f.diverged,
                })
            })
            .collect();
        top["monte_carlo"] = json!({"runs": report.runs, "wall_s": seconds, "filters": per});
    }
    top
}

/// The per-epoch series of one filter as CSV (`lincov_<filter>.csv`).
pub fn write_csv<W: std::io::Write>(w: &mut csv::Writer<W>, l: &EntryLinCov) -> csv::Result<()> {
    let mut header = vec![
        "t_s".to_string(),
        "pos_rmse_m".into(),
        "vel_rmse_mps".into(),
        "pos_sigma_m".into(),
        "vel_sigma_mps".into(),
        "nees".into(),
        "nees_dof".into(),
    ];
    for s in &l.states {
        header.push(format!("rmse_{s}"));
        header.push(format!("sigma_{s}"));
        header.push(format!("mean_error_{s}"));
    }
    w.write_record(&header)?;
    for e in &l.epochs {
        let mut row = vec![
            e.t.to_string(),
            e.pos_m.to_string(),
            e.vel_mps.to_string(),
            e.pos_sigma_m.to_string(),
            e.vel_sigma_mps.to_string(),
            e.nees.to_string(),
            e.nees_dof.to_string(),
        ];
        for i in 0..l.states.len() {
            row.push(e.rmse[i].to_string());
            row.push(e.sigma[i].to_string());
            row.push(e.mean_error[i].to_string());
        }
        w.write_record(&row)?;
    }
    w.flush()?;
    Ok(())
}
