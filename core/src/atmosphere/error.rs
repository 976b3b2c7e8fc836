//! The single error type of the atmosphere module.

use thiserror::Error;

use super::columns::HeightUnit;

/// Everything that can go wrong when building, fitting, parsing or configuring an atmosphere.
///
/// Parser variants carry the source name (usually a file name supplied by the caller) and the
/// 1-based line number; configuration variants carry the dotted field path.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AtmosphereError {
    /// A scalar parameter (model coefficient, configuration field) is outside its allowed range.
    #[error("{field} = {value} is out of range: {allowed}")]
    OutOfRange {
        /// Field path or parameter name, e.g. `truth.atmosphere.rho_ref_kgm3`.
        field: String,
        /// The offending value.
        value: f64,
        /// Human-readable allowed range, e.g. `must be > 0 and < 1`.
        allowed: String,
    },
    /// A textual configuration field is invalid (empty file name, empty column name, ...).
    #[error("{field}: {problem}")]
    InvalidField {
        /// Field path.
        field: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A table given directly as vectors (not parsed from text) is invalid.
    #[error("invalid density table: {problem}")]
    InvalidTable {
        /// What is wrong, naming the 1-based point index where applicable.
        problem: String,
    },
    /// A least-squares fit could not be computed (too few or degenerate samples).
    #[error("least-squares fit failed: {problem}")]
    FitFailed {
        /// Why the fit failed.
        problem: String,
    },
    /// The caller-supplied loader could not provide a table file.
    #[error("cannot read atmosphere table file '{file}': {source}")]
    LoadFailed {
        /// The file name as written in the scenario.
        file: String,
        /// What the loader reported.
        source: crate::files::FileError,
    },
    /// The text contains no header line (empty, or only comments and blank lines).
    #[error("{source_name}: no header line found (the text is empty or holds only comments)")]
    NoHeader {
        /// Source (file) name.
        source_name: String,
    },
    /// A requested column is not in the header.
    #[error(
        "{source_name}: line {line}: no {role} column named '{requested}' (tried {tried}); header columns are: {found}"
    )]
    MissingColumn {
        /// Source (file) name.
        source_name: String,
        /// Line of the header.
        line: usize,
        /// `height` or `density`.
        role: &'static str,
        /// The requested column name.
        requested: String,
        /// Every name that was tried (requested name and aliases), comma-separated.
        tried: String,
        /// The header names found, comma-separated.
        found: String,
    },
    /// The header declares a height unit different from the requested one.
    #[error(
        "{source_name}: line {line}: column {column} declares unit {declared} but the table is read with height unit {requested}; set the height unit to {declared}"
    )]
    HeightUnitMismatch {
        /// Source (file) name.
        source_name: String,
        /// Line of the header.
        line: usize,
        /// Header name of the height column.
        column: String,
        /// Unit declared by the header.
        declared: HeightUnit,
        /// Unit requested by the caller.
        requested: HeightUnit,
    },
    /// A data row has a different number of fields than the header.
    #[error(
        "{source_name}: line {line}: expected {expected} fields (as in the header), found {found}"
    )]
    FieldCount {
        /// Source (file) name.
        source_name: String,
        /// Line of the row.
        line: usize,
        /// Number of header fields.
        expected: usize,
        /// Number of fields in this row.
        found: usize,
    },
    /// A field could not be read as a number.
    #[error("{source_name}: line {line}: column {column}: '{text}' is not a number")]
    MalformedNumber {
        /// Source (file) name.
        source_name: String,
        /// Line of the row.
        line: usize,
        /// Header name of the column.
        column: String,
        /// The text that failed to parse.
        text: String,
    },
    /// A field parsed as infinity or NaN.
    #[error("{source_name}: line {line}: column {column}: '{text}' is not finite")]
    NonFiniteNumber {
        /// Source (file) name.
        source_name: String,
        /// Line of the row.
        line: usize,
        /// Header name of the column.
        column: String,
        /// The text of the field.
        text: String,
    },
    /// A density is zero or negative.
    #[error("{source_name}: line {line}: column {column}: density {value} is not positive")]
    NonPositiveDensity {
        /// Source (file) name.
        source_name: String,
        /// Line of the row.
        line: usize,
        /// Header name of the density column.
        column: String,
        /// The density read.
        value: f64,
    },
    /// A density outside the physical envelope [`super::parse::DENSITY_ENVELOPE_KGM3`].
    #[error(
        "{source_name}: line {line}: column {column}: density {value} kg/m³ is outside the \
         physical envelope [{min:e}, {max}] kg/m³ (is the column a density in kg/m³?)"
    )]
    DensityOutOfRange {
        /// Source (file) name.
        source_name: String,
        /// Line of the row.
        line: usize,
        /// Header name of the density column.
        column: String,
        /// The density read.
        value: f64,
        /// Smallest accepted density.
        min: f64,
        /// Largest accepted density.
        max: f64,
    },
    /// Two rows repeat an altitude or break the monotonic order of the altitudes.
    #[error(
        "{source_name}: lines {first_line} and {second_line}: altitude {second_value} after {first_value} {problem}"
    )]
    NonMonotonic {
        /// Source (file) name.
        source_name: String,
        /// Line of the earlier row.
        first_line: usize,
        /// Line of the later row.
        second_line: usize,
        /// Altitude of the earlier row, in the table's unit.
        first_value: f64,
        /// Altitude of the later row, in the table's unit.
        second_value: f64,
        /// `repeats the altitude` or `breaks the increasing order`/`breaks the decreasing order`.
        problem: String,
    },
    /// Fewer data rows than the spline needs.
    #[error("{source_name}: found {found} data rows, at least {required} are needed")]
    TooFewRows {
        /// Source (file) name.
        source_name: String,
        /// Rows found.
        found: usize,
        /// Minimum number of rows.
        required: usize,
    },
    /// More data rows than [`super::parse::MAX_TABLE_ROWS`].
    #[error("{source_name}: line {line}: more than {limit} data rows; the table is refused")]
    TooManyRows {
        /// Source (file) name.
        source_name: String,
        /// Line of the first row over the limit.
        line: usize,
        /// The limit.
        limit: usize,
    },
    /// More stacked profiles than [`super::profiles::MAX_PROFILES`].
    #[error("{source_name}: line {line}: more than {limit} stacked profiles; the set is refused")]
    TooManyProfiles {
        /// Source (file) name.
        source_name: String,
        /// Line where the first profile over the limit starts.
        line: usize,
        /// The limit.
        limit: usize,
    },
    /// One profile of a set has too few rows or cannot be splined.
    #[error("{source_name}: lines {first_line}-{last_line}: profile {profile}: {problem}")]
    BadProfile {
        /// Source (file) name.
        source_name: String,
        /// 0-based profile index.
        profile: usize,
        /// First data line of the profile.
        first_line: usize,
        /// Last data line of the profile.
        last_line: usize,
        /// What is wrong.
        problem: String,
    },
    /// A requested profile index is not in the set.
    #[error(
        "{source_name}: profile {profile} does not exist: the file holds {count} profile(s), allowed 0 to {max}"
    )]
    ProfileOutOfRange {
        /// Source (file) name.
        source_name: String,
        /// The requested 0-based index.
        profile: usize,
        /// Number of profiles in the file.
        count: usize,
        /// Largest allowed index (`count − 1`).
        max: usize,
    },
}

impl AtmosphereError {
    /// Shorthand for [`AtmosphereError::OutOfRange`].
    pub(crate) fn out_of_range(
        field: impl Into<String>,
        value: f64,
        allowed: impl Into<String>,
    ) -> Self {
        AtmosphereError::OutOfRange {
            field: field.into(),
            value,
            allowed: allowed.into(),
        }
    }
}

/// Check `lo < value < hi` (open interval) and finiteness.
pub(crate) fn check_open(field: &str, value: f64, lo: f64, hi: f64) -> Result<(), AtmosphereError> {
    if value.is_finite() && value > lo && value < hi {
        Ok(())
    } else {
        Err(AtmosphereError::out_of_range(
            field,
            value,
            format!("must be > {lo} and < {hi}"),
        ))
    }
}

/// Check `lo <= value <= hi` (closed interval) and finiteness.
pub(crate) fn check_closed(
    field: &str,
    value: f64,
    lo: f64,
    hi: f64,
) -> Result<(), AtmosphereError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(AtmosphereError::out_of_range(
            field,
            value,
            format!("must be >= {lo} and <= {hi}"),
        ))
    }
}

/// Join a field prefix and a field name with a dot (no dot when the prefix is empty).
pub(crate) fn field_path(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}
