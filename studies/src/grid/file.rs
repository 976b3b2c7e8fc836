//! A grid file (`trade --grid FILE.toml`): scenarios × variations × filters in one study.
//!
//! ```toml
//! name = "beacon-study"          # report name
//! runs = 200                     # Monte Carlo runs per cell
//! seed = 1
//! filters = ["ekf", "dcifaif"]   # filters that do not fit a cell are listed as refused
//! scenarios = ["four-beacon-fusion", "my-scenario.toml"]
//!
//! [variations]                   # every list multiplies the grid; omitted = no variation
//! beacons = [2, 3, 4]            # keep the first N beacons
//! beacon_fault = [false, true]   # the last beacon goes silent at fault_time_s (default 2/3 of the entry)
//! fault_time_s = 200.0
//! perturbation_scale = [0.0, 1.0] # scale of the truth density perturbation (adds the default one if absent)
//! noise_scale = [1.0, 2.0]       # multiplies every sensor noise (and the filters' assumed noise)
//! beacon_files = ["opt.toml"]    # take the [[beacons]] of these scenario files (e.g. optimizer output)
//! ```

use crate::error::{StudyError, StudyResult};
use crate::options::{check_count, runs};
use serde::Deserialize;

/// Most cells a grid may have (scenarios × every variation list).
pub const MAX_CELLS: usize = 100_000;

/// A grid file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridFile {
    /// Report name.
    pub name: String,
    /// Runs per cell.
    pub runs: usize,
    /// Master seed (every cell uses it).
    #[serde(default = "one")]
    pub seed: u64,
    /// Filter names.
    pub filters: Vec<String>,
    /// Scenario names or files (relative to the grid file).
    pub scenarios: Vec<String>,
    /// Variations.
    #[serde(default)]
    pub variations: Variations,
}

fn one() -> u64 {
    1
}

/// Variation axes of a grid.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Variations {
    /// Keep the first N beacons.
    #[serde(default)]
    pub beacons: Vec<usize>,
    /// Last beacon silent from `fault_time_s` on.
    #[serde(default)]
    pub beacon_fault: Vec<bool>,
    /// Fault time (s) (default: 2/3 of the duration).
    #[serde(default)]
    pub fault_time_s: Option<f64>,
    /// Density perturbation scale.
    #[serde(default)]
    pub perturbation_scale: Vec<f64>,
    /// Measurement-noise scale.
    #[serde(default)]
    pub noise_scale: Vec<f64>,
    /// Beacon sets from scenario files.
    #[serde(default)]
    pub beacon_files: Vec<String>,
}

impl GridFile {
    /// Parse and check a grid file's text: `runs` from 1 to `MAX_RUNS`, at most [`MAX_CELLS`]
    /// cells. Messages do not name the file (the caller adds it).
    pub fn from_toml(text: &str) -> StudyResult<GridFile> {
        let grid: GridFile =
            toml::from_str(text).map_err(|e| StudyError::Refused(e.to_string()))?;
        runs("runs", grid.runs as i128)?;
        check_count("cells", grid.cells(), 0, MAX_CELLS)?;
        Ok(grid)
    }

    /// The number of cells: scenarios × each variation list's length (1 where omitted),
    /// saturating.
    pub fn cells(&self) -> usize {
        let v = &self.variations;
        [
            v.beacon_files.len(),
            v.beacons.len(),
            v.beacon_fault.len(),
            v.perturbation_scale.len(),
            v.noise_scale.len(),
        ]
        .iter()
        .fold(self.scenarios.len(), |n, &k| n.saturating_mul(k.max(1)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_and_cells_are_bounded_naming_the_option() {
        let base = "name = \"g\"\nfilters = [\"ekf\"]\nscenarios = [\"orbiters-3\"]\n";
        let e = GridFile::from_toml(&format!("{base}runs = 0\n"))
            .unwrap_err()
            .to_string();
        assert_eq!(e, "runs = 0 is out of range: must be from 1 to 10000000");
        let huge = format!(
            "{base}runs = 2\n[variations]\nbeacons = [{}]\nnoise_scale = [{}]\n",
            vec!["1"; 1000].join(","),
            vec!["1.0"; 1000].join(",")
        );
        let e = GridFile::from_toml(&huge).unwrap_err().to_string();
        assert!(e.starts_with("cells = 1000000 is out of range"), "{e}");
        let g = GridFile::from_toml(&format!("{base}runs = 3\n")).unwrap();
        assert_eq!((g.cells(), g.seed), (1, 1));
    }
}
