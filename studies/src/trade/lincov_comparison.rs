//! `trade --method both`: LinCov of each filter (`entrynav::sim::lincov_entry`) beside the
//! finished Monte Carlo, per filter and headline figure (time-averaged and final position and
//! velocity RMSE, every state's time-averaged RMSE, ANEES/dof, the mean error's share of it):
//! LinCov's prediction, the ratio LinCov / Monte Carlo and a flag where the two differ by more
//! than the Monte Carlo's 95 % sampling interval (RMSE: the Gaussian bound RMSE/√(2N); ANEES:
//! ANEES·√(2/(dof·N))) — where they do, the filter or the truth is nonlinear enough on the
//! dispersed runs for LinCov's first-order prediction to miss. The summary carries the
//! comparison under `lincov`.

use crate::error::StudyResult;
use crate::lincov::analysis::{Analysed, analyse, mean_error_nees};
use crate::lincov::document::to_json;
use crate::statistics::{Z95, se_anees, se_rmse_bound};
use entrynav::estimation::chi_square::chi_square_quantile;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::lincov::{EntryLinCovEpoch, LinCovOptions};
use entrynav::sim::{FilterReport, TradeReport};
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// The first-order LinCov of `filters` (a trade's LinCov has no second-order option).
pub fn first_order(scenario: &Scenario, filters: &[FilterKind]) -> StudyResult<Vec<Analysed>> {
    analyse(
        scenario,
        filters,
        &scenario.config.name,
        LinCovOptions::default(),
    )
}

/// One compared figure.
#[derive(Debug, Clone)]
pub struct ComparedFigure {
    /// `rmse_time_avg.pos_m`, `anees_per_dof`, …
    pub figure: String,
    /// LinCov's prediction.
    pub lincov: f64,
    /// The Monte Carlo's value.
    pub mc: f64,
    /// Half-width of the Monte Carlo's 95 % interval.
    pub half: f64,
}

impl ComparedFigure {
    /// LinCov / Monte Carlo.
    pub fn ratio(&self) -> f64 {
        self.lincov / self.mc
    }

    /// Whether LinCov lies outside the Monte Carlo's 95 % interval.
    pub fn disagrees(&self) -> bool {
        (self.lincov - self.mc).abs() > self.half
    }

    fn json(&self) -> Value {
        let f = |v: f64| if v.is_finite() { json!(v) } else { Value::Null };
        json!({
            "figure": self.figure,
            "lincov": f(self.lincov),
            "monte_carlo": f(self.mc),
            "ratio": f(self.ratio()),
            "mc_interval_95": [f(self.mc - self.half), f(self.mc + self.half)],
            "outside_mc_interval": self.disagrees(),
        })
    }
}

/// The figures of one filter: headline figures first, then every state's time-averaged RMSE.
pub fn figures(a: &Analysed, f: &FilterReport) -> Vec<ComparedFigure> {
    let l = &a.lincov;
    let n = f.runs.saturating_sub(f.failed);
    let mut out = Vec::new();
    let mut rmse = |figure: String, lincov: f64, mc: Option<f64>| {
        if let Some(mc) = mc.filter(|m| m.is_finite() && *m > 0.0)
            && lincov.is_finite()
        {
            let half = Z95 * se_rmse_bound(mc, n);
            out.push(ComparedFigure {
                figure,
                lincov,
                mc,
                half,
            });
        }
    };
    let get = |m: &BTreeMap<String, Option<f64>>, k: &str| m.get(k).copied().flatten();
    let (avg, fin) = (&f.rmse_time_avg, &f.rmse_final);
    rmse(
        "rmse_time_avg.pos_m".into(),
        l.time_avg(|e| e.pos_m),
        get(avg, "pos_m"),
    );
    rmse(
        "rmse_final.pos_m".into(),
        l.final_value(|e| e.pos_m),
        get(fin, "pos_m"),
    );
    rmse(
        "rmse_time_avg.vel_mps".into(),
        l.time_avg(|e| e.vel_mps),
        get(avg, "vel_mps"),
    );
    rmse(
        "rmse_final.vel_mps".into(),
        l.final_value(|e| e.vel_mps),
        get(fin, "vel_mps"),
    );
    for (i, name) in l.states.iter().enumerate() {
        rmse(
            format!("rmse_time_avg.{name}"),
            l.time_avg(|e| e.rmse[i]),
            get(avg, name),
        );
    }
    out.extend(consistency_figures(a, f, n));
    out
}

/// ANEES/dof and the NEES/dof a mean error carries.
fn consistency_figures(a: &Analysed, f: &FilterReport, n: u64) -> Vec<ComparedFigure> {
    let l = &a.lincov;
    let c = &f.consistency;
    let mut out = Vec::new();
    let Some(anees) = c.anees else { return out };
    let dof = c.nees_dof.max(1) as f64;
    out.push(ComparedFigure {
        figure: "anees_per_dof".into(),
        lincov: l.nees_ratio_time_avg(),
        mc: anees / dof,
        half: Z95 * se_anees(anees, dof, n) / dof,
    });
    // The NEES/dof a mean error carries, q = m̄ᵀP⁻¹m̄/dof in LinCov's P. With the Monte
    // Carlo's m̂ = m̄ + ε, ε ~ N(0, Σ/n) and P⁻¹Σ ≈ c·I (c = ANEES/dof), its estimate is
    // q + 2m̄ᵀP⁻¹ε/dof + εᵀP⁻¹ε/dof: standard deviation ≈ 2√(q·c/n) from the first term and
    // a noise floor whose 95 % point is χ²₀.₉₅(dof)/dof · c/n from the second. The interval
    // is ±(Z₉₅ of the first + the floor's 95 % point), taken symmetric.
    let (q, _) = mean_error_nees(l, None);
    let (q_mc, _) = mean_error_nees(l, Some(f));
    if q.is_finite() && q_mc.is_finite() && n > 0 {
        let per_dof = anees / dof / n as f64;
        let floor = chi_square_quantile(0.95, c.nees_dof.max(1)) / dof * per_dof;
        out.push(ComparedFigure {
            figure: "mean_error_nees_per_dof".into(),
            lincov: q,
            mc: q_mc,
            half: 2.0 * Z95 * (q_mc.max(0.0) * per_dof).sqrt() + floor,
        });
    }
    out
}

/// A named curve of `(t, value)` points.
pub type NamedCurve = (String, Vec<(f64, f64)>);

/// LinCov beside a finished Monte Carlo.
pub struct LinCovComparison {
    /// Each filter's prediction.
    pub analysed: Vec<Analysed>,
    json: Value,
}

impl LinCovComparison {
    /// LinCov of the report's filters on `scenario`, compared with `report`.
    pub fn of(
        scenario: &Scenario,
        filters: &[FilterKind],
        report: &TradeReport,
    ) -> StudyResult<Self> {
        let analysed = first_order(scenario, filters)?;
        let mut json = to_json(scenario, &analysed, None)["lincov"].take();
        let per: Vec<Value> = analysed
            .iter()
            .filter_map(|a| {
                let f = report.filters.iter().find(|f| f.name == a.lincov.filter)?;
                let rows: Vec<Value> = figures(a, f).iter().map(ComparedFigure::json).collect();
                Some(json!({"name": f.name, "runs": f.runs, "figures": rows}))
            })
            .collect();
        json["versus_monte_carlo"] = json!(per);
        Ok(LinCovComparison { analysed, json })
    }

    /// The `lincov` block of the summary.
    pub fn json(&self) -> &Value {
        &self.json
    }

    /// LinCov's RMSE curves per metric (every state, `pos_m`, `vel_mps`), each named
    /// "`<filter>` LinCov", for the RMSE charts beside the Monte Carlo's.
    pub fn curves(&self) -> BTreeMap<String, Vec<NamedCurve>> {
        let mut out: BTreeMap<String, Vec<NamedCurve>> = BTreeMap::new();
        for a in &self.analysed {
            let l = &a.lincov;
            let name = format!("{} LinCov", l.filter);
            let series = |f: &dyn Fn(&EntryLinCovEpoch) -> f64| {
                l.epochs.iter().map(|e| (e.t, f(e))).collect::<Vec<_>>()
            };
            let mut add = |metric: &str, points: Vec<(f64, f64)>| {
                out.entry(metric.to_string())
                    .or_default()
                    .push((name.clone(), points));
            };
            add("pos_m", series(&|e| e.pos_m));
            add("vel_mps", series(&|e| e.vel_mps));
            for (i, state) in l.states.iter().enumerate() {
                add(state, series(&|e| e.rmse[i]));
            }
        }
        out
    }
}
