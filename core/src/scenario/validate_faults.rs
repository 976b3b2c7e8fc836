//! Checks of `[[faults]]`: each fault names a beacon of the scenario, needs the sensor it acts
//! on, and keeps its times, probabilities and sizes finite and in range.

use super::config::ScenarioConfig;
use super::error::ScenarioError;
use super::validate_range::R;
use super::validate_range::{Checker, Range};
use crate::sensors::FaultConfig;

impl ScenarioConfig {
    /// `[[faults]]`.
    pub(super) fn check_faults(&self, c: &mut Checker) -> R {
        let start = || Range::ge(0.0).le(1e6).unit("s");
        let probability = || Range::ge(0.0).le(1.0);
        for (i, fault) in self.faults.iter().enumerate() {
            let f = |name: &str| format!("faults[{i}].{name}");
            if let Some(name) = fault.beacon()
                && !self.beacons.iter().any(|b| b.name() == name)
            {
                let known: Vec<&str> = self.beacons.iter().map(|b| b.name()).collect();
                return Err(ScenarioError::invalid(
                    f("beacon"),
                    format!(
                        "'{name}' is not a beacon of this scenario (beacons: {})",
                        known.join(", ")
                    ),
                ));
            }
            let needs_range = matches!(
                fault,
                FaultConfig::RangeBias { .. }
                    | FaultConfig::RangeStuck { .. }
                    | FaultConfig::RangeOutliers { .. }
            );
            if needs_range && self.sensors.range.is_none() {
                return Err(ScenarioError::invalid(
                    f("kind"),
                    format!(
                        "a '{}' fault needs range measurements ([sensors.range])",
                        fault.kind()
                    ),
                ));
            }
            if !needs_range && self.sensors.imu.is_none() {
                return Err(ScenarioError::invalid(
                    f("kind"),
                    format!(
                        "an '{}' fault needs an accelerometer ([sensors.imu])",
                        fault.kind()
                    ),
                ));
            }
            match fault {
                FaultConfig::RangeBias {
                    start_s,
                    bias_m,
                    drift_mps,
                    ..
                } => {
                    c.range(f("start_s"), *start_s, start())?;
                    c.range(f("bias_m"), *bias_m, Range::within(1e7).unit("m"))?;
                    c.range(f("drift_mps"), *drift_mps, Range::within(1e4).unit("m/s"))?;
                }
                FaultConfig::RangeStuck { start_s, .. } => {
                    c.range(f("start_s"), *start_s, start())?;
                }
                FaultConfig::RangeOutliers {
                    start_s,
                    probability: p,
                    size_m,
                    ..
                } => {
                    c.range(f("start_s"), *start_s, start())?;
                    c.range(f("probability"), *p, probability())?;
                    c.range(f("size_m"), *size_m, Range::ge(0.0).le(1e7).unit("m"))?;
                }
                FaultConfig::AccelBias { start_s, bias_mps2 } => {
                    c.range(f("start_s"), *start_s, start())?;
                    for (k, b) in bias_mps2.iter().enumerate() {
                        c.range(
                            f(&format!("bias_mps2[{k}]")),
                            *b,
                            Range::within(100.0).unit("m/s²"),
                        )?;
                    }
                }
                FaultConfig::AccelSpikes {
                    start_s,
                    probability: p,
                    size_mps2,
                } => {
                    c.range(f("start_s"), *start_s, start())?;
                    c.range(f("probability"), *p, probability())?;
                    c.range(
                        f("size_mps2"),
                        *size_mps2,
                        Range::ge(0.0).le(1000.0).unit("m/s²"),
                    )?;
                }
            }
        }
        Ok(())
    }
}
