//! A Monte Carlo trade of navigation filters on a scenario: its options ([`options`]), the
//! scenario, filters and runs it starts from ([`setup`]), the study itself, new or resumed, with
//! checkpoints and cancellation ([`study`]), its summary's `resume` block ([`resume`]), shards
//! and their merge ([`shard`], [`merge`]), LinCov beside it ([`lincov_comparison`]), delivery
//! at deployment for a scenario with `[guidance]` ([`delivery`]), what the papers predict a filter
//! does ([`expected`]), the CSV series
//! ([`csv_series`]) and one run replayed in full ([`replay`]).

pub mod csv_series;
pub mod delivery;
pub mod expected;
pub mod lincov_comparison;
pub mod merge;
pub mod options;
pub mod replay;
pub mod resume;
pub mod setup;
pub mod shard;
pub mod study;

pub use merge::{MergedTrade, merge_trade_shards};
pub use options::{Method, TradeMode, TradeOptions};
pub use replay::{ReplayedRun, replay_trade_run};
pub use resume::{read_resume, resume_checksum};
pub use setup::{TradeScenario, TradeSetup};
pub use shard::{ShardRun, StudyProvenance, run_trade_shard};
pub use study::{TradeOutcome, run_trade_lincov, run_trade_study};
