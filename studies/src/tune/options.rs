//! The options of a tuning study (`entrynav tune`, Python `tune`), their defaults (the command
//! line's) and their bounds.

use crate::error::StudyResult;
use crate::options::{check_count, check_threads};
use crate::tune::search::{TuneObjective, TuneOptions};

/// Most runs of the tuning set and of the validation set (`runs`, `validation_runs`): every
/// evaluation of the search flies every filter over all the tuning runs, kept in memory.
pub const MAX_TUNING_RUNS: usize = 100_000;

/// Largest evaluation budget of the search (`max_evaluations`): each evaluation is a Monte Carlo
/// over the tuning runs.
pub const MAX_EVALUATIONS: usize = 100_000;

/// What to tune and how.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TuneStudyOptions {
    /// Filter(s) to make consistent, comma-separated: each is tuned on its own and gets its own
    /// `[filter.tuned.<name>]` (`--filter`).
    pub filters: String,
    /// Monte Carlo runs of the tuning set (common random numbers: every evaluation sees them).
    pub runs: usize,
    /// Master seed of the tuning runs (the validation runs use a different one).
    pub seed: u64,
    /// Runs of the fresh validation set.
    pub validation_runs: usize,
    /// Tune on innovations alone (ANIS/dof -> 1): what a flight team has without the truth.
    pub nis_only: bool,
    /// Also tune a factor on the assumed measurement noise per channel kind.
    pub tune_noise: bool,
    /// Evaluation budget of the search, per filter.
    pub max_evaluations: usize,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Give the tuned file even when a primary figure is worse than the input's on the fresh
    /// validation runs beyond the Monte Carlo noise (position RMSE, failed or diverged runs,
    /// |ln ANEES/dof|, |ln ANIS/dof|).
    pub force: bool,
}

impl Default for TuneStudyOptions {
    fn default() -> Self {
        TuneStudyOptions {
            filters: "ekf".into(),
            runs: 24,
            seed: 1,
            validation_runs: 100,
            nis_only: false,
            tune_noise: false,
            max_evaluations: 150,
            threads: None,
            force: false,
        }
    }
}

impl TuneStudyOptions {
    /// Refuse an option outside its range, naming it.
    pub fn validate(&self) -> StudyResult<()> {
        check_count("runs", self.runs, 1, MAX_TUNING_RUNS)?;
        check_count("validation_runs", self.validation_runs, 1, MAX_TUNING_RUNS)?;
        check_count("max_evaluations", self.max_evaluations, 1, MAX_EVALUATIONS)?;
        check_threads(self.threads)?;
        crate::options::filter_list("filters", &self.filters)?;
        Ok(())
    }

    /// The objective the search minimises.
    pub fn objective(&self) -> TuneObjective {
        if self.nis_only {
            TuneObjective::NisOnly
        } else {
            TuneObjective::NeesAndNis
        }
    }

    /// The search's own options.
    pub fn search(&self) -> TuneOptions {
        TuneOptions {
            objective: self.objective(),
            max_evaluations: self.max_evaluations,
            ..Default::default()
        }
    }

    /// Seed of the validation runs: a different study than the tuning runs.
    pub fn validation_seed(&self) -> u64 {
        self.seed.wrapping_add(0x5EED_0000_0000_0001)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_count_is_bounded_and_named() {
        let ok = TuneStudyOptions::default();
        assert!(ok.validate().is_ok());
        let cases = [
            (
                TuneStudyOptions {
                    runs: 0,
                    ..ok.clone()
                },
                "runs = 0 is out of range: must be from 1 to 100000",
            ),
            (
                TuneStudyOptions {
                    validation_runs: 100_001,
                    ..ok.clone()
                },
                "validation_runs = 100001 is out of range: must be from 1 to 100000",
            ),
            (
                TuneStudyOptions {
                    max_evaluations: 0,
                    ..ok.clone()
                },
                "max_evaluations = 0 is out of range: must be from 1 to 100000",
            ),
            (
                TuneStudyOptions {
                    threads: Some(0),
                    ..ok.clone()
                },
                "threads = 0 is out of range: must be from 1 to 1024",
            ),
        ];
        for (options, message) in cases {
            assert_eq!(options.validate().unwrap_err().to_string(), message);
        }
    }

    #[test]
    fn keyword_arguments_build_the_options_and_unknown_ones_are_refused() {
        let o: TuneStudyOptions =
            serde_json::from_str(r#"{"filters": "ekf,ukf", "runs": 6, "nis_only": true}"#).unwrap();
        assert_eq!(
            (o.filters.as_str(), o.runs, o.nis_only),
            ("ekf,ukf", 6, true)
        );
        assert_eq!(o.validation_runs, 100);
        assert!(serde_json::from_str::<TuneStudyOptions>(r#"{"run": 6}"#).is_err());
    }
}
