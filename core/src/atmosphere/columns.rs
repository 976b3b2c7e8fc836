//! Column naming of density tables: which header names hold height, density and radius.

use serde::{Deserialize, Serialize};

/// Unit of the height column of a table.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum HeightUnit {
    /// Kilometres (Mars-GRAM's `Height(km)` / `Hgtkm` / `Var_X` / `HgtMOLA`).
    #[default]
    Km,
    /// Metres.
    M,
}

impl HeightUnit {
    /// Metres per unit.
    pub fn to_metres(self) -> f64 {
        match self {
            HeightUnit::Km => 1_000.0,
            HeightUnit::M => 1.0,
        }
    }

    /// `km` or `m`.
    pub fn symbol(self) -> &'static str {
        match self {
            HeightUnit::Km => "km",
            HeightUnit::M => "m",
        }
    }
}

impl std::fmt::Display for HeightUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.symbol())
    }
}

/// Height names tried, in order, when the height name is left at its default `height`:
/// `height`, Mars-GRAM's `Hgtkm`, `Var_X` (Monte Carlo output, where X is height),
/// `HgtMOLA` (height above the MOLA areoid), then common spellings.
pub const HEIGHT_ALIASES: [&str; 8] = [
    "height",
    "hgtkm",
    "var_x",
    "hgtmola",
    "height_km",
    "altitude_km",
    "alt_km",
    "altitude",
];

/// Density names tried, in order, when the density name is left at its default `denstot`.
/// Densities must be in kg/m³ (as Mars-GRAM's `DENSTOT`/`Denavg` are).
pub const DENSITY_ALIASES: [&str; 5] = ["denstot", "density", "rho", "denavg", "density_kgm3"];

/// Radius names looked for when no radius column is named: a planet-centred radius in km
/// (Mars-GRAM's `Radius`). When found, rows are placed by radius, not by height.
pub const RADIUS_ALIASES: [&str; 3] = ["radius", "radius_km", "radkm"];

/// Which columns of a table hold height, density and (optionally) radius, and the height unit.
///
/// Column names match header names case-insensitively, either exactly or after removing a
/// parenthesised or bracketed unit suffix: `height` matches `Height(km)` and `HEIGHT (km)`.
/// When a name is left at its default (`height`, `denstot`) and is not found, the aliases
/// [`HEIGHT_ALIASES`] / [`DENSITY_ALIASES`] are tried in order; an explicit name gets no aliases.
/// If the chosen height header declares a unit (`(km)`, `(m)`, `..._km`, `Hgtkm`) that differs
/// from `height_unit`, parsing fails instead of silently scaling by 1000.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableColumns {
    /// Header name of the height column.
    pub height: String,
    /// Header name of the density column (kg/m³).
    pub density: String,
    /// Header name of the radius column (km, planet-centred); `None`: use one of
    /// [`RADIUS_ALIASES`] if the header has it.
    pub radius: Option<String>,
    /// Unit of the height column.
    pub height_unit: HeightUnit,
}

impl Default for TableColumns {
    fn default() -> Self {
        TableColumns {
            height: "height".to_string(),
            density: "denstot".to_string(),
            radius: None,
            height_unit: HeightUnit::Km,
        }
    }
}

impl TableColumns {
    /// Defaults overridden by the given names (scenario fields, CLI flags).
    pub fn named(
        height: Option<&str>,
        density: Option<&str>,
        height_unit: Option<HeightUnit>,
    ) -> TableColumns {
        let d = TableColumns::default();
        TableColumns {
            height: height.map_or(d.height, str::to_string),
            density: density.map_or(d.density, str::to_string),
            radius: None,
            height_unit: height_unit.unwrap_or(d.height_unit),
        }
    }
}

/// Split a header name into (base name, unit text) at a trailing `(...)` or `[...]`.
pub(crate) fn split_unit(name: &str) -> (&str, Option<&str>) {
    let name = name.trim();
    for (open, close) in [('(', ')'), ('[', ']')] {
        if let Some(body) = name.strip_suffix(close) {
            if let Some(pos) = body.rfind(open) {
                return (
                    body[..pos].trim(),
                    Some(body[pos + open.len_utf8()..].trim()),
                );
            }
        }
    }
    (name, None)
}

pub(crate) fn header_matches(header: &str, want: &str) -> bool {
    let want = want.trim();
    header.trim().eq_ignore_ascii_case(want) || split_unit(header).0.eq_ignore_ascii_case(want)
}

/// Unit declared by a height header, if recognisable.
pub(crate) fn declared_unit(header: &str) -> Option<HeightUnit> {
    let (base, unit) = split_unit(header);
    if let Some(u) = unit {
        return match u.to_ascii_lowercase().as_str() {
            "km" => Some(HeightUnit::Km),
            "m" => Some(HeightUnit::M),
            _ => None,
        };
    }
    let b = base.to_ascii_lowercase();
    if b.ends_with("km") {
        Some(HeightUnit::Km)
    } else if b.ends_with("_m") {
        Some(HeightUnit::M)
    } else {
        None
    }
}

/// Find a column: the requested name, then (only if it is the default) the aliases. `Err`
/// lists every name tried.
pub(crate) fn find_column(
    header: &[&str],
    requested: &str,
    default: &str,
    aliases: &[&str],
) -> Result<usize, Vec<String>> {
    let mut tried = vec![requested.to_string()];
    if let Some(i) = header.iter().position(|h| header_matches(h, requested)) {
        return Ok(i);
    }
    if !default.is_empty() && requested.trim().eq_ignore_ascii_case(default) {
        for alias in aliases {
            if !tried.iter().any(|t| t.eq_ignore_ascii_case(alias)) {
                tried.push((*alias).to_string());
            }
            if let Some(i) = header.iter().position(|h| header_matches(h, alias)) {
                return Ok(i);
            }
        }
    }
    Err(tried)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_suffixes_are_split() {
        assert_eq!(split_unit("Height(km)"), ("Height", Some("km")));
        assert_eq!(split_unit(" HEIGHT [m] "), ("HEIGHT", Some("m")));
        assert_eq!(split_unit("DENSTOT"), ("DENSTOT", None));
        assert_eq!(split_unit(")"), (")", None));
        assert!(header_matches("Height(km)", "height"));
        assert!(header_matches("Height(km)", "HEIGHT(KM)"));
        assert!(!header_matches("Heights", "height"));
        assert_eq!(declared_unit("Hgtkm"), Some(HeightUnit::Km));
        assert_eq!(declared_unit("alt_m"), Some(HeightUnit::M));
        assert_eq!(declared_unit("Height(m)"), Some(HeightUnit::M));
        assert_eq!(declared_unit("altitude"), None);
        assert_eq!(declared_unit("Var_X"), None);
    }

    #[test]
    fn gram_names_are_found_in_any_order() {
        let h = ["DENSLO", "DENSTOT", "Radius", "Var_X", "RadAU"];
        assert_eq!(find_column(&h, "height", "height", &HEIGHT_ALIASES), Ok(3));
        assert_eq!(
            find_column(&h, "denstot", "denstot", &DENSITY_ALIASES),
            Ok(1)
        );
        assert_eq!(find_column(&h, "radius", "radius", &RADIUS_ALIASES), Ok(2));
        let m = ["Time", "HgtMOLA", "Denavg"];
        assert_eq!(find_column(&m, "height", "height", &HEIGHT_ALIASES), Ok(1));
        assert_eq!(
            find_column(&m, "denstot", "denstot", &DENSITY_ALIASES),
            Ok(2)
        );
        // An explicit name gets no aliases.
        assert_eq!(
            find_column(&h, "alt", "height", &HEIGHT_ALIASES),
            Err(vec!["alt".to_string()])
        );
    }
}
