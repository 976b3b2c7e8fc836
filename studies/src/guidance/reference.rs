//! `entrynav guidance reference` as a study: the reference trajectory `[guidance]` builds from the
//! onboard nominal entry (Mendeck & Craig, AIAA 2011-6639: the reference drag, altitude-rate and
//! range-to-go profiles against speed, and the gains F1 = ∂R/∂D, F2 = ∂R/∂ṙ, F3 = ∂R/∂(L/D) from
//! the adjoint sensitivities), tabulated, and its CSV and JSON documents.

use crate::error::{StudyError, StudyResult};
use entrynav::scenario::Scenario;
use serde_json::{Value, json};
use std::io::Write;

/// The columns of the table, in order.
pub const COLUMNS: [&str; 12] = [
    "t_s",
    "speed_mps",
    "altitude_m",
    "fpa_deg",
    "downrange_m",
    "range_to_go_m",
    "drag_mps2",
    "rdot_mps",
    "f1_m_per_mps2",
    "f2_m_per_mps",
    "f3_m",
    "u_vertical_ld",
];

/// The reference trajectory and its gains.
#[derive(Debug, Clone, PartialEq)]
pub struct GuidanceReference {
    /// The scenario's name.
    pub scenario: String,
    /// The reference bank \[deg\].
    pub bank_deg: f64,
    /// Its vertical lift-to-drag ratio.
    pub vertical_ld: f64,
    /// Downrange from entry to the deployment trigger \[m\].
    pub downrange_to_trigger_m: f64,
    /// The target's latitude and longitude \[deg\].
    pub target_deg: (f64, f64),
    /// One row per point, speed decreasing, in the order of [`COLUMNS`] (never empty).
    pub rows: Vec<[f64; 12]>,
}

/// The reference of `scenario`'s `[guidance]`.
pub fn run_reference(scenario: &Scenario) -> StudyResult<GuidanceReference> {
    let name = &scenario.config.name;
    let built = scenario
        .build_guidance()
        .ok_or_else(|| {
            StudyError::Refused(format!(
                "scenario '{name}' has no [guidance] section; add one (or --set 'guidance={{…}}')"
            ))
        })?
        .map_err(|e| StudyError::Refused(format!("the reference of '{name}': {e}")))?;
    let radius = scenario.planet.radius;
    let r = &built.reference;
    let rows: Vec<[f64; 12]> = r
        .points
        .iter()
        .map(|p| {
            [
                p.t,
                p.x[2],
                p.x[1] - radius,
                p.x[3].to_degrees(),
                p.x[0] * radius,
                p.range_to_go,
                p.drag,
                p.rdot,
                p.f1,
                p.f2,
                p.f3,
                p.x[4],
            ]
        })
        .collect();
    if rows.is_empty() {
        return Err(StudyError::Refused(format!(
            "the reference of '{name}' has no point"
        )));
    }
    Ok(GuidanceReference {
        scenario: name.clone(),
        bank_deg: r.bank.to_degrees(),
        vertical_ld: r.vertical_ld,
        downrange_to_trigger_m: r.total_range(radius),
        target_deg: (built.target.lat.to_degrees(), built.target.lon.to_degrees()),
        rows,
    })
}

impl GuidanceReference {
    /// The JSON document (`--json`): the summary and the table.
    pub fn to_json(&self) -> Value {
        let (lat, lon) = self.target_deg;
        json!({
            "scenario": self.scenario,
            "reference_bank_deg": self.bank_deg,
            "vertical_lift_to_drag": self.vertical_ld,
            "downrange_to_trigger_m": self.downrange_to_trigger_m,
            "target": {"lat_deg": lat, "lon_deg": lon},
            "columns": COLUMNS,
            "points": self.rows,
        })
    }

    /// The CSV table (`--csv`): [`COLUMNS`], then one row per point.
    pub fn write_csv<W: Write>(&self, w: &mut csv::Writer<W>) -> csv::Result<()> {
        w.write_record(COLUMNS)?;
        for row in &self.rows {
            w.write_record(row.iter().map(|v| format!("{v:.9e}")))?;
        }
        Ok(())
    }

    /// The first point (entry) and the last (the deployment trigger); `None` without points.
    pub fn ends(&self) -> Option<(&[f64; 12], &[f64; 12])> {
        Some((self.rows.first()?, self.rows.last()?))
    }
}
