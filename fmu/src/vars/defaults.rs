//! The default parameters of the generic FMUs (scenario, filter, seed) and of the guidance and
//! guided FMUs (scenario file, filter).

/// Default parameter values.
pub const DEFAULT_SCENARIO: &str = "four-beacon-fusion";
/// Default filter.
pub const DEFAULT_FILTER: &str = "dcifaif";
/// Default seed.
pub const DEFAULT_SEED: i32 = 1;

/// The scenario file (in every generic FMU's `resources/`, as every built-in is) that the
/// guidance FMU's `scenario` parameter names by default: the built-in `msl-guided` (`msl-airdata`
/// with Apollo final-phase guidance on the 45° reference, the Mars 2020 range trigger at 450 m/s and
/// a 7 km altitude safeguard).
pub const GUIDED_SCENARIO_FILE: &str = "msl-guided.toml";

/// The default filter of the guided FMU `MarsEntryNavGuided` (one that fits its default
/// scenario, which has no radio beacons).
pub const GUIDED_FILTER: &str = "ekf";
