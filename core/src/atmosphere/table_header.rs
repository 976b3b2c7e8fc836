//! The header of a density table (see [`super::parse`]): the header line, the columns chosen
//! from it ([`ChosenColumns`]: height, density and radius, by name or alias) and the numbers of
//! its data rows (`D` exponents of Fortran output included).

use super::columns::{
    DENSITY_ALIASES, HEIGHT_ALIASES, RADIUS_ALIASES, TableColumns, declared_unit, find_column,
};
use super::error::AtmosphereError;

fn is_numeric_row(line: &str) -> bool {
    let mut fields = line
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|f| !f.is_empty())
        .peekable();
    fields.peek().is_some() && fields.all(|f| parse_number(f.trim_matches('"')).is_some())
}

fn is_name_row(line: &str) -> bool {
    let mut fields = line
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|f| !f.is_empty())
        .peekable();
    fields.peek().is_some() && fields.all(|f| parse_number(f.trim_matches('"')).is_none())
}

/// The header line: its 1-based number and its text without a leading `#`.
pub(super) fn find_header(text: &str) -> Option<(usize, &str)> {
    let lines: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty())
        .collect();
    for (k, &(n, l)) in lines.iter().enumerate() {
        match l.strip_prefix('#') {
            None => return Some((n, l.strip_prefix('\u{feff}').unwrap_or(l))),
            Some(body) => {
                let next_is_data = lines
                    .get(k + 1)
                    .is_some_and(|(_, next)| !next.starts_with('#') && is_numeric_row(next));
                if is_name_row(body) && next_is_data {
                    return Some((n, body.trim()));
                }
            }
        }
    }
    None
}

pub(super) fn parse_number(text: &str) -> Option<f64> {
    text.parse::<f64>().ok().or_else(|| {
        if text.contains(['D', 'd']) && !text.contains(['E', 'e']) {
            text.replace(['D', 'd'], "E").parse::<f64>().ok()
        } else {
            None
        }
    })
}

/// The columns a table is read from: (index, header name) of the height, the density and, when
/// the table has one, the radius column.
pub(super) struct ChosenColumns {
    pub(super) height: (usize, String),
    pub(super) density: (usize, String),
    pub(super) radius: Option<(usize, String)>,
}

/// Choose the height, density and radius columns of `header` (line `header_line`) by the names
/// or aliases of `columns`; refuse a height column whose declared unit is not the requested one.
pub(super) fn choose_columns(
    header: &[&str],
    header_line: usize,
    source_name: &str,
    columns: &TableColumns,
) -> Result<ChosenColumns, AtmosphereError> {
    let src = || source_name.to_string();
    let missing =
        |role: &'static str, requested: &str, tried: Vec<String>| AtmosphereError::MissingColumn {
            source_name: src(),
            line: header_line,
            role,
            requested: requested.to_string(),
            tried: tried.join(", "),
            found: header.join(", "),
        };
    let hi = find_column(header, &columns.height, "height", &HEIGHT_ALIASES)
        .map_err(|t| missing("height", &columns.height, t))?;
    let di = find_column(header, &columns.density, "denstot", &DENSITY_ALIASES)
        .map_err(|t| missing("density", &columns.density, t))?;
    let ri = match &columns.radius {
        Some(name) => {
            Some(find_column(header, name, "", &[]).map_err(|t| missing("radius", name, t))?)
        }
        None => find_column(header, "radius", "radius", &RADIUS_ALIASES).ok(),
    };
    let (h_name, d_name) = (header[hi].to_string(), header[di].to_string());
    let r_name = ri.map(|i| header[i].to_string());
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
    Ok(ChosenColumns {
        height: (hi, h_name),
        density: (di, d_name),
        radius: ri.zip(r_name),
    })
}

/// The number in field `text` of column `column` on line `line`: finite, or an error naming them.
pub(super) fn table_number(
    source_name: &str,
    line: usize,
    column: &str,
    text: &str,
) -> Result<f64, AtmosphereError> {
    let src = || source_name.to_string();
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
}
