//! `entrynav._entrynav`: the native half of the Python package (the typed API is the pure
//! Python `entrynav/__init__.py` over it).
//!
//! Every function is a study of the study layer (`entrynav-studies`), the same functions the
//! `entrynav` command calls: a scenario crosses the boundary as its TOML text and folder
//! ([`scenario`]), a study's options as keyword arguments checked by the study layer
//! ([`options`]), results as the JSON the command line writes. Studies run with the GIL
//! released; a trade is watched ([`watch`]) so Ctrl-C and a progress callback reach it. Errors
//! become Python exceptions by their kind ([`errors`]); a panic is caught and becomes
//! `RuntimeError`. This crate links neither the command line nor an FMI host.

mod errors;
mod keywords;
mod options;
mod scenario;
mod series;
mod studies;
mod trade;
mod watch;

use pyo3::prelude::*;

/// The version of the library.
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

/// The native module.
#[pymodule]
fn _entrynav(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(scenario::builtin_scenarios, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::resolve_scenario, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::apply_sets, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::scenario_json, m)?)?;
    m.add_function(wrap_pyfunction!(trade::trade, m)?)?;
    m.add_function(wrap_pyfunction!(trade::trade_shard, m)?)?;
    m.add_class::<trade::NativeTrade>()?;
    m.add_function(wrap_pyfunction!(studies::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(studies::tune, m)?)?;
    m.add_function(wrap_pyfunction!(studies::observe, m)?)?;
    m.add_function(wrap_pyfunction!(studies::deliver, m)?)?;
    m.add_function(wrap_pyfunction!(studies::optimize_ground, m)?)?;
    m.add_function(wrap_pyfunction!(studies::optimize_select, m)?)?;
    m.add_function(wrap_pyfunction!(studies::optimize_orbiters, m)?)?;
    m.add_function(wrap_pyfunction!(studies::fmu_pack, m)?)?;
    m.add_function(wrap_pyfunction!(keywords::keywords, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    Ok(())
}
