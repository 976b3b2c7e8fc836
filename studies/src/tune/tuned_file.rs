//! The scenario file `entrynav tune` writes: the user's own text, edited in place with
//! `toml_edit` so that every comment, blank line and key order survives, with the `--set`
//! overrides the tuning ran with written in, and one `[filter.tuned.<name>]` table per tuned
//! filter (replaced when the file already has one), its provenance in the comment above it and
//! its numbers at six significant digits.

use crate::error::{StudyError, StudyResult};
use entrynav::estimation::{AeroScaledNoise, ProcessNoiseModel};
use entrynav::scenario::{FilterRetuneConfig, NoiseInflation};
use toml_edit::{Array, DocumentMut, Item, Table, Value};

/// Why the text could not be edited: refused (exit code 2), as the command always did.
fn refused(message: impl std::fmt::Display) -> StudyError {
    StudyError::Refused(message.to_string())
}

/// `Err(refused(…))` with a formatted message.
macro_rules! bail {
    ($($arg:tt)*) => { return Err(refused(format!($($arg)*))) };
}

/// One filter's tuning to write.
pub struct Retune<'a> {
    /// Filter name (the table key).
    pub name: &'a str,
    /// What to write.
    pub config: &'a FilterRetuneConfig,
    /// Comment lines above the table (without `# `).
    pub comment: &'a [String],
}

/// `value` rounded to six significant digits, as TOML text (exponent form below 1e-4 and from
/// 1e6): `2.0556425029701622e-14` becomes `2.05564e-14`.
pub fn six_digits(value: f64) -> String {
    if !value.is_finite() || value == 0.0 {
        return format!("{value:?}");
    }
    let sci = format!("{value:.5e}");
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
    let exp: i32 = exp.parse().unwrap_or(0);
    if !(-4..6).contains(&exp) {
        return format!("{mantissa}e{exp}");
    }
    let v: f64 = format!("{mantissa}e{exp}").parse().unwrap_or(value);
    let s = format!("{v}");
    if s.contains('.') { s } else { format!("{s}.0") }
}

/// `value` rounded to six significant digits.
pub fn round6(value: f64) -> f64 {
    six_digits(value).parse().unwrap_or(value)
}

/// The retune with every number rounded to six significant digits: what the file will hold.
pub fn rounded(config: &FilterRetuneConfig) -> FilterRetuneConfig {
    let r = |n: &NoiseInflation| NoiseInflation {
        accel: round6(n.accel),
        dynamic_pressure: round6(n.dynamic_pressure),
        heating: round6(n.heating),
        range: round6(n.range),
        range_rate: round6(n.range_rate),
    };
    FilterRetuneConfig {
        q_diag: config
            .q_diag
            .as_ref()
            .map(|q| q.iter().copied().map(round6).collect()),
        process_noise: config.process_noise.map(|m| match m {
            ProcessNoiseModel::AeroScaled(mut a) => {
                a.fraction = a.fraction.map(round6);
                a.density_sigma = round6(a.density_sigma);
                ProcessNoiseModel::AeroScaled(a)
            }
            constant => constant,
        }),
        noise_inflation: config.noise_inflation.as_ref().map(r),
    }
}

/// `{ model = "aero-scaled", fraction = [..], floor_mps2 = .., correlation_… = .. }`.
fn aero_inline(a: &AeroScaledNoise) -> StudyResult<toml_edit::InlineTable> {
    let mut inline = toml_edit::InlineTable::new();
    inline.insert("model", Value::from("aero-scaled"));
    let mut fraction = Array::new();
    for f in a.fraction {
        fraction.push(number(f)?);
    }
    inline.insert("fraction", Value::Array(fraction));
    inline.insert("floor_mps2", number(a.floor_mps2)?);
    if let Some(t) = a.correlation_time_s {
        inline.insert("correlation_time_s", number(t)?);
    }
    if let Some(l) = a.correlation_length_m {
        inline.insert("correlation_length_m", number(l)?);
    }
    if a.density_sigma > 0.0 {
        inline.insert("density_sigma", number(a.density_sigma)?);
    }
    Ok(inline)
}

fn number(value: f64) -> StudyResult<Value> {
    six_digits(value)
        .parse::<Value>()
        .map_err(|e| refused(format!("cannot write {value} as TOML: {e}")))
}

/// `source` (a scenario's TOML text) with the `sets` (`PATH=VALUE`, as `--set` takes them) and
/// the `retunes` written in.
pub fn edit(source: &str, sets: &[String], retunes: &[Retune<'_>]) -> StudyResult<String> {
    let mut doc: DocumentMut = source.parse().map_err(|e| {
        refused(format!(
            "the scenario text is not TOML that can be edited: {e}"
        ))
    })?;
    for set in sets {
        apply_set(&mut doc, set).map_err(|e| refused(format!("--set {set}: {e}")))?;
    }
    let filter = doc
        .get_mut("filter")
        .and_then(Item::as_table_mut)
        .ok_or_else(|| refused("the scenario has no [filter] table to tune"))?;
    let tuned = filter.entry("tuned").or_insert_with(|| {
        let mut t = Table::new();
        t.set_implicit(true);
        Item::Table(t)
    });
    let tuned = tuned
        .as_table_mut()
        .ok_or_else(|| refused("filter.tuned is not a table"))?;
    for r in retunes {
        let mut table = match tuned.remove(r.name) {
            Some(Item::Table(t)) => t,
            _ => Table::new(),
        };
        if let Some(q) = &r.config.q_diag {
            let mut array = Array::new();
            for v in q {
                array.push_formatted(number(*v)?.decorated("\n    ", ""));
            }
            array.set_trailing_comma(true);
            array.set_trailing("\n");
            table.insert("q_diag", toml_edit::value(array));
        }
        if let Some(ProcessNoiseModel::AeroScaled(a)) = &r.config.process_noise {
            table.insert("process_noise", toml_edit::value(aero_inline(a)?));
        }
        match &r.config.noise_inflation {
            Some(n) => {
                let mut inline = toml_edit::InlineTable::new();
                let d = NoiseInflation::default();
                for (key, v, one) in [
                    ("accel", n.accel, d.accel),
                    ("dynamic_pressure", n.dynamic_pressure, d.dynamic_pressure),
                    ("heating", n.heating, d.heating),
                    ("range", n.range, d.range),
                    ("range_rate", n.range_rate, d.range_rate),
                ] {
                    if v != one {
                        inline.insert(key, number(v)?);
                    }
                }
                table.insert("noise_inflation", toml_edit::value(inline));
            }
            None => {
                table.remove("noise_inflation");
            }
        }
        let comment: String = r.comment.iter().map(|l| format!("# {l}\n")).collect();
        table.decor_mut().set_prefix(format!("\n{comment}"));
        table.set_position(None);
        tuned.insert(r.name, Item::Table(table));
    }
    Ok(doc.to_string())
}

/// Write one `PATH=VALUE` override into the document as `--set` reads it: tables along the path
/// are created, a numeric key indexes an array (`beacons.0.lat_deg`), a value that is not TOML is
/// a string; the comment beside a replaced value is kept.
fn apply_set(doc: &mut DocumentMut, set: &str) -> StudyResult<()> {
    let (path, value) = set
        .split_once('=')
        .ok_or_else(|| refused("expected PATH=VALUE"))?;
    let value: Value = value
        .trim()
        .parse()
        .unwrap_or_else(|_| Value::from(value.to_string()));
    let keys: Vec<&str> = path.trim().split('.').collect();
    if keys.iter().any(|k| k.is_empty()) {
        bail!("empty key in the path");
    }
    set_in_table(doc.as_table_mut(), &keys, value)
}

fn index(k: &str, n: usize) -> StudyResult<usize> {
    k.parse::<usize>()
        .ok()
        .filter(|&i| i < n)
        .ok_or_else(|| refused(format!("'{k}' is not an index of an array of {n} entries")))
}

fn replace_keeping_decor(old: &mut Value, new: Value) {
    let decor = old.decor().clone();
    *old = new;
    *old.decor_mut() = decor;
}

fn set_in_table(t: &mut dyn toml_edit::TableLike, keys: &[&str], value: Value) -> StudyResult<()> {
    let (k, rest) = keys.split_first().ok_or_else(|| refused("empty path"))?;
    if rest.is_empty() {
        match t.get_mut(k) {
            Some(Item::Value(old)) => replace_keeping_decor(old, value),
            _ => {
                t.insert(k, Item::Value(value));
            }
        }
        return Ok(());
    }
    if t.get(k).is_none() {
        t.insert(k, Item::Table(Table::new()));
    }
    match t.get_mut(k) {
        Some(Item::ArrayOfTables(a)) => {
            let i = index(rest[0], a.len())?;
            let inner = a
                .get_mut(i)
                .ok_or_else(|| refused(format!("no entry {i}")))?;
            if rest.len() == 1 {
                bail!("'{k}.{i}' is a table: set one of its fields");
            }
            set_in_table(inner, &rest[1..], value)
        }
        Some(Item::Value(v)) => set_in_value(v, rest, value),
        Some(item) => {
            let inner = item
                .as_table_like_mut()
                .ok_or_else(|| refused(format!("'{k}' is not a table")))?;
            set_in_table(inner, rest, value)
        }
        None => bail!("cannot create '{k}'"),
    }
}

fn set_in_value(v: &mut Value, keys: &[&str], value: Value) -> StudyResult<()> {
    match v {
        Value::Array(arr) => {
            let i = index(keys[0], arr.len())?;
            let el = arr
                .get_mut(i)
                .ok_or_else(|| refused(format!("no entry {i}")))?;
            if keys.len() == 1 {
                replace_keeping_decor(el, value);
                Ok(())
            } else {
                set_in_value(el, &keys[1..], value)
            }
        }
        Value::InlineTable(t) => set_in_table(t, keys, value),
        _ => bail!("cannot reach '{}': its parent is a value", keys[0]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_six_significant_digits() {
        assert_eq!(six_digits(2.0556425029701622e-14), "2.05564e-14");
        assert_eq!(six_digits(1234567.891), "1.23457e6");
        assert_eq!(six_digits(100.0), "100.0");
        assert_eq!(six_digits(0.25), "0.25");
        assert!((round6(2.0556425029701622e-14) / 2.0556425029701622e-14 - 1.0).abs() < 5e-6);
    }

    #[test]
    fn sets_index_arrays_as_the_loader_does() {
        let source = "[filter]\nq_diag = [1.0, 2.0] # Q\n\n[[beacons]]\nname = \"a\"\nlat_deg = 1.0\n\n[[beacons]]\nname = \"b\"\nlat_deg = 2.0 # north\n";
        let out = edit(
            source,
            &[
                "beacons.1.lat_deg=5.5".to_string(),
                "filter.q_diag.0=3.0".to_string(),
            ],
            &[],
        )
        .unwrap();
        assert!(out.contains("lat_deg = 5.5 # north"), "{out}");
        assert!(out.contains("q_diag = [3.0, 2.0] # Q"), "{out}");
        assert!(edit(source, &["beacons.2.lat_deg=1".to_string()], &[]).is_err());
    }

    #[test]
    fn comments_layout_and_sets_survive() {
        let source = "# my study\nname = \"x\" # keep\n\n[filter]\n# shared Q\nq_diag = [1.0, 2.0]\n\n[truth]\nbank_deg = 30.0 # flown\n";
        let retune = FilterRetuneConfig {
            q_diag: Some(vec![0.1234567891, 2e-14]),
            process_noise: None,
            noise_inflation: None,
        };
        let comment = vec!["tuned".to_string()];
        let out = edit(
            source,
            &["truth.bank_deg=45.0".to_string()],
            &[Retune {
                name: "ekf",
                config: &retune,
                comment: &comment,
            }],
        )
        .unwrap();
        assert!(
            out.starts_with(
                "# my study\nname = \"x\" # keep\n\n[filter]\n# shared Q\nq_diag = [1.0, 2.0]\n"
            ),
            "{out}"
        );
        assert!(out.contains("bank_deg = 45.0 # flown"), "{out}");
        assert!(
            out.contains("# tuned\n[filter.tuned.ekf]\nq_diag = [\n    0.123457,\n    2e-14,\n]"),
            "{out}"
        );
        // Re-tuning replaces the table instead of adding a second one.
        let again = edit(
            &out,
            &[],
            &[Retune {
                name: "ekf",
                config: &retune,
                comment: &comment,
            }],
        )
        .unwrap();
        assert_eq!(again.matches("[filter.tuned.ekf]").count(), 1, "{again}");
    }
}
