//! `trade merge`: shard files combined into the study's report, exactly the single-process
//! result. The merged summary keeps the shards' `--set` overrides and atmosphere source; shards
//! that differ in them are refused, as are files that are not shards.

use crate::error::{StudyError, StudyResult};
use crate::provenance::{Provenance, Summary};
use crate::trade::delivery::merged_delivery;
use crate::trade::shard::StudyProvenance;
use crate::trade::study::{pretty, summary};
use entrynav::sim::guided::delivery::DeliveryReport;
use entrynav::sim::guided::delivery_shard::DeliveryShard;
use entrynav::sim::{ShardResult, TradeReport, merge_shards};
use serde_json::Value;

/// The merged study.
pub struct MergedTrade {
    /// The statistics.
    pub report: TradeReport,
    /// The provenance the shards share.
    pub provenance: StudyProvenance,
    /// The scenario fingerprint of the shards.
    pub scenario_fingerprint: String,
    /// The sum of the shards' wall times \[s\].
    pub wall_s: f64,
    /// How many shards were merged.
    pub shards: usize,
    /// Delivery at deployment, when the shards carry it.
    pub delivery: Option<DeliveryReport>,
}

impl MergedTrade {
    /// The merged summary's provenance, for `command_line`.
    pub fn provenance(&self, command_line: Vec<String>) -> Provenance {
        Provenance {
            scenario_fingerprint: Some(self.scenario_fingerprint.clone()),
            overrides: self.provenance.overrides.clone(),
            atmosphere: self.provenance.atmosphere.clone(),
            ..Provenance::new(command_line, &[])
        }
    }

    /// The merged summary (what `trade merge --json` writes), by `Serialize`.
    pub fn summary<'a>(&'a self, provenance: &'a Provenance) -> Summary<'a> {
        let blocks = (None, self.delivery.as_ref());
        summary(provenance, &self.report, None, self.wall_s, blocks)
    }

    /// The merged summary's text.
    pub fn to_json(&self, provenance: &Provenance) -> StudyResult<String> {
        pretty(&self.summary(provenance))
    }
}

/// One shard file, read.
struct ShardIn {
    part: ShardResult,
    provenance: StudyProvenance,
    wall_s: Option<f64>,
    delivery: Option<DeliveryShard>,
}

/// Parse the shard file `text`; errors say what is wrong with it.
fn parse(text: &str) -> Result<ShardIn, String> {
    let mut v: Value =
        serde_json::from_str(text).map_err(|e| format!("not a shard file (not JSON: {e})"))?;
    let provenance = v
        .get_mut("provenance")
        .map(Value::take)
        .ok_or("no `provenance` (written by an older entrynav); run the shard again")?;
    let provenance: StudyProvenance =
        serde_json::from_value(provenance).map_err(|e| format!("corrupt `provenance`: {e}"))?;
    let wall_s = v
        .as_object_mut()
        .and_then(|o| o.remove("wall_s"))
        .and_then(|w| w.as_f64())
        .filter(|w| w.is_finite() && *w >= 0.0);
    let delivery = match v.as_object_mut().and_then(|o| o.remove("delivery")) {
        Some(d) => Some(
            serde_json::from_value::<DeliveryShard>(d)
                .map_err(|e| format!("corrupt `delivery`: {e}"))?,
        ),
        None => None,
    };
    let part: ShardResult =
        serde_json::from_value(v).map_err(|e| format!("not a shard file: {e}"))?;
    Ok(ShardIn {
        part,
        provenance,
        wall_s,
        delivery,
    })
}

fn json_or_null(v: &Option<Value>) -> String {
    v.as_ref().map_or_else(|| "null".into(), |v| v.to_string())
}

/// Merge the shard files `shards`, each `(label, text)` (the label names the file in messages:
/// `shard LABEL: …`). Refuses a file that is not a shard, one without provenance (an older
/// entrynav), shards whose overrides or atmosphere source differ (naming both files), and shards
/// whose sums or deliveries do not fit together. The wall time is the sum of the shards' (0 for
/// a shard file without one).
pub fn merge_trade_shards(shards: &[(String, String)]) -> StudyResult<MergedTrade> {
    let mut parts = Vec::new();
    let mut deliveries = Vec::new();
    let mut wall_s = 0.0;
    let mut shared: Option<(StudyProvenance, &str)> = None;
    for (label, text) in shards {
        let shard = parse(text).map_err(|m| StudyError::Refused(format!("shard {label}: {m}")))?;
        wall_s += shard.wall_s.unwrap_or(0.0);
        deliveries.push(shard.delivery);
        match &shared {
            None => shared = Some((shard.provenance, label)),
            Some((first, first_label)) if *first != shard.provenance => {
                let p = &shard.provenance;
                return Err(StudyError::Refused(format!(
                    "cannot merge shards of different studies: {first_label} has overrides {:?} \
                     and atmosphere {}, {label} has overrides {:?} and atmosphere {}",
                    first.overrides,
                    json_or_null(&first.atmosphere),
                    p.overrides,
                    json_or_null(&p.atmosphere),
                )));
            }
            Some(_) => {}
        }
        parts.push(shard.part);
    }
    let provenance = shared
        .map(|(p, _)| p)
        .ok_or_else(|| StudyError::Refused("trade merge: no shard file given".into()))?;
    let n_shards = parts.len();
    let delivery = merged_delivery(deliveries)?;
    let scenario_fingerprint = parts
        .first()
        .map(|p| p.scenario_fingerprint.clone())
        .unwrap_or_default();
    let report = merge_shards(parts)?;
    Ok(MergedTrade {
        report,
        provenance,
        scenario_fingerprint,
        wall_s,
        shards: n_shards,
        delivery,
    })
}
