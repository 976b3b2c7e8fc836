//! Readers for density tables: CSV and Mars-GRAM-style whitespace columns.
//!
//! Both take the file *text* and a `source_name` used in error messages (the crate does no I/O).
//!
//! **Header.** The header of column names is the first line that is either
//! * not blank and not `#`-prefixed (an averaged Mars-GRAM file, a hand-made CSV), or
//! * a `#`-prefixed line whose fields are all non-numeric names and that is directly followed (blank
//!   lines aside) by a row of numbers — the first line of Mars-GRAM Monte Carlo output,
//!   `#    Var_X        DENSLO     DENSAV     DENSHI    DENSTOT  DustOD  Radius ...`.
//!
//! Other blank and `#` lines are skipped anywhere; a later line equal to the header (a header
//! repeated between stacked profiles) is skipped too. Every other line is a data row with exactly
//! as many fields as the header. Line numbers in errors are 1-based and count every line.
//! At most [`MAX_TABLE_ROWS`] data rows are read. [`parse_csv`] / [`parse_mars_gram`] return one
//! profile; [`super::profiles::parse_profiles`] reads stacked profiles (a Monte Carlo set): a
//! row whose height falls back past the middle of the current profile's height span starts a new
//! profile, a smaller step back is a non-monotonic error.

use serde::{Deserialize, Serialize};

use super::error::AtmosphereError;
use super::tabulated::{MIN_TABLE_POINTS, Tabulated};

use super::columns::{HeightUnit, TableColumns};
use super::table_header::{ChosenColumns, choose_columns, find_header, table_number};

/// Most data rows read from one table text (all profiles together); more is an error.
pub const MAX_TABLE_ROWS: usize = 1_000_000;

/// Text format of a density table file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum TableFormat {
    /// Comma-separated values with a header line ([`parse_csv`]).
    Csv,
    /// Whitespace-separated Mars-GRAM-style columns with a header line ([`parse_mars_gram`]).
    MarsGram,
}

impl TableFormat {
    /// Split one line into fields.
    pub(crate) fn split(self, line: &str) -> Vec<&str> {
        match self {
            TableFormat::Csv => line
                .split(',')
                .map(|f| {
                    let f = f.trim();
                    f.strip_prefix('"')
                        .and_then(|g| g.strip_suffix('"'))
                        .unwrap_or(f)
                })
                .collect(),
            TableFormat::MarsGram => line.split_whitespace().collect(),
        }
    }

    /// CSV when the header line (found as described in [this module](self)) holds a comma,
    /// Mars-GRAM-style whitespace columns otherwise.
    pub fn detect(text: &str) -> TableFormat {
        match find_header(text) {
            Some((_, h)) if h.contains(',') => TableFormat::Csv,
            _ => TableFormat::MarsGram,
        }
    }
}

/// The densities a table may hold \[kg/m³\]. Above: 1 kg/m³ is 50 times Mars's densest surface
/// air (≈ 0.02 kg/m³) and close to Earth's sea level; a value above it is a unit mistake or a
/// wrong column (a `Radius` column read as density holds ≈ 3396) and would decelerate the entry
/// at hundreds of g (1e3 kg/m³ at 50 km: 528 g). Below: 1e-20 kg/m³ is far thinner than Mars's
/// exosphere at 500 km (≈ 1e-14); smaller (subnormal) values lose precision in ln ρ and the
/// spline and made the truth non-finite.
pub const DENSITY_ENVELOPE_KGM3: [f64; 2] = [1e-20, 1.0];

/// One data row as read: the line, height (m, as given, before any datum shift), density and
/// planet-centred radius (m) when the table has a radius column.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RawRow {
    /// 1-based line number.
    pub line: usize,
    /// Height column value converted to metres (the file's own datum).
    pub height_m: f64,
    /// Density (kg/m³), > 0.
    pub density: f64,
    /// Radius column value converted to metres (column in km), if present.
    pub radius_m: Option<f64>,
}

/// A table as read: which columns were used and the rows in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct RawTable {
    /// 1-based line of the header.
    pub header_line: usize,
    /// Header name of the height column used.
    pub height_column: String,
    /// Header name of the density column used.
    pub density_column: String,
    /// Header name of the radius column used, if any.
    pub radius_column: Option<String>,
    /// Data rows, in file order.
    pub rows: Vec<RawRow>,
}

/// Read every data row of a table (no profile splitting, no datum): header detection, column
/// choice ([`TableColumns`]), numbers, positive densities, the [`MAX_TABLE_ROWS`] cap.
pub fn read_table(
    text: &str,
    source_name: &str,
    format: TableFormat,
    columns: &TableColumns,
) -> Result<RawTable, AtmosphereError> {
    let src = || source_name.to_string();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let (header_line, header_text) =
        find_header(text).ok_or_else(|| AtmosphereError::NoHeader { source_name: src() })?;
    let header = format.split(header_text);
    let chosen = choose_columns(&header, header_line, source_name, columns)?;
    let mut rows = Vec::new();
    for (i, raw) in text.lines().enumerate().skip(header_line) {
        let (line, t) = (i + 1, raw.trim());
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let row = format.split(t);
        if row == header {
            continue;
        }
        if row.len() != header.len() {
            return Err(AtmosphereError::FieldCount {
                source_name: src(),
                line,
                expected: header.len(),
                found: row.len(),
            });
        }
        if rows.len() == MAX_TABLE_ROWS {
            return Err(AtmosphereError::TooManyRows {
                source_name: src(),
                line,
                limit: MAX_TABLE_ROWS,
            });
        }
        rows.push(read_row(
            &row,
            line,
            &chosen,
            source_name,
            columns.height_unit,
        )?);
    }
    Ok(RawTable {
        header_line,
        height_column: chosen.height.1,
        density_column: chosen.density.1,
        radius_column: chosen.radius.map(|(_, name)| name),
        rows,
    })
}

/// One data row's height, density (positive, within [`DENSITY_ENVELOPE_KGM3`]) and radius, from
/// the fields of line `line` in the `chosen` columns.
fn read_row(
    row: &[&str],
    line: usize,
    chosen: &ChosenColumns,
    source_name: &str,
    height_unit: HeightUnit,
) -> Result<RawRow, AtmosphereError> {
    let src = || source_name.to_string();
    let (hi, h_name) = &chosen.height;
    let (di, d_name) = &chosen.density;
    let h = table_number(source_name, line, h_name, row[*hi])?;
    let density = table_number(source_name, line, d_name, row[*di])?;
    if density <= 0.0 {
        return Err(AtmosphereError::NonPositiveDensity {
            source_name: src(),
            line,
            column: d_name.clone(),
            value: density,
        });
    }
    let [min, max] = DENSITY_ENVELOPE_KGM3;
    if !(min..=max).contains(&density) {
        return Err(AtmosphereError::DensityOutOfRange {
            source_name: src(),
            line,
            column: d_name.clone(),
            value: density,
            min,
            max,
        });
    }
    let radius_m = match &chosen.radius {
        Some((i, name)) => Some(table_number(source_name, line, name, row[*i])? * 1e3),
        None => None,
    };
    Ok(RawRow {
        line,
        height_m: h * height_unit.to_metres(),
        density,
        radius_m,
    })
}

/// Split rows into profiles. A row that breaks the height order of the current profile starts a
/// new profile when it falls back past the middle of that profile's height span (a restart, as
/// between Mars-GRAM Monte Carlo profiles); a smaller step back, or a repeated height, is an
/// error naming both lines. Returns index ranges into `rows`.
pub(crate) fn split_profiles(
    rows: &[RawRow],
    source_name: &str,
    unit: HeightUnit,
) -> Result<Vec<std::ops::Range<usize>>, AtmosphereError> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut increasing: Option<bool> = None;
    for i in 1..rows.len() {
        let (a, b) = (rows[i - 1], rows[i]);
        let error = |problem: String| AtmosphereError::NonMonotonic {
            source_name: source_name.to_string(),
            first_line: a.line,
            second_line: b.line,
            first_value: a.height_m / unit.to_metres(),
            second_value: b.height_m / unit.to_metres(),
            problem,
        };
        if a.height_m == b.height_m {
            return Err(error("repeats the altitude".to_string()));
        }
        let up = b.height_m > a.height_m;
        match increasing {
            Some(dir) if dir != up => {
                let middle = 0.5 * (rows[start].height_m + a.height_m);
                let restart = if dir {
                    b.height_m < middle
                } else {
                    b.height_m > middle
                };
                if !restart {
                    return Err(error(format!(
                        "breaks the {} order",
                        if dir { "increasing" } else { "decreasing" }
                    )));
                }
                out.push(start..i);
                start = i;
                increasing = None;
            }
            _ => increasing = Some(up),
        }
    }
    if !rows.is_empty() {
        out.push(start..rows.len());
    }
    Ok(out)
}

/// Parse a comma-separated table holding one profile (fields trimmed, surrounding double
/// quotes removed). Heights are taken as given (above the reference sphere).
pub fn parse_csv(
    text: &str,
    source_name: &str,
    columns: &TableColumns,
) -> Result<Tabulated, AtmosphereError> {
    parse_single(text, source_name, TableFormat::Csv, columns)
}

/// Parse a Mars-GRAM-style table holding one profile: whitespace-separated columns under a
/// header line of names, e.g. `Time(sec) Height(km) Lat(deg) ... DENSTOT ...` or
/// `#  Var_X  DENSLO  DENSAV  DENSHI  DENSTOT ...`. Fortran `D` exponents (`1.5D-03`) are
/// accepted. Heights are taken as given (above the reference sphere).
pub fn parse_mars_gram(
    text: &str,
    source_name: &str,
    columns: &TableColumns,
) -> Result<Tabulated, AtmosphereError> {
    parse_single(text, source_name, TableFormat::MarsGram, columns)
}

fn parse_single(
    text: &str,
    source_name: &str,
    format: TableFormat,
    columns: &TableColumns,
) -> Result<Tabulated, AtmosphereError> {
    let table = read_table(text, source_name, format, columns)?;
    let parts = split_profiles(&table.rows, source_name, columns.height_unit)?;
    if let [first, second, ..] = parts.as_slice() {
        let (a, b) = (table.rows[first.end - 1], table.rows[second.start]);
        let up = table.rows[first.start + 1].height_m > table.rows[first.start].height_m;
        return Err(AtmosphereError::NonMonotonic {
            source_name: source_name.to_string(),
            first_line: a.line,
            second_line: b.line,
            first_value: a.height_m / columns.height_unit.to_metres(),
            second_value: b.height_m / columns.height_unit.to_metres(),
            problem: format!(
                "restarts the {} order: the text holds {} stacked profiles (a Monte Carlo set); read it as a profile set",
                if up { "increasing" } else { "decreasing" },
                parts.len()
            ),
        });
    }
    if table.rows.len() < MIN_TABLE_POINTS {
        return Err(AtmosphereError::TooFewRows {
            source_name: source_name.to_string(),
            found: table.rows.len(),
            required: MIN_TABLE_POINTS,
        });
    }
    let (alt, rho) = table.rows.iter().map(|r| (r.height_m, r.density)).unzip();
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
    use crate::atmosphere::table_header::parse_number;

    #[test]
    fn fortran_exponents() {
        assert_eq!(parse_number("1.5D-03"), Some(1.5e-3));
        assert_eq!(parse_number("2.0e1"), Some(20.0));
        assert_eq!(parse_number("abc"), None);
        assert_eq!(parse_number("dd"), None);
    }

    #[test]
    fn hash_header_only_when_names_precede_numbers() {
        let gram = "#  Var_X  DENSTOT  Radius\n -5.0 2.0E-02 3390.5\n";
        assert_eq!(find_header(gram), Some((1, "Var_X  DENSTOT  Radius")));
        let commented = "# made by hand\nheight denstot\n0 1e-2\n";
        assert_eq!(find_header(commented), Some((2, "height denstot")));
        let dated = "# Mars-GRAM 2010 output\n1 2\n";
        assert_eq!(find_header(dated), Some((2, "1 2")));
        assert_eq!(find_header("# a b\n# c d\n"), None);
        assert_eq!(
            TableFormat::detect("# height,denstot\n0,1\n"),
            TableFormat::Csv
        );
        assert_eq!(TableFormat::detect(gram), TableFormat::MarsGram);
    }
}
