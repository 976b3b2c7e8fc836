//! The options of a trade ([`TradeOptions`]) and how its statistics are computed ([`Method`]),
//! with their checks: the bounds of every count and interval, and the combinations of a method
//! with a mode (resume, shard, replay, grid) that have no meaning.

use crate::error::{StudyError, StudyResult};
use crate::options::{MAX_RUNS, OptionError, check_count, check_threads};

/// The default checkpoint interval (s): a study over a minute long is checkpointed; writing a
/// summary takes milliseconds, so the cost is negligible.
pub const DEFAULT_CHECKPOINT_EVERY_S: f64 = 60.0;

/// The checkpoint interval's allowed range (s), besides 0 (off).
pub const CHECKPOINT_EVERY_RANGE_S: (f64, f64) = (0.1, 86_400.0);

/// How a trade computes its statistics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Monte Carlo of `runs` dispersed runs.
    #[default]
    Mc,
    /// LinCov of each filter along the nominal trajectory (one pass, no runs).
    Lincov,
    /// Both, with LinCov / Monte Carlo for every headline figure.
    Both,
}

impl Method {
    /// The name the command line and Python give it.
    pub fn name(self) -> &'static str {
        match self {
            Method::Mc => "mc",
            Method::Lincov => "lincov",
            Method::Both => "both",
        }
    }
}

/// What a trade invocation does besides a plain study, for [`TradeOptions::check_mode`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TradeMode {
    /// A study, or the continuation of an interrupted one (`resume`).
    Study {
        /// Whether it continues a partial summary.
        resume: bool,
    },
    /// One shard of a study.
    Shard,
    /// One run replayed in full.
    Replay,
    /// A grid of scenarios × variations × filters.
    Grid,
}

/// The options of a trade (the flags of `entrynav trade`, the keywords of Python's `trade`).
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TradeOptions {
    /// Comma-separated filters: ekf, ukf, ci, dcifaif, mmae, mmae-moe, ukf-cm, ukf-ac, uskf-nn.
    pub filters: String,
    /// Monte Carlo runs (`None`: the scenario's `monte_carlo.runs`), 1 to [`MAX_RUNS`].
    pub runs: Option<usize>,
    /// Master seed; the same seed gives the same statistics on any thread count.
    pub seed: u64,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Form the posterior Cramér–Rao lower bound from the same truth runs.
    pub pcrlb: bool,
    /// How the statistics are computed.
    pub method: Method,
    /// Seconds between checkpoints of a study (0: none; `None`: [`DEFAULT_CHECKPOINT_EVERY_S`]
    /// when the caller keeps checkpoints), else within [`CHECKPOINT_EVERY_RANGE_S`].
    pub checkpoint_every: Option<f64>,
}

impl Default for TradeOptions {
    fn default() -> Self {
        TradeOptions {
            filters: "ekf".into(),
            runs: None,
            seed: 1,
            threads: None,
            pcrlb: true,
            method: Method::Mc,
            checkpoint_every: None,
        }
    }
}

/// Check a checkpoint interval: 0 (off) or within [`CHECKPOINT_EVERY_RANGE_S`].
pub fn check_checkpoint_every(seconds: f64) -> Result<f64, OptionError> {
    let (lo, hi) = CHECKPOINT_EVERY_RANGE_S;
    if seconds == 0.0 || (lo..=hi).contains(&seconds) {
        Ok(seconds)
    } else {
        Err(OptionError::new(
            "checkpoint_every",
            seconds,
            format!("0 (no checkpoints) or from {lo} to {hi} s"),
        ))
    }
}

impl TradeOptions {
    /// Refuse an option outside its range, naming it.
    pub fn validate(&self) -> StudyResult<()> {
        if let Some(runs) = self.runs {
            check_count("runs", runs, 1, MAX_RUNS)?;
        }
        check_threads(self.threads)?;
        crate::options::filter_list("filters", &self.filters)?;
        if let Some(s) = self.checkpoint_every {
            check_checkpoint_every(s)?;
        }
        Ok(())
    }

    /// Refuse a method the mode has no meaning for, naming both, and a run count LinCov has no
    /// use for.
    pub fn check_mode(&self, mode: TradeMode) -> StudyResult<()> {
        let why = match (mode, self.method) {
            (_, Method::Mc) => None,
            (TradeMode::Study { resume: true }, _) => Some((
                "--resume",
                "only a Monte Carlo study is resumed; use --method mc",
            )),
            (TradeMode::Study { resume: false }, Method::Lincov) if self.runs.is_some() => Some((
                "--runs",
                "LinCov flies no runs; use --method both to compare",
            )),
            (TradeMode::Study { resume: false }, _) => None,
            (TradeMode::Grid, Method::Both) => {
                Some(("--grid", "a grid runs one method: mc or lincov"))
            }
            (TradeMode::Grid, _) => None,
            (TradeMode::Shard, _) => Some(("--shard", "LinCov is one pass, not sharded")),
            (TradeMode::Replay, _) => Some(("--replay-run", "a replay is one Monte Carlo run")),
        };
        match why {
            Some((flag, why)) => Err(self.refuse(flag, why)),
            None => Ok(()),
        }
    }

    /// `--method M with FLAG: WHY`.
    pub fn refuse(&self, flag: &str, why: &str) -> StudyError {
        StudyError::Refused(format!(
            "--method {} with {flag}: {why}",
            self.method.name()
        ))
    }

    /// The checkpoint interval of a study (s), `None` for none: `checkpoint_every` (0: none), by
    /// default [`DEFAULT_CHECKPOINT_EVERY_S`] when the summary goes to a file (`to_file`); an
    /// interval without such a file is refused.
    pub fn checkpoint_interval(&self, to_file: bool) -> StudyResult<Option<f64>> {
        match self.checkpoint_every {
            Some(s) => {
                check_checkpoint_every(s)?;
                if !to_file && s > 0.0 {
                    return Err(StudyError::Refused(format!(
                        "--checkpoint-every {s} needs --json FILE (the checkpoint is the partial \
                         summary written there)"
                    )));
                }
                Ok((s > 0.0).then_some(s))
            }
            None => Ok(to_file.then_some(DEFAULT_CHECKPOINT_EVERY_S)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_bound_names_its_option() {
        let bad = |o: TradeOptions| o.validate().unwrap_err().to_string();
        let runs = TradeOptions {
            runs: Some(0),
            ..TradeOptions::default()
        };
        assert_eq!(
            bad(runs),
            "runs = 0 is out of range: must be from 1 to 10000000"
        );
        let threads = TradeOptions {
            threads: Some(0),
            ..TradeOptions::default()
        };
        assert!(bad(threads).starts_with("threads = 0 is out of range"));
        for s in [-1.0, 0.01, 1e9, f64::NAN] {
            let o = TradeOptions {
                checkpoint_every: Some(s),
                ..TradeOptions::default()
            };
            let e = bad(o);
            assert!(
                e.starts_with("checkpoint_every = ") && e.contains("86400"),
                "{e}"
            );
        }
        assert!(TradeOptions::default().validate().is_ok());
    }

    #[test]
    fn a_method_without_meaning_for_the_mode_is_refused() {
        let lincov = TradeOptions {
            method: Method::Lincov,
            ..TradeOptions::default()
        };
        let e = lincov
            .check_mode(TradeMode::Study { resume: true })
            .unwrap_err();
        assert!(e.to_string().starts_with("--method lincov with --resume"));
        assert!(lincov.check_mode(TradeMode::Grid).is_ok());
        assert!(lincov.check_mode(TradeMode::Shard).is_err());
        let both = TradeOptions {
            method: Method::Both,
            ..TradeOptions::default()
        };
        assert!(both.check_mode(TradeMode::Grid).is_err());
        assert!(both.check_mode(TradeMode::Study { resume: false }).is_ok());
        let runs = TradeOptions {
            runs: Some(10),
            ..lincov
        };
        let e = runs.check_mode(TradeMode::Study { resume: false });
        assert!(e.unwrap_err().to_string().contains("--runs"));
        assert!(runs.check_mode(TradeMode::Grid).is_ok());
    }

    #[test]
    fn the_checkpoint_interval_needs_a_file() {
        let o = TradeOptions::default();
        assert_eq!(o.checkpoint_interval(true).unwrap(), Some(60.0));
        assert_eq!(o.checkpoint_interval(false).unwrap(), None);
        let every = TradeOptions {
            checkpoint_every: Some(5.0),
            ..TradeOptions::default()
        };
        let e = every.checkpoint_interval(false).unwrap_err().to_string();
        assert!(e.contains("needs --json FILE"), "{e}");
        let off = TradeOptions {
            checkpoint_every: Some(0.0),
            ..TradeOptions::default()
        };
        assert_eq!(off.checkpoint_interval(true).unwrap(), None);
    }
}
