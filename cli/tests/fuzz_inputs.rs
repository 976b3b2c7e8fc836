//! A mutation fuzzer of our own for what users hand us: scenario files (every built-in, mutated
//! in its TOML values and in its text) and atmosphere tables (a Mars-GRAM file mutated in its
//! numbers and its text), each run through the real binary (`simulate`, some `trade --runs 2`,
//! `atmosphere inspect`) with a 20 s limit.
//!
//! Acceptance (issue "Nothing lost, nothing silent"): no panic, no hang beyond 20 s, no crash by
//! a signal, every refusal naming a field or the file, and no accepted input printing a
//! non-finite number. The default run tries [`DEFAULT_VARIANTS`] variants; CI's long mode sets
//! `ENTRYNAV_FUZZ_VARIANTS=2000`. Variant `i` is drawn from seed `SEED ^ i` alone, so a failure
//! printed as `variant i` is replayed by `ENTRYNAV_FUZZ_ONLY=i`; the failing input is also kept
//! in the scratch folder.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use toml::Value;

/// Variants of the default `cargo test` run.
const DEFAULT_VARIANTS: usize = 300;
/// Master seed of the variants.
const SEED: u64 = 0x5EED_F022;
/// A child still running after this is a hang.
const LIMIT: Duration = Duration::from_secs(20);
/// The averaged Mars-GRAM table of the core's tests (read at run time: a crate embeds only its
/// own files).
fn gram() -> String {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../core/tests/data/gram/averaged.txt"
    );
    std::fs::read_to_string(path).expect("core/tests/data/gram/averaged.txt")
}

/// SplitMix64: a tiny, seeded generator (the test needs reproducible choices, nothing more).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// A replacement for a number: the edges users and corrupted files produce.
fn mutate_number(rng: &mut Rng, x: f64) -> Value {
    match rng.below(14) {
        0 => Value::Float(0.0),
        1 => Value::Float(-1.0),
        2 => Value::Float(1e308),
        3 => Value::Float(-1e308),
        4 => Value::Float(1e-310),
        5 => Value::Float(f64::NAN),
        6 => Value::Float(f64::INFINITY),
        7 => Value::Float(x * 1e6),
        8 => Value::Float(-x),
        9 => Value::Float(x * 1e-6),
        10 => Value::String("12".into()),
        11 => Value::Array(vec![Value::Float(x)]),
        12 => Value::Integer(i64::MAX),
        _ => Value::Float(x + 0.5),
    }
}

/// Every leaf path of a TOML value (`a.b[2].c`), for picking one at random.
fn leaves(v: &Value, path: &mut Vec<PathStep>, out: &mut Vec<Vec<PathStep>>) {
    match v {
        Value::Table(t) => {
            out.push(path.clone());
            for (k, c) in t {
                path.push(PathStep::Key(k.clone()));
                leaves(c, path, out);
                path.pop();
            }
        }
        Value::Array(a) => {
            out.push(path.clone());
            for (i, c) in a.iter().enumerate() {
                path.push(PathStep::Index(i));
                leaves(c, path, out);
                path.pop();
            }
        }
        _ => out.push(path.clone()),
    }
}

#[derive(Clone, Debug)]
enum PathStep {
    Key(String),
    Index(usize),
}

fn at<'a>(v: &'a mut Value, path: &[PathStep]) -> &'a mut Value {
    path.iter().fold(v, |v, s| match (s, v) {
        (PathStep::Key(k), Value::Table(t)) => t.get_mut(k).unwrap(),
        (PathStep::Index(i), Value::Array(a)) => &mut a[*i],
        _ => unreachable!("path from leaves()"),
    })
}

/// One structural mutation of a scenario's TOML value.
fn mutate_value(rng: &mut Rng, doc: &mut Value) {
    let mut all = Vec::new();
    leaves(doc, &mut Vec::new(), &mut all);
    let path = rng.pick(&all).clone();
    let (parent, last) = match path.split_last() {
        Some((last, parent)) => (parent.to_vec(), Some(last.clone())),
        None => (Vec::new(), None),
    };
    let choice = rng.below(10);
    let node = at(doc, &path);
    match (choice, node) {
        (0, _) => {
            // Delete the key or element.
            match (last, at(doc, &parent)) {
                (Some(PathStep::Key(k)), Value::Table(t)) => {
                    t.remove(&k);
                }
                (Some(PathStep::Index(i)), Value::Array(a)) => {
                    a.remove(i);
                }
                _ => {}
            }
        }
        (1, Value::Array(a)) => {
            // Over-long or short arrays.
            if rng.below(2) == 0 {
                let extra = a.first().cloned().unwrap_or(Value::Float(1.0));
                let n = *rng.pick(&[1usize, 7, 1000]);
                a.extend(std::iter::repeat_n(extra, n));
            } else {
                a.pop();
            }
        }
        (2, Value::Table(t)) => {
            t.insert("unexpected_key".into(), Value::Float(1.0));
        }
        (_, Value::Float(x)) => {
            let x = *x;
            *at(doc, &path) = mutate_number(rng, x);
        }
        (_, Value::Integer(n)) => {
            let x = *n as f64;
            *at(doc, &path) = mutate_number(rng, x);
        }
        (_, Value::String(s)) => {
            *s = match rng.below(4) {
                0 => String::new(),
                1 => "no-such-thing".into(),
                2 => "x".repeat(100_000),
                _ => format!("{s}{s}"),
            };
        }
        (_, Value::Boolean(b)) => *b = !*b,
        (_, other) => *other = Value::Float(f64::NAN),
    }
}

/// One text-level corruption: truncation, a deleted, duplicated or swapped line, random bytes.
fn mutate_text(rng: &mut Rng, text: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return text.to_string();
    }
    match rng.below(5) {
        0 => {
            let mut cut = rng.below(text.len());
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            return text[..cut].to_string();
        }
        1 => {
            lines.remove(rng.below(lines.len()));
        }
        2 => {
            let i = rng.below(lines.len());
            let l = lines[i].clone();
            lines.insert(i, l);
        }
        3 => {
            let (i, j) = (rng.below(lines.len()), rng.below(lines.len()));
            lines.swap(i, j);
        }
        _ => {
            let i = rng.below(lines.len());
            let junk: String = (0..1 + rng.below(8))
                .map(|_| *rng.pick(&['\0', '"', '[', '=', '#', '\u{feff}', '9', 'e', '-', ',']))
                .collect();
            let at = rng.below(lines[i].len() + 1);
            let at = (0..=at)
                .rev()
                .find(|k| lines[i].is_char_boundary(*k))
                .unwrap_or(0);
            lines[i].insert_str(at, &junk);
        }
    }
    lines.join("\n")
}

/// A number in a table line replaced by an edge value.
fn mutate_table_number(rng: &mut Rng, text: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = 1 + rng.below(lines.len() - 1);
    let fields: Vec<&str> = lines[i].split_whitespace().collect();
    let k = rng.below(fields.len());
    let new = *rng.pick(&[
        "0", "-1", "1e308", "1.0E+03", "1e-310", "NaN", "inf", "-0", "1.2E", "3396.4", "", "1e-40",
    ]);
    let mut f: Vec<String> = fields.iter().map(|s| s.to_string()).collect();
    f[k] = new.to_string();
    lines[i] = f.join("  ");
    lines.join("\n")
}

/// What one run of the binary did.
enum Outcome {
    Accepted(String),
    Refused(i32, String),
    Failed(String),
}

fn run(dir: &Path, args: &[&str]) -> Outcome {
    let mut child = Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start entrynav");
    // One reader per pipe: a child filling one pipe while we wait on the other would deadlock.
    let drain = |mut r: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            let _ = r.read_to_string(&mut text);
            text
        })
    };
    let out = drain(Box::new(child.stdout.take().unwrap()));
    let err = drain(Box::new(child.stderr.take().unwrap()));
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Outcome::Failed(format!("still running after {} s", LIMIT.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let (o, e) = (out.join().unwrap(), err.join().unwrap());
    match status.code() {
        Some(0) => Outcome::Accepted(o),
        Some(c @ (1 | 2)) if !e.contains("panicked") => Outcome::Refused(c, e),
        Some(c) => Outcome::Failed(format!("exit {c}: {e}")),
        None => Outcome::Failed(format!("killed by a signal: {e}")),
    }
}

/// Every key name of the built-in scenarios (recursively), except words so generic that their
/// appearance in a message says nothing.
fn schema_keys() -> Vec<String> {
    fn walk(v: &Value, out: &mut Vec<String>) {
        match v {
            Value::Table(t) => {
                for (k, c) in t {
                    out.push(k.clone());
                    walk(c, out);
                }
            }
            Value::Array(a) => a.iter().for_each(|c| walk(c, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for name in entrynav::scenario::BUILTIN_NAMES {
        let doc: Value = toml::from_str(entrynav::scenario::builtin_toml(name).unwrap()).unwrap();
        walk(&doc, &mut out);
    }
    out.sort();
    out.dedup();
    out
}

/// Whether an error message names a field or the file (its name, or a line of it). A field is
/// a key of the scenario schema as a whole word; keys that are also common words (`name`,
/// `file`, `model`, ...) count only as a field path (`x.name`) or a field label (`name:`).
fn names_something(err: &str, file: &str, keys: &[String]) -> bool {
    let generic = [
        "name",
        "file",
        "model",
        "kind",
        "format",
        "description",
        "reference",
    ];
    let words: Vec<&str> = err
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .collect();
    let named = |k: &str| {
        if generic.contains(&k) {
            err.contains(&format!(".{k}")) || err.contains(&format!("{k}:"))
        } else {
            words.contains(&k)
        }
    };
    err.contains(file) || err.contains("line ") || keys.iter().any(|k| named(k))
}

/// A printed number that is not finite (`NaN`, `inf`) in an accepted run's output.
fn prints_non_finite(out: &str) -> bool {
    out.split(|c: char| c.is_whitespace() || c == ',' || c == '(' || c == ')')
        .any(|w| matches!(w.trim_end_matches(';'), "NaN" | "inf" | "-inf"))
}

#[derive(Default)]
struct Tally {
    accepted: usize,
    refused: usize,
    failures: Vec<String>,
}

#[test]
fn mutated_scenarios_and_tables_never_panic_hang_or_refuse_silently() {
    let variants: usize = std::env::var("ENTRYNAV_FUZZ_VARIANTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_VARIANTS);
    let only: Option<usize> = std::env::var("ENTRYNAV_FUZZ_ONLY")
        .ok()
        .and_then(|v| v.parse().ok());
    let dir: PathBuf = common::scratch_dir("fuzz", "inputs");
    let names = entrynav::scenario::BUILTIN_NAMES;
    let keys = schema_keys();
    let gram = gram();
    let mut tally = Tally::default();
    let clock = Instant::now();
    for i in (0..variants).filter(|i| only.is_none_or(|o| o == *i)) {
        let mut rng = Rng(SEED ^ i as u64);
        let (file, commands): (String, Vec<Vec<String>>) = if rng.below(4) == 0 {
            let text = if rng.below(2) == 0 {
                mutate_table_number(&mut rng, &gram)
            } else {
                mutate_text(&mut rng, &gram)
            };
            let f = format!("table-{i}.txt");
            std::fs::write(dir.join(&f), text).unwrap();
            (
                f.clone(),
                vec![vec!["atmosphere".into(), "inspect".into(), f]],
            )
        } else {
            let name = *rng.pick(&names);
            let base = entrynav::scenario::builtin_toml(name).unwrap();
            let text = if rng.below(3) == 0 {
                mutate_text(&mut rng, base)
            } else {
                let mut doc: Value = toml::from_str(base).unwrap();
                for _ in 0..1 + rng.below(3) {
                    mutate_value(&mut rng, &mut doc);
                }
                toml::to_string(&doc).unwrap_or_else(|e| format!("# {e}"))
            };
            let f = format!("scenario-{i}.toml");
            std::fs::write(dir.join(&f), text).unwrap();
            // The CSV of every truth sample and measurement, to standard output: scanned for
            // non-finite numbers (a 1e308 m range noise once wrote inf there).
            let mut cmds = vec![
                ["simulate", "--scenario", &f, "--out", "-"]
                    .map(String::from)
                    .to_vec(),
            ];
            if i % 4 == 1 {
                cmds.push(
                    [
                        "trade",
                        "--scenario",
                        &f,
                        "--runs",
                        "2",
                        "--quiet",
                        "--no-pcrlb",
                    ]
                    .map(String::from)
                    .to_vec(),
                );
            }
            (f, cmds)
        };
        for cmd in &commands {
            let args: Vec<&str> = cmd.iter().map(String::as_str).collect();
            let what = format!("variant {i} ({file}): entrynav {}", args.join(" "));
            match run(&dir, &args) {
                Outcome::Accepted(out) if prints_non_finite(&out) => tally.failures.push(format!(
                    "{what}: accepted and printed a non-finite number:\n{out}"
                )),
                Outcome::Accepted(_) => tally.accepted += 1,
                Outcome::Refused(_, err) if names_something(&err, &file, &keys) => {
                    tally.refused += 1
                }
                Outcome::Refused(code, err) => tally.failures.push(format!(
                    "{what}: exit {code} naming no field or file: {err}"
                )),
                Outcome::Failed(why) => tally.failures.push(format!("{what}: {why}")),
            }
        }
    }
    println!(
        "fuzz: {variants} variants in {:.1} s: {} runs accepted, {} refused naming a field or \
         file, {} failures (inputs in {})",
        clock.elapsed().as_secs_f64(),
        tally.accepted,
        tally.refused,
        tally.failures.len(),
        dir.display()
    );
    assert!(
        tally.failures.is_empty(),
        "{} failures (replay one with ENTRYNAV_FUZZ_ONLY=i):\n{}",
        tally.failures.len(),
        tally.failures.join("\n---\n")
    );
}
