//! Delivery at deployment of a sharded study (`core/src/sim/delivery_shard.rs`): the runs of
//! every shard, stored as a shard file stores them (JSON round trip included) and merged by run
//! index, give the same delivery table as the single-process study — failures and their
//! messages included; shards of different studies, a run in two shards and a missing run are
//! refused.

#[path = "support/seed001_guided.rs"]
mod seed001_guided;

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::guided::delivery::run_delivery;
use entrynav::sim::guided::delivery_shard::{
    DeliveryShard, DeliveryShardError, deliver_runs, merge_delivery_shards,
};

/// `msl-guided` on seed 001's dispersions, whose failures the shards must carry.
fn msl_guided() -> Scenario {
    Scenario::build(
        seed001_guided::seed001_guided_config(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

/// Through the shard file's JSON and back.
fn round_trip(s: DeliveryShard) -> DeliveryShard {
    serde_json::from_str(&serde_json::to_string(&s).unwrap()).unwrap()
}

#[test]
fn merged_shards_give_the_single_process_delivery_table() {
    let sc = msl_guided();
    let (runs, seed, filters) = (60, 3, [FilterKind::Ekf]);
    let whole = run_delivery(&sc, &filters, runs, seed, &|_| ()).unwrap();
    // The sample must contain failures, so that their storage is exercised.
    assert!(
        whole.rows.iter().any(|r| r.failures > 0),
        "{:?}",
        whole.rows
    );
    let shards: Vec<DeliveryShard> = [40..60, 0..25, 25..40]
        .into_iter()
        .map(|r| round_trip(deliver_runs(&sc, &filters, runs, seed, r).unwrap()))
        .collect();
    let merged = merge_delivery_shards(shards).unwrap();
    assert_eq!(merged.rows, whole.rows);
    assert_eq!(
        (
            merged.runs,
            merged.seed,
            &merged.algorithm,
            merged.bank_rate_limit_deg_s
        ),
        (
            whole.runs,
            whole.seed,
            &whole.algorithm,
            whole.bank_rate_limit_deg_s
        )
    );
    for (a, b) in merged.per_run.iter().zip(&whole.per_run) {
        for (x, y) in a.iter().zip(b) {
            match (x, y) {
                (Ok(x), Ok(y)) => assert_eq!(x, y),
                (Err(x), Err(y)) => assert_eq!(x.to_string(), y.to_string()),
                _ => panic!("{x:?} vs {y:?}"),
            }
        }
    }
}

#[test]
fn shards_that_do_not_make_one_study_are_refused() {
    let sc = msl_guided();
    let f = [FilterKind::Ekf];
    let part = |r, seed| deliver_runs(&sc, &f, 8, seed, r).unwrap();
    let e = merge_delivery_shards(vec![part(0..4, 1), part(4..8, 2)]).unwrap_err();
    assert!(
        matches!(e, DeliveryShardError::Mismatch { field: "seed", .. }),
        "{e}"
    );
    let e = merge_delivery_shards(vec![part(0..5, 1), part(4..8, 1)]).unwrap_err();
    assert_eq!(
        e,
        DeliveryShardError::Run {
            run: 4,
            why: "in two shards",
            runs: 8
        }
    );
    let e = merge_delivery_shards(vec![part(0..3, 1), part(4..8, 1)]).unwrap_err();
    assert_eq!(e.to_string(), "run 3 is in no shard (study of 8 runs)");
    assert!(deliver_runs(&sc, &f, 8, 1, 4..9).is_err());
    assert_eq!(
        merge_delivery_shards(vec![]).unwrap_err(),
        DeliveryShardError::Empty
    );
}
