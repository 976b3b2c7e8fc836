//! The CSV tables of `entrynav-dev fmu run` and `cross-check`: an input table read from CSV (a `time`
//! column and one column per input), and time series written as CSV, both through the `csv`
//! crate.

use anyhow::{Context, Result, bail, ensure};
use entrynav_fmu::vars::{Type, Value, Var};

/// The value of variable `v` written as `text` (surrounding quotes and spaces ignored).
pub(super) fn parse_value(v: &Var, text: &str) -> Result<Value> {
    let t = text.trim().trim_matches('"');
    Ok(match v.ty {
        Type::Real => Value::Real(
            t.parse()
                .with_context(|| format!("{}: bad real '{t}'", v.name))?,
        ),
        Type::Integer => Value::Integer(
            t.parse()
                .with_context(|| format!("{}: bad integer '{t}'", v.name))?,
        ),
        Type::Boolean => Value::Boolean(match t {
            "1" | "true" | "True" | "1.0" => true,
            "0" | "false" | "False" | "0.0" => false,
            _ => bail!("{}: bad boolean '{t}'", v.name),
        }),
        Type::String => Value::String(t.to_string()),
    })
}

/// A value as a CSV cell: reals round-trip (`{:?}`), Booleans as 0/1.
pub(super) fn fmt_value(v: &Value) -> String {
    match v {
        Value::Real(x) => format!("{x:?}"),
        Value::Integer(x) => x.to_string(),
        Value::Boolean(x) => (*x as i32).to_string(),
        Value::String(s) => s.clone(),
    }
}

/// An input table: the variables of its columns and its rows (time, values).
#[derive(Debug, Default)]
pub(super) struct Table {
    pub(super) columns: Vec<Var>,
    pub(super) rows: Vec<(f64, Vec<Value>)>,
}

impl Table {
    /// Parse a CSV with a `time` column and one column per variable of `vars` (cells may be
    /// quoted, as the FMI cross-check rules write the header; blank lines are skipped).
    pub(super) fn parse(text: &str, vars: &[Var]) -> Result<Table> {
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .flexible(true)
            .from_reader(text.as_bytes());
        // A quote after a space (`a, "b"`) is not CSV quoting; strip it as the FMI tools write it.
        let unquote = |s: &str| s.trim_matches('"').trim().to_string();
        let names: Vec<String> = reader
            .headers()
            .context("input table header")?
            .iter()
            .map(unquote)
            .collect();
        ensure!(!names.is_empty(), "empty input table");
        ensure!(
            names.first().map(String::as_str) == Some("time"),
            "the first column of the input table must be 'time'"
        );
        let columns = names
            .iter()
            .skip(1)
            .map(|n| {
                vars.iter()
                    .find(|v| v.name == *n)
                    .cloned()
                    .with_context(|| format!("no variable '{n}'"))
            })
            .collect::<Result<Vec<_>>>()?;
        let mut rows = Vec::new();
        for record in reader.records() {
            let record = record.context("input table")?;
            if record.len() == 1 && record[0].is_empty() {
                continue;
            }
            let line = record.position().map_or(0, |p| p.line());
            ensure!(
                record.len() == names.len(),
                "input row on line {line} has {} cells, expected {}",
                record.len(),
                names.len()
            );
            let t: f64 = unquote(&record[0])
                .parse()
                .with_context(|| format!("line {line}: bad time '{}'", &record[0]))?;
            let vals = columns
                .iter()
                .zip(record.iter().skip(1))
                .map(|(v, c)| parse_value(v, c))
                .collect::<Result<Vec<_>>>()?;
            rows.push((t, vals));
        }
        Ok(Table { columns, rows })
    }

    /// The row that applies at `t`: the last at or before it (the first before any).
    pub(super) fn at(&self, t: f64) -> Option<&Vec<Value>> {
        self.rows
            .iter()
            .rev()
            .find(|(rt, _)| *rt <= t + 1e-9)
            .or(self.rows.first())
            .map(|(_, v)| v)
    }
}

/// The CSV text of `rows` under a `time` column and the `names` of their values: the header
/// quoted when `quote_header` (as the cross-check rules want), cells quoted only where CSV needs
/// it.
pub(super) fn csv(
    names: &[&str],
    rows: &[(f64, Vec<Value>)],
    quote_header: bool,
) -> Result<String> {
    let header_style = match quote_header {
        true => csv::QuoteStyle::Always,
        false => csv::QuoteStyle::Necessary,
    };
    let mut header = csv::WriterBuilder::new()
        .quote_style(header_style)
        .from_writer(Vec::new());
    header.write_record(std::iter::once("time").chain(names.iter().copied()))?;
    let mut out = csv::Writer::from_writer(header.into_inner()?);
    for (t, vals) in rows {
        out.write_record(std::iter::once(format!("{t:?}")).chain(vals.iter().map(fmt_value)))?;
    }
    Ok(String::from_utf8(out.into_inner()?)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use entrynav_fmu::vars::{Model, variables};

    fn var(name: &str) -> Var {
        variables(Model::Combined)
            .iter()
            .find(|v| v.name == name)
            .cloned()
            .unwrap()
    }

    #[test]
    fn a_table_written_reads_back_the_same() {
        let (bank, avail) = (var("bank_angle"), var("beacon_available_2"));
        let rows = vec![
            (0.0, vec![Value::Real(0.1), Value::Boolean(true)]),
            (1.5, vec![Value::Real(-1e-300), Value::Boolean(false)]),
        ];
        for quote in [false, true] {
            let text = csv(&["bank_angle", "beacon_available_2"], &rows, quote).unwrap();
            let t = Table::parse(&text, &variables(Model::Combined)).unwrap();
            assert_eq!(t.columns, [bank.clone(), avail.clone()]);
            assert_eq!(t.rows, rows);
        }
    }

    #[test]
    fn the_header_is_quoted_for_the_cross_check_and_numbers_never() {
        let rows = vec![(0.25, vec![Value::Real(2.0), Value::Integer(-3)])];
        assert_eq!(
            csv(&["a", "b"], &rows, true).unwrap(),
            "\"time\",\"a\",\"b\"\n0.25,2.0,-3\n"
        );
        assert_eq!(
            csv(&["a", "b"], &rows, false).unwrap(),
            "time,a,b\n0.25,2.0,-3\n"
        );
        // A name that holds the delimiter stays one column (the old writer split it in two).
        assert_eq!(
            csv(&["x,y"], &[(0.0, vec![Value::Real(1.0)])], false).unwrap(),
            "time,\"x,y\"\n0.0,1.0\n"
        );
    }

    #[test]
    fn quoted_cells_blank_lines_and_short_rows() {
        let vars = &variables(Model::Combined);
        let t = Table::parse("\"time\", \"bank_angle\"\n\n0, \"0.5\"\n  \n2,1\n", vars).unwrap();
        assert_eq!(
            t.rows,
            [(0.0, vec![Value::Real(0.5)]), (2.0, vec![Value::Real(1.0)])]
        );
        assert_eq!(t.at(1.0), Some(&vec![Value::Real(0.5)]));
        let short = Table::parse("time,bank_angle\n0\n", vars).unwrap_err();
        assert!(
            format!("{short:#}").contains("1 cells, expected 2"),
            "{short:#}"
        );
        let no_time = Table::parse("t,bank_angle\n0,1\n", vars).unwrap_err();
        assert!(format!("{no_time:#}").contains("'time'"), "{no_time:#}");
        assert!(Table::parse("time,nope\n", vars).is_err());
    }
}
