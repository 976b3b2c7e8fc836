//! [`apply_overrides`]: `--set PATH=VALUE` edits of a scenario in TOML syntax, re-validated.

use crate::error::LoadError;
use entrynav::scenario::ScenarioConfig;

/// Apply `--set path=value` overrides (TOML dotted path, TOML value syntax) to a scenario and
/// re-validate it, e.g. `truth.density_bias=0.095` or `dispersions.density_bias=0`; a numeric
/// key indexes an array: `beacons.0.lat_deg=3.0`, `filter.q_diag.3=1e-6`. A value that
/// is not valid TOML is taken as a string.
pub fn apply_overrides(cfg: ScenarioConfig, sets: &[String]) -> Result<ScenarioConfig, LoadError> {
    if sets.is_empty() {
        return Ok(cfg);
    }
    let mut doc: toml::Table =
        toml::from_str(&cfg.to_toml_string()).map_err(|source| LoadError::OverrideParse {
            sets: sets.join(" "),
            source,
        })?;
    for set in sets {
        let bad = |reason: String| LoadError::Override {
            set: set.clone(),
            reason,
        };
        let (path, value) = set
            .split_once('=')
            .ok_or_else(|| bad("expected PATH=VALUE, e.g. truth.density_bias=0.095".to_string()))?;
        let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {value}")) {
            Ok(mut t) => t
                .remove("v")
                .unwrap_or(toml::Value::String(value.to_string())),
            Err(_) => toml::Value::String(value.to_string()),
        };
        let keys: Vec<&str> = path.trim().split('.').collect();
        let (last, parents) = keys
            .split_last()
            .ok_or_else(|| bad("empty path".to_string()))?;
        // A numeric key indexes an array (`beacons.0.lat_deg`, `filter.q_diag.3`).
        if let Some((first, rest)) = parents.split_first() {
            let mut slot: &mut toml::Value = doc
                .entry(first.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            for k in rest.iter().chain(std::iter::once(last)) {
                slot = match slot {
                    toml::Value::Array(items) => {
                        let n = items.len();
                        let i: usize = k.parse().map_err(|_| {
                            bad(format!("'{k}' is not an index of an array of {n} entries"))
                        })?;
                        items.get_mut(i).ok_or_else(|| {
                            bad(format!(
                                "index {i} is past the array's {n} entries (0 to {})",
                                n.saturating_sub(1)
                            ))
                        })?
                    }
                    toml::Value::Table(t) => t
                        .entry(k.to_string())
                        .or_insert_with(|| toml::Value::Table(toml::Table::new())),
                    _ => return Err(bad(format!("cannot reach '{k}': its parent is a value"))),
                };
            }
            *slot = value;
        } else {
            doc.insert(last.to_string(), value);
        }
        // A value of the wrong type or an unknown field is this argument's fault: say so, not
        // "line 96, column 16" of a document the user never wrote.
        if let Err(e) = toml::Value::Table(doc.clone()).try_into::<ScenarioConfig>() {
            return Err(bad(e.message().trim_end().to_string()));
        }
    }
    let text = toml::to_string(&doc).map_err(|source| LoadError::OverrideWrite {
        sets: sets.join(" "),
        source,
    })?;
    Ok(ScenarioConfig::from_toml_str(
        &text,
        "scenario with --set overrides",
    )?)
}
