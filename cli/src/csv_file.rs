//! The CSV files the CLI writes, through the `csv` crate: comma-separated, `\n` line ends, a
//! field quoted only when it holds a comma, a quote or a line break. Numbers never do, so numeric
//! columns are exactly the text the caller formatted; a name with a comma (a beacon, a scenario,
//! a grid variation) is quoted and reads back whole.

use anyhow::Result;
use entrynav_studies::output::atomic_file::AtomicFile;
use std::io::Write;
use std::path::Path;

/// A CSV writer into a file (written whole or not at all, [`entrynav_studies::output::atomic_file`]).
pub type FileWriter = csv::Writer<AtomicFile>;

/// A CSV writer over `w` (the writer buffers; call `flush` at the end to see write errors).
pub fn writer<W: Write>(w: W) -> csv::Writer<W> {
    csv::Writer::from_writer(w)
}

/// Write the CSV file `path` with `body`, creating its folder. A file or folder that cannot be
/// created is refused with its path; an error while writing rows is a runtime failure (exit
/// code 1) naming the path.
pub fn write(path: &Path, body: impl FnOnce(&mut FileWriter) -> Result<()>) -> Result<()> {
    write_with_comment(path, |w| body(w).map(|()| None))
}

/// [`write`], where `body` may return a comment line (`# …`, no line break) that goes after the
/// records (the `csv` crate writes no comments). The file appears whole, comment included, or
/// not at all.
pub fn write_with_comment(
    path: &Path,
    body: impl FnOnce(&mut FileWriter) -> Result<Option<String>>,
) -> Result<()> {
    let runtime = |e: &dyn std::fmt::Display| {
        crate::exit_code::Runtime(format!("writing {}: {e:#}", path.display()))
    };
    let mut w = writer(AtomicFile::create(path)?);
    let comment = body(&mut w).map_err(|e| runtime(&format!("{e:#}")))?;
    let mut file = w.into_inner().map_err(|e| runtime(e.error()))?;
    if let Some(line) = comment {
        writeln!(file, "{line}").map_err(|e| runtime(&e))?;
    }
    Ok(file.commit()?)
}

/// A value as the CLI's CSV files write it: Rust's shortest round-trip `Display` (`0.1`, `0.0000001`,
/// `NaN`), an empty field when absent.
pub fn opt(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv_of(rows: &[&[&str]]) -> String {
        let mut w = writer(Vec::new());
        for r in rows {
            w.write_record(*r).unwrap();
        }
        String::from_utf8(w.into_inner().unwrap()).unwrap()
    }

    #[test]
    fn plain_fields_are_written_as_comma_joined_lines() {
        // The layout every CSV of the CLI had when it was written by `join(",")`.
        let rows: [&[&str]; 3] = [
            &["t_s", "rmse_r_m", "weight_0"],
            &["0.5", "1.25e-7", ""],
            &["NaN", "-inf", "12"],
        ];
        let joined: String = rows.iter().map(|r| r.join(",") + "\n").collect();
        assert_eq!(csv_of(&rows), joined);
    }

    #[test]
    fn a_name_with_a_comma_or_a_quote_is_quoted_and_reads_back_whole() {
        let name = "DSS-14, \"Goldstone\"";
        let text = csv_of(&[&["run", "beacon"], &["3", name]]);
        assert_eq!(text, "run,beacon\n3,\"DSS-14, \"\"Goldstone\"\"\"\n");
        let mut r = csv::Reader::from_reader(text.as_bytes());
        let rec = r.records().next().unwrap().unwrap();
        assert_eq!(&rec[1], name);
    }

    #[test]
    fn absent_values_are_empty_and_numbers_keep_their_shortest_form() {
        assert_eq!(opt(None), "");
        assert_eq!(opt(Some(0.1 + 0.2)), "0.30000000000000004");
        assert_eq!(opt(Some(1e-7)), "0.0000001");
    }
}
