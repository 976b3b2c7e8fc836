//! The options of an observability study (`entrynav observe`, Python `observe`), their defaults
//! (the command line's) and their bounds.

use crate::error::StudyResult;
use crate::options::{MAX_RUNS, check_count, real};
use entrynav::observability::Method;
use serde::{Deserialize, Deserializer};

/// Most truth runs the PCRLB averages over (`runs` with `pcrlb`).
pub const MAX_PCRLB_RUNS: usize = 100_000;

/// Shortest analysis step \[s\] (`step`); a step below the truth step is one truth step.
pub const MIN_STEP_S: f64 = 1e-3;

/// Longest analysis step \[s\] (`step`): the longest run a scenario may have.
pub const MAX_STEP_S: f64 = 7200.0;

/// What to analyse along the scenario's nominal trajectory.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObserveOptions {
    /// How the observability matrix is computed: `lie` (exact Lie derivatives, seed 002 eq. 12),
    /// `quadratic` (eq. 13-17) or `linear` (the linearisation, eq. 19).
    #[serde(deserialize_with = "method_by_name")]
    pub method: Method,
    /// Also analyse each IMU + one-beacon subsystem (seed 000 eq. 9, Fig. 3).
    pub subsystems: bool,
    /// Seconds between analysis points along the nominal truth trajectory.
    pub step: f64,
    /// The range Fisher information at every point (seed 002 eq. 27-28, 36-41, 54).
    pub fim: bool,
    /// With `fim`: only the scenario's first N range beacons, compared with the best geometry of
    /// N free beacons (seed 002 Table 1).
    pub beacons: Option<usize>,
    /// Also the posterior Cramér–Rao lower bound over `runs` truth runs, without a filter.
    pub pcrlb: bool,
    /// With `pcrlb`: truth runs the bound averages over.
    pub runs: usize,
    /// With `pcrlb`: master seed of the truth runs (the runs a `trade` with this seed flies).
    pub seed: u64,
}

impl Default for ObserveOptions {
    fn default() -> Self {
        ObserveOptions {
            method: Method::Lie,
            subsystems: false,
            step: 1.0,
            fim: false,
            beacons: None,
            pcrlb: false,
            runs: 100,
            seed: 1,
        }
    }
}

impl ObserveOptions {
    /// Refuse an option outside its range, naming it.
    pub fn validate(&self) -> StudyResult<()> {
        real("step", self.step, MIN_STEP_S, MAX_STEP_S)?;
        let most_runs = if self.pcrlb { MAX_PCRLB_RUNS } else { MAX_RUNS };
        check_count("runs", self.runs, 1, most_runs)?;
        Ok(())
    }
}

/// A [`Method`] by its name (`lie`, `quadratic`, `linear`), as the command line spells it.
fn method_by_name<'de, D: Deserializer<'de>>(d: D) -> Result<Method, D::Error> {
    let name = String::deserialize(d)?;
    name.parse().map_err(serde::de::Error::custom)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_step_and_the_runs_are_bounded_and_named() {
        let ok = ObserveOptions::default();
        assert!(ok.validate().is_ok());
        let step = ObserveOptions {
            step: 0.0,
            ..ok.clone()
        };
        assert_eq!(
            step.validate().unwrap_err().to_string(),
            "step = 0 is out of range: must be a number from 0.001 to 7200"
        );
        let nan = ObserveOptions {
            step: f64::NAN,
            ..ok.clone()
        };
        assert!(
            nan.validate()
                .unwrap_err()
                .to_string()
                .starts_with("step = NaN")
        );
        let runs = ObserveOptions {
            pcrlb: true,
            runs: 100_001,
            ..ok.clone()
        };
        assert_eq!(
            runs.validate().unwrap_err().to_string(),
            "runs = 100001 is out of range: must be from 1 to 100000"
        );
        let zero = ObserveOptions { runs: 0, ..ok };
        assert!(zero.validate().is_err());
    }

    #[test]
    fn the_method_is_given_by_its_name() {
        let o: ObserveOptions =
            serde_json::from_str(r#"{"method": "quadratic", "fim": true}"#).unwrap();
        assert_eq!((o.method, o.fim), (Method::Quadratic, true));
        let e = serde_json::from_str::<ObserveOptions>(r#"{"method": "exact"}"#).unwrap_err();
        assert!(
            e.to_string()
                .contains("unknown observability method 'exact'"),
            "{e}"
        );
    }
}
