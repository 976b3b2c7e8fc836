//! Parsers for density tables: CSV and Mars-GRAM-style whitespace columns.
//!
//! Both take the file *text* and a `source_name` used in error messages (the crate does no I/O).
//! Lines that are blank or start with `#` are skipped anywhere; the first other line is the header
//! of column names; every following line is a data row with exactly as many fields as the header.
//! Line numbers in errors are 1-based and count every line of the text.

use serde::{Deserialize, Serialize};

use super::error::AtmosphereError;
use super::tabulated::{MIN_TABLE_POINTS, Tabulated};

/// Unit of the height column of a table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HeightUnit {
    /// Kilometres (Mars-GRAM's `Height(km)` / `Hgtkm`).
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

/// Names of the height aliases tried when the default height name `height` is not in the header.
pub const HEIGHT_ALIASES: [&str; 6] = [
    "height",
    "hgtkm",
    "height_km",
    "altitude_km",
    "alt_km",
    "altitude",
];

/// Names of the density aliases tried when the default density name `denstot` is not in the
/// header. Densities must be in kg/m³ (as Mars-GRAM's `DENSTOT`/`Denavg` are).
pub const DENSITY_ALIASES: [&str; 5] = ["denstot", "density", "rho", "denavg", "density_kgm3"];

/// Which columns of a table hold altitude and density, and the altitude unit.
///
/// Column names match header names case-insensitively, either exactly or after removing a
/// parenthesised or bracketed unit suffix: `height` matches `Height(km)` and `HEIGHT (km)`.
/// When a name is left at its default (`height`, `denstot`) and is not found, the aliases
/// [`HEIGHT_ALIASES`] / [`DENSITY_ALIASES`] are tried in order. If the chosen height header
/// declares a unit (`(km)`, `(m)`, `..._km`, `Hgtkm`) that differs from `height_unit`, parsing
/// fails instead of silently scaling by 1000.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableColumns {
    /// Header name of the altitude column (altitude above the reference sphere).
    pub height: String,
    /// Header name of the density column (kg/m³).
    pub density: String,
    /// Unit of the altitude column.
    pub height_unit: HeightUnit,
}

impl Default for TableColumns {
    fn default() -> Self {
        TableColumns {
            height: "height".to_string(),
            density: "denstot".to_string(),
            height_unit: HeightUnit::Km,
        }
    }
}

/// Parse a comma-separated table (fields trimmed, surrounding double quotes removed).
pub fn parse_csv(
    text: &str,
    source_name: &str,
    columns: &TableColumns,
) -> Result<Tabulated, AtmosphereError> {
    parse_table(text, source_name, columns, |line| {
        line.split(',')
            .map(|f| {
                let f = f.trim();
                f.strip_prefix('"')
                    .and_then(|g| g.strip_suffix('"'))
                    .unwrap_or(f)
            })
            .collect()
    })
}

/// Parse a Mars-GRAM-style table: whitespace-separated columns under a header line of names,
/// e.g. `Time(sec) Height(km) Lat(deg) ... DENSTOT ...` or `Time Hgtkm ... Denavg ...`.
/// Fortran `D` exponents (`1.5D-03`) are accepted.
pub fn parse_mars_gram(
    text: &str,
    source_name: &str,
    columns: &TableColumns,
) -> Result<Tabulated, AtmosphereError> {
    parse_table(text, source_name, columns, |line| {
        line.split_whitespace().collect()
    })
}

/// Split a header name into (base name, unit text) at a trailing `(...)` or `[...]`.
fn split_unit(name: &str) -> (&str, Option<&str>) {
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

fn header_matches(header: &str, want: &str) -> bool {
    let want = want.trim();
    header.trim().eq_ignore_ascii_case(want) || split_unit(header).0.eq_ignore_ascii_case(want)
}

/// Unit declared by a height header, if recognisable.
fn declared_unit(header: &str) -> Option<HeightUnit> {
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

/// Find a column: the requested name, then (only if it is the default) the aliases.
fn find_column(
    header: &[&str],
    requested: &str,
    default: &str,
    aliases: &[&str],
) -> Result<usize, Vec<String>> {
    let mut tried = vec![requested.to_string()];
    if let Some(i) = header.iter().position(|h| header_matches(h, requested)) {
        return Ok(i);
    }
    if requested.trim().eq_ignore_ascii_case(default) {
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

fn parse_number(text: &str) -> Option<f64> {
    text.parse::<f64>().ok().or_else(|| {
        if text.contains(['D', 'd']) && !text.contains(['E', 'e']) {
            text.replace(['D', 'd'], "E").parse::<f64>().ok()
        } else {
            None
        }
    })
}

fn parse_table<'t>(
    text: &'t str,
    source_name: &str,
    columns: &TableColumns,
    split: impl Fn(&'t str) -> Vec<&'t str>,
) -> Result<Tabulated, AtmosphereError> {
    let src = || source_name.to_string();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| {
            let t = l.trim();
            !t.is_empty() && !t.starts_with('#')
        });
    let (header_line, header_text) = lines
        .next()
        .ok_or_else(|| AtmosphereError::NoHeader { source_name: src() })?;
    let header = split(header_text);
    let missing =
        |role: &'static str, requested: &str, tried: Vec<String>| AtmosphereError::MissingColumn {
            source_name: src(),
            line: header_line,
            role,
            requested: requested.to_string(),
            tried: tried.join(", "),
            found: header.join(", "),
        };
    let hi = find_column(&header, &columns.height, "height", &HEIGHT_ALIASES)
        .map_err(|t| missing("height", &columns.height, t))?;
    let di = find_column(&header, &columns.density, "denstot", &DENSITY_ALIASES)
        .map_err(|t| missing("density", &columns.density, t))?;
    let (h_name, d_name) = (header[hi].to_string(), header[di].to_string());
    let declared = declared_unit(&h_name).filter(|d| *d != columns.height_unit);
    if let Some(declared) = declared {
        return Err(AtmosphereError::HeightUnitMismatch {
            source_name: src(),
            line: header_line,
            column: h_name,
            declared,
            requested: columns.height_unit,
        });
    }

    let number = |line: usize, column: &str, text: &str| -> Result<f64, AtmosphereError> {
        match parse_number(text) {
            None => Err(AtmosphereError::MalformedNumber {
                source_name: src(),
                line,
                column: column.to_string(),
                text: text.to_string(),
            }),
            Some(v) if !v.is_finite() => Err(AtmosphereError::NonFiniteNumber {
                source_name: src(),
                line,
                column: column.to_string(),
                text: text.to_string(),
            }),
            Some(v) => Ok(v),
        }
    };

    let mut alt = Vec::new();
    let mut rho = Vec::new();
    let mut prev: Option<(usize, f64)> = None;
    let mut increasing: Option<bool> = None;
    for (line, row_text) in lines {
        let row = split(row_text);
        if row.len() != header.len() {
            return Err(AtmosphereError::FieldCount {
                source_name: src(),
                line,
                expected: header.len(),
                found: row.len(),
            });
        }
        let h = number(line, &h_name, row[hi])?;
        let r = number(line, &d_name, row[di])?;
        if r <= 0.0 {
            return Err(AtmosphereError::NonPositiveDensity {
                source_name: src(),
                line,
                column: d_name.clone(),
                value: r,
            });
        }
        if let Some((pl, ph)) = prev {
            let up = h > ph;
            let problem = if h == ph {
                Some("repeats the altitude".to_string())
            } else {
                match increasing {
                    Some(dir) if dir != up => Some(format!(
                        "breaks the {} order",
                        if dir { "increasing" } else { "decreasing" }
                    )),
                    _ => None,
                }
            };
            if let Some(problem) = problem {
                return Err(AtmosphereError::NonMonotonic {
                    source_name: src(),
                    first_line: pl,
                    second_line: line,
                    first_value: ph,
                    second_value: h,
                    problem,
                });
            }
            increasing = Some(up);
        }
        prev = Some((line, h));
        alt.push(h * columns.height_unit.to_metres());
        rho.push(r);
    }
    if alt.len() < MIN_TABLE_POINTS {
        return Err(AtmosphereError::TooFewRows {
            source_name: src(),
            found: alt.len(),
            required: MIN_TABLE_POINTS,
        });
    }
    Tabulated::new(alt, rho).map_err(|e| match e {
        AtmosphereError::InvalidTable { problem } => AtmosphereError::InvalidTable {
            problem: format!("{source_name}: {problem}"),
        },
        other => other,
    })
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
    }

    #[test]
    fn fortran_exponents() {
        assert_eq!(parse_number("1.5D-03"), Some(1.5e-3));
        assert_eq!(parse_number("2.0e1"), Some(20.0));
        assert_eq!(parse_number("abc"), None);
        assert_eq!(parse_number("dd"), None);
    }
}
