//! The trade family of studies as a front end calls them: a study, its shards merged back into
//! exactly its statistics, the `resume` block read back, a comparison of two summaries, a grid.

use entrynav::sim::{NoCheckpoint, Shard};
use entrynav_studies::ScenarioInput;
use entrynav_studies::compare::input::SummaryIn;
use entrynav_studies::compare::study::compare_summaries;
use entrynav_studies::grid::run::{GridOptions, GridStudy, run_grid};
use entrynav_studies::progress::silent;
use entrynav_studies::provenance::Provenance;
use entrynav_studies::trade::merge::merge_trade_shards;
use entrynav_studies::trade::options::{Method, TradeOptions};
use entrynav_studies::trade::resume::{read_resume, resume_checksum};
use entrynav_studies::trade::setup::{TradeScenario, TradeSetup};
use entrynav_studies::trade::shard::run_trade_shard;
use entrynav_studies::trade::study::{partial_summary, run_trade_study};
use entrynav_studies::{ErrorKind, StudyError};

fn setup(options: &TradeOptions) -> TradeSetup {
    let input = ScenarioInput::resolve("orbiters-3", &[]).unwrap();
    TradeSetup::new(TradeScenario::build(&input).unwrap(), options).unwrap()
}

#[test]
fn merged_shards_are_the_study_and_a_summary_reads_back() {
    let options = TradeOptions {
        runs: Some(300),
        seed: 3,
        threads: Some(2),
        pcrlb: false,
        ..TradeOptions::default()
    };
    let setup = setup(&options);
    let mut none = NoCheckpoint;
    let study = run_trade_study(&setup, &options, None, &mut none, None, &silent).unwrap();
    assert!(study.report.complete && study.partial.is_none() && study.warnings.is_empty());
    let shards: Vec<(String, String)> = (0..2)
        .map(|index| {
            let shard = Shard { index, count: 2 };
            let file = run_trade_shard(&setup, &options, shard, None).unwrap();
            assert!(file.interruption().is_none() && file.notes.is_empty());
            (format!("s{index}"), file.to_json().unwrap())
        })
        .collect();
    let merged = merge_trade_shards(&shards).unwrap();
    // Equal outside the CPU times (which the JSON keeps apart, under `timing`).
    let json = |r: &entrynav::sim::TradeReport| serde_json::to_value(&r.filters).unwrap();
    assert!(
        json(&merged.report) == json(&study.report),
        "merged != study"
    );
    assert_eq!(merged.shards, 2);

    // A summary is what `trade compare` reads; the same study compares equal.
    let provenance = Provenance::new(vec!["test".into()], &[]);
    let text = study.to_json(&provenance).unwrap();
    let summary = SummaryIn::parse(&text).unwrap();
    let cmp = compare_summaries(("a", &summary), ("b", &summary), None);
    assert!(cmp.filters[0].rows.iter().all(|r| r.difference.diff == 0.0));

    // A checkpoint's `resume` block reads back; an edited one is refused.
    let mut partial = merge_shards_partial(&shards);
    partial.complete = false;
    let (text, _) = partial_summary(&provenance, &partial, 1.0).unwrap();
    assert_eq!(
        resume_checksum(&read_resume(&text).unwrap()),
        resume_checksum(&partial)
    );
    let edited = text.replace(
        "\"resume_checksum\": \"fnv1a64:",
        "\"resume_checksum\": \"fnv1a64:0",
    );
    let e = read_resume(&edited).unwrap_err();
    assert!(e.to_string().contains("does not match its checksum"), "{e}");
    assert_eq!(e.kind(), ErrorKind::Refused);
}

/// The first shard's sums, standing in for a partial study.
fn merge_shards_partial(shards: &[(String, String)]) -> entrynav::sim::ShardResult {
    let mut v: serde_json::Value = serde_json::from_str(&shards[0].1).unwrap();
    let o = v.as_object_mut().unwrap();
    for k in ["provenance", "wall_s", "delivery"] {
        o.remove(k);
    }
    serde_json::from_value(v).unwrap()
}

#[test]
fn shards_of_different_studies_or_no_shard_are_refused() {
    let e = merge_trade_shards(&[]).err().unwrap();
    assert_eq!(e.to_string(), "trade merge: no shard file given");
    let e = merge_trade_shards(&[("x.json".into(), "{".into())])
        .err()
        .unwrap();
    assert!(
        e.to_string().starts_with("shard x.json: not a shard file"),
        "{e}"
    );
}

#[test]
fn a_lincov_grid_hands_over_its_rows() {
    let dir = std::env::temp_dir().join(format!("entrynav-studies-grid-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("g.toml");
    std::fs::write(
        &path,
        "name = \"g\"\nruns = 2\nfilters = [\"ekf\", \"dcifaif\"]\nscenarios = [\"four-beacon-fusion\"]\n\
         [variations]\nbeacons = [1, 4]\n",
    )
    .unwrap();
    let study = GridStudy::load(
        &path,
        &GridOptions {
            method: Method::Lincov,
        },
    )
    .unwrap();
    assert_eq!(study.cells.len(), 2);
    let cells = std::sync::Mutex::new(Vec::new());
    let progress = |s: entrynav_studies::progress::Step<'_>| {
        cells.lock().unwrap().push(s.task.to_string());
    };
    let results = run_grid(&study, None, &progress, |_| Ok::<_, Box<StudyError>>(())).unwrap();
    assert!(results.stopped.is_none());
    assert_eq!(results.rows.len(), 4);
    assert!(results.rows[0].refused.is_some(), "dcifaif on one beacon");
    let cells = cells.into_inner().unwrap();
    assert!(cells[0].starts_with("c00 four-beacon-fusion (1 beacons): 1 filters × LinCov"));
    let e = GridStudy::load(
        &path,
        &GridOptions {
            method: Method::Both,
        },
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("--method both with --grid"));
}
