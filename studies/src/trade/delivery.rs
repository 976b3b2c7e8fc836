//! Delivery at deployment beside a trade of a scenario with `[guidance]`: the same runs flown
//! with each filter in the guidance loop (`entrynav::sim::delivery`), for the whole study, for
//! one shard's runs, and merged from shards.
//!
//! The whole study's table is the guidance study's
//! [`delivery_of_study`](crate::guidance::deliver::delivery_of_study).

use crate::error::{StudyError, StudyResult, chain};
use crate::threads::with_threads;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::Shard;
use entrynav::sim::guided::delivery::DeliveryReport;
use entrynav::sim::guided::delivery_shard::{DeliveryShard, deliver_runs, merge_delivery_shards};
use entrynav::sim::monte_carlo::shard::ACCUMULATION_BLOCK;

/// The delivery runs of `shard`'s blocks, merged by run index when the shards are merged.
pub fn shard_delivery(
    scenario: &Scenario,
    filters: &[FilterKind],
    (runs, seed): (usize, u64),
    shard: Shard,
    threads: Option<usize>,
) -> StudyResult<DeliveryShard> {
    let blocks = shard.blocks(runs);
    let block = ACCUMULATION_BLOCK;
    let span = (blocks.start * block).min(runs)..(blocks.end * block).min(runs);
    with_threads(threads, || {
        deliver_runs(scenario, filters, runs, seed, span).map_err(|e| {
            StudyError::Failed(format!(
                "the delivery at deployment of the shard's runs: {}",
                chain(&e)
            ))
        })
    })
}

/// The delivery of merged shards: every shard's runs in run order (`None` when no shard has
/// deliveries). Refuses a merge where some shards have deliveries and others not (one flown
/// without `[guidance]`, or by an older entrynav), or whose deliveries do not fit together.
pub fn merged_delivery(
    deliveries: Vec<Option<DeliveryShard>>,
) -> StudyResult<Option<DeliveryReport>> {
    let with = deliveries.iter().filter(|d| d.is_some()).count();
    if with == 0 {
        return Ok(None);
    }
    if with < deliveries.len() {
        return Err(StudyError::Refused(format!(
            "{with} of {} shards carry a delivery table and the others do not; run the others \
             again with this entrynav",
            deliveries.len()
        )));
    }
    let merged = merge_delivery_shards(deliveries.into_iter().flatten().collect())
        .map_err(|e| StudyError::Refused(format!("trade merge: {e}")))?;
    Ok(Some(merged))
}
