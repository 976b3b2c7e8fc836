//! What produced a trade JSON: the `provenance` block (version, commit, command line, overrides,
//! scenario fingerprint, atmosphere source) and the `timing` block, the only part of a summary
//! that is not reproducible. Everything outside `timing` is byte-identical across thread counts
//! and repeats of the same command (and outside `provenance.command_line` when only `--threads`
//! differs).

use entrynav::sim::TradeReport;
use serde::Serialize;
use std::collections::BTreeMap;

/// Where a summary came from.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    /// Version of the `entrynav` crate that wrote the file.
    pub version: &'static str,
    /// `git rev-parse HEAD` at build time; `null` when the binary was not built in a git checkout.
    pub git_commit: Option<&'static str>,
    /// The command line, program name first.
    pub command_line: Vec<String>,
    /// The `--set PATH=VALUE` overrides, in the order given.
    pub overrides: Vec<String>,
    /// FNV-1a 64 of the resolved scenario's canonical TOML (after overrides and atmosphere
    /// options), as in shard files; `null` where several scenarios contribute (grids).
    pub scenario_fingerprint: Option<String>,
    /// The truth atmosphere: `--atmosphere-file` if given, the scenario's truth model, and
    /// whether the per-run perturbation is on.
    pub atmosphere: Option<serde_json::Value>,
    /// The resolved scenario (every field, after overrides), so that `trade compare` can say what
    /// differs between two studies; absent where several scenarios contribute (grids).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scenario: Option<serde_json::Value>,
}

impl Provenance {
    /// The provenance of a study run by `command_line` (program name first) with these
    /// overrides.
    pub fn new(command_line: Vec<String>, overrides: &[String]) -> Provenance {
        Provenance {
            version: env!("CARGO_PKG_VERSION"),
            git_commit: option_env!("ENTRYNAV_GIT_COMMIT"),
            command_line,
            overrides: overrides.to_vec(),
            scenario_fingerprint: None,
            atmosphere: None,
            scenario: None,
        }
    }

    /// Fill in the scenario's fingerprint and atmosphere source.
    pub fn with_scenario(
        mut self,
        scenario: &entrynav::scenario::Scenario,
        atmosphere_file: Option<&std::path::Path>,
    ) -> Provenance {
        self.scenario_fingerprint = Some(entrynav::sim::monte_carlo::shard::scenario_fingerprint(
            scenario,
        ));
        self.scenario = serde_json::to_value(&scenario.config).ok();
        let truth = &scenario.config.truth;
        self.atmosphere = Some(serde_json::json!({
            "file": atmosphere_file.map(|p| p.display().to_string()),
            "truth": serde_json::to_value(&truth.atmosphere).unwrap_or(serde_json::Value::Null),
            "perturbation": truth.perturbation.is_some(),
        }));
        self
    }
}

/// Wall-clock measurements (not reproducible).
#[derive(Debug, Clone, Serialize)]
pub struct Timing {
    /// Wall time of the study (s) (0 for a merge).
    pub wall_s: f64,
    /// Mean CPU time per filter step (µs), per filter.
    pub us_per_step: BTreeMap<String, f64>,
}

impl Timing {
    /// The timing of `report` run in `wall_s` seconds.
    pub fn of(report: &TradeReport, wall_s: f64) -> Timing {
        Timing {
            wall_s,
            us_per_step: report
                .filters
                .iter()
                .map(|f| (f.name.clone(), f.us_per_step))
                .collect(),
        }
    }
}

/// A trade summary as written to `--json`: provenance, the report, timing.
#[derive(Serialize)]
pub struct Summary<'a> {
    /// Where it came from.
    pub provenance: &'a Provenance,
    /// The statistics.
    #[serde(flatten)]
    pub report: &'a TradeReport,
    /// Only in a partial summary: the finished blocks' sums (a single-process shard file, CPU
    /// timings included), from which `trade --resume FILE` continues.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resume: Option<&'a entrynav::sim::ShardResult>,
    /// Only beside `resume`: its checksum (`trade::resume::resume_checksum`), checked by `--resume`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resume_checksum: Option<String>,
    /// Only with `trade --method both`: LinCov of each filter beside the Monte Carlo
    /// (`trade::lincov_comparison::Comparison`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lincov: Option<&'a serde_json::Value>,
    /// Only for a scenario with `[guidance]`: delivery at deployment with each filter in the
    /// guidance loop, perfect navigation and the unguided reference bank (`entrynav::sim::guided::delivery`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delivery: Option<&'a entrynav::sim::guided::delivery::DeliveryReport>,
    /// Wall-clock timing.
    pub timing: Timing,
}
