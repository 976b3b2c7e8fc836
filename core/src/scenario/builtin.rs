//! The built-in scenarios, embedded from this crate's `scenarios/` folder (`core/scenarios/`, inside the crate so that `cargo package` carries them).

/// Names of the built-in scenarios, in listing order.
pub const BUILTIN_NAMES: [&str; 12] = [
    "four-beacon-fusion",
    "four-beacon-fusion-fault",
    "four-beacon-fusion-faults",
    "four-beacon-fusion-paper",
    "msl-airdata",
    "msl-airdata-paper",
    "ground-beacons-3",
    "orbiters-3",
    "msl-pressure",
    "msl-pressure-orbiter",
    "msl-guided",
    "four-beacon-fusion-guided",
];

/// TOML text of a built-in scenario, if `name` is one.
pub fn builtin_toml(name: &str) -> Option<&'static str> {
    Some(match name {
        "four-beacon-fusion" => include_str!("../../scenarios/four-beacon-fusion.toml"),
        "four-beacon-fusion-fault" => {
            include_str!("../../scenarios/four-beacon-fusion-fault.toml")
        }
        "four-beacon-fusion-faults" => {
            include_str!("../../scenarios/four-beacon-fusion-faults.toml")
        }
        "four-beacon-fusion-paper" => {
            include_str!("../../scenarios/four-beacon-fusion-paper.toml")
        }
        "msl-airdata" => include_str!("../../scenarios/msl-airdata.toml"),
        "msl-airdata-paper" => include_str!("../../scenarios/msl-airdata-paper.toml"),
        "ground-beacons-3" => include_str!("../../scenarios/ground-beacons-3.toml"),
        "orbiters-3" => include_str!("../../scenarios/orbiters-3.toml"),
        "msl-pressure" => include_str!("../../scenarios/msl-pressure.toml"),
        "msl-pressure-orbiter" => include_str!("../../scenarios/msl-pressure-orbiter.toml"),
        "msl-guided" => include_str!("../../scenarios/msl-guided.toml"),
        "four-beacon-fusion-guided" => {
            include_str!("../../scenarios/four-beacon-fusion-guided.toml")
        }
        _ => return None,
    })
}
