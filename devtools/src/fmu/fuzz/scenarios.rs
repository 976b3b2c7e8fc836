//! [`Scenarios`]: what the model needs to know of every scenario an instance may be given.

use anyhow::Result;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use entrynav::sim::guided::accel_slots;
use entrynav_fmu::vars::{GUIDED_SCENARIO_FILE, Specific, guided_scenario};
use std::collections::HashMap;
use std::sync::Arc;

/// Scenario timing and which filters fit, per built-in scenario, the guided scenario file and
/// the embedded scenario of a specific FMU.
pub(super) struct Scenarios {
    /// (duration, the filter's step) by scenario name.
    pub(super) timing: HashMap<String, (f64, f64)>,
    /// The filters that fit, by scenario name.
    pub(super) fits: HashMap<String, Vec<&'static str>>,
    /// The scenarios the guided FMU can fly (a `[guidance]` section and the accelerometers).
    pub(super) guided: Vec<String>,
}

impl Scenarios {
    /// The built-in scenarios, the guided scenario file, and the embedded scenario of a
    /// specific FMU.
    pub(super) fn new(specific: Option<&Specific>) -> Result<Scenarios> {
        let mut all = Vec::new();
        for name in BUILTIN_NAMES {
            let s = Scenario::build(ScenarioConfig::builtin(name)?, &entrynav::files::no_files)?;
            all.push((name.to_string(), Arc::new(s)));
        }
        if let Some(sp) = specific {
            all.push((sp.scenario.config.name.clone(), Arc::clone(&sp.scenario)));
        }
        // The guided scenario file every generic FMU ships (the default of the guided models).
        all.push((
            GUIDED_SCENARIO_FILE.to_string(),
            Arc::new(guided_scenario()?),
        ));
        let (mut timing, mut fits, mut guided) = (HashMap::new(), HashMap::new(), Vec::new());
        for (name, s) in all {
            if s.config.guidance.is_some() && accel_slots(&s.onboard).is_some() {
                guided.push(name.clone());
            }
            let t = &s.config.timing;
            timing.insert(name.clone(), (t.duration_s, s.onboard.filter_step_s));
            let ok: Vec<&'static str> = FilterKind::ALL
                .into_iter()
                .filter(|k| k.misfit(&s.onboard).is_none())
                .map(FilterKind::name)
                .collect();
            fits.insert(name, ok);
        }
        Ok(Scenarios {
            timing,
            fits,
            guided,
        })
    }
}
