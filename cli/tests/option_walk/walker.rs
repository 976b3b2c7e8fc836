//! The option walker: every option of every subcommand of a clap command tree, given extreme and
//! malformed values on top of a small valid command line, run as a real process. A probe fails
//! on a hang (still running after [`TIMEOUT`]), a crash (a signal, a panic's exit 101 or its
//! message) or an error that does not name the option. An accepted value is fine as long as the
//! run ends in time: the bounds exist so that no value makes the work unbounded.
//!
//! Shared by `cli/tests/option_walk.rs` (`entrynav`) and `devtools/tests/option_walk.rs`
//! (`entrynav-dev`).

#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Longest a probe may run: the acceptance bound.
pub const TIMEOUT: Duration = Duration::from_secs(10);

/// A probe still running after [`TIMEOUT`] while every core runs probes is run again (one retry
/// at a time) with this much time: one that finishes then was slow under load (`fmu pack` writing
/// every FMU while the machine also builds), not hung; a real hang still hangs.
pub const ALONE_TIMEOUT: Duration = Duration::from_secs(60);

/// One leaf command of the tree: its path (`["optimize", "select"]`) and its arguments.
pub struct Leaf {
    /// Subcommand names from the root.
    pub path: Vec<String>,
    /// The leaf's value-taking arguments: (id, long name or value name, positional?, choices?).
    pub options: Vec<OptionInfo>,
}

/// What the walker needs of one argument.
#[derive(Clone, Debug)]
pub struct OptionInfo {
    /// clap's id (the field name).
    pub id: String,
    /// `--long` for an option, the value name (`FILE`) for a positional.
    pub shown: String,
    /// The names a message may use for it: `--grid-deg`, `grid_deg`, `grid-deg`.
    pub names: Vec<String>,
    /// A positional argument (placed after the options).
    pub positional: bool,
    /// The value must be one of clap's possible values (clap checks those itself).
    pub has_choices: bool,
}

/// Every command under `cmd` that takes options or has no subcommands (`trade` and `trade
/// compare` both), the `help` subcommand excluded.
pub fn leaves(cmd: &clap::Command) -> Vec<Leaf> {
    let mut out = Vec::new();
    walk(cmd, &mut Vec::new(), &mut out);
    out
}

fn walk(cmd: &clap::Command, path: &mut Vec<String>, out: &mut Vec<Leaf>) {
    let subs: Vec<&clap::Command> = cmd
        .get_subcommands()
        .filter(|s| s.get_name() != "help")
        .collect();
    let options: Vec<OptionInfo> = cmd
        .get_arguments()
        .filter(|a| a.get_action().takes_values())
        .map(info)
        .collect();
    if subs.is_empty() || !options.is_empty() {
        out.push(Leaf {
            path: path.clone(),
            options,
        });
    }
    for s in subs {
        path.push(s.get_name().to_string());
        walk(s, path, out);
        path.pop();
    }
}

fn info(a: &clap::Arg) -> OptionInfo {
    let id = a.get_id().as_str().to_string();
    let positional = a.is_positional();
    // A positional is named by its value name (`SHARDS`) or by an id long enough not to be a
    // common word (`scenario`; not `a` or `file`, which "No such file" holds).
    let mut names = if positional {
        if id.len() > 4 {
            vec![id.clone()]
        } else {
            Vec::new()
        }
    } else {
        vec![id.clone(), id.replace('_', "-")]
    };
    for alias in a.get_visible_aliases().unwrap_or_default() {
        names.push(format!("--{alias}"));
        names.push(alias.replace('-', "_"));
    }
    let shown = match a.get_long() {
        Some(l) => {
            names.push(format!("--{l}"));
            names.push(l.replace('-', "_"));
            format!("--{l}")
        }
        None => {
            let v = a
                .get_value_names()
                .and_then(|v| v.first())
                .map_or(id.to_uppercase(), |s| s.to_string());
            names.push(v.clone());
            v
        }
    };
    OptionInfo {
        id,
        shown,
        names,
        positional,
        has_choices: !a.get_possible_values().is_empty(),
    }
}

/// The bad values every option is given, in a folder that holds a FIFO named `pipe` and a
/// folder named `folder`.
pub fn extreme_values(dir: &Path) -> Vec<String> {
    let long_name = dir.join("n".repeat(300)).display().to_string();
    let deep: String = "x".repeat(10_240);
    vec![
        "-1".into(),
        "0".into(),
        "10000000000000".into(),
        "1e300".into(),
        "1e-9".into(),
        "-1e300".into(),
        "nan".into(),
        "inf".into(),
        String::new(),
        deep,
        long_name,
        dir.join("pipe").display().to_string(),
        dir.join("folder").display().to_string(),
        "/dev/zero".into(),
    ]
}

/// Make the scratch folder of the probes: a FIFO `pipe` and a folder `folder` in it.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("entrynav-walk-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("folder")).unwrap();
    let ok = Command::new("mkfifo")
        .arg(d.join("pipe"))
        .status()
        .expect("mkfifo");
    assert!(ok.success(), "mkfifo failed");
    d
}

/// One probe: a command line and the option and value it tries.
#[derive(Clone, Debug)]
pub struct Probe {
    /// The command probed (`optimize select`).
    pub command: String,
    /// The whole argument list after the program name.
    pub args: Vec<String>,
    /// The option probed.
    pub option: OptionInfo,
    /// The value given.
    pub value: String,
}

/// The command line of `leaf` from `base` (valid arguments by id, each a list of values; an empty
/// list is a flag), with option `probed` (an id) given `value` instead of its base value.
pub fn line(
    leaf: &Leaf,
    base: &BTreeMap<String, Vec<String>>,
    probed: Option<(&str, &str)>,
) -> Vec<String> {
    let mut args = leaf.path.clone();
    let mut positionals = Vec::new();
    for opt in &leaf.options {
        let given: Vec<String> = match probed {
            Some((id, v)) if id == opt.id => vec![v.to_string()],
            _ => match base.get(&opt.id) {
                Some(vals) => vals.clone(),
                None => continue,
            },
        };
        for g in given {
            if opt.positional {
                positionals.push(g);
            } else {
                args.push(opt.shown.clone());
                args.push(g);
            }
        }
    }
    for (id, vals) in base {
        if vals.is_empty() {
            args.push(format!("--{}", id.replace('_', "-")));
        }
    }
    args.extend(positionals);
    args
}

/// The probes of `leaf`: every option without a fixed set of choices, given every value.
pub fn probes(leaf: &Leaf, base: &BTreeMap<String, Vec<String>>, values: &[String]) -> Vec<Probe> {
    let mut out = Vec::new();
    for o in leaf.options.iter().filter(|o| !o.has_choices) {
        for v in values {
            out.push(Probe {
                command: leaf.path.join(" "),
                args: line(leaf, base, Some((&o.id, v))),
                option: o.clone(),
                value: v.clone(),
            });
        }
    }
    out
}

/// The valid command line of each command (by path, `optimize select`) as option ids and values.
pub type BaseLines = BTreeMap<String, Vec<(&'static str, Vec<String>)>>;

/// Every command under `tree` paired with its base line; panics naming a command without one,
/// or a base line that sets an option its command does not have.
pub fn commands(
    tree: &clap::Command,
    bases: &BaseLines,
) -> Vec<(Leaf, BTreeMap<String, Vec<String>>)> {
    let name = tree.get_name().to_string();
    leaves(tree)
        .into_iter()
        .map(|leaf| {
            let key = leaf.path.join(" ");
            let base: BTreeMap<String, Vec<String>> = bases
                .get(&key)
                .unwrap_or_else(|| panic!("no base line for `{name} {key}`"))
                .iter()
                .map(|(id, v)| (id.to_string(), v.clone()))
                .collect();
            for id in base.keys() {
                assert!(
                    leaf.options.iter().any(|o| o.id == *id),
                    "the base line of `{name} {key}` sets `{id}`, which it does not have"
                );
            }
            (leaf, base)
        })
        .collect()
}

/// The probes of every command of `commands`, after checking that each base line runs cleanly
/// (exit 0), so that what a probe changes is the probed value alone.
pub fn checked_probes(
    program: &Path,
    commands: &[(Leaf, BTreeMap<String, Vec<String>>)],
    dir: &Path,
) -> Vec<Probe> {
    let values = extreme_values(dir);
    let mut probes = Vec::new();
    for (i, (leaf, base)) in commands.iter().enumerate() {
        let args = line(leaf, base, None);
        let out = run(program, &args, dir, 100_000 + i);
        assert_eq!(
            out.code,
            Some(0),
            "the base line `{} {}` does not run cleanly ({:.1} s): {}",
            program.display(),
            args.join(" "),
            out.seconds,
            out.stderr
        );
        probes.extend(self::probes(leaf, base, &values));
    }
    probes
}

/// Run `probes` on every core and fail the test with every failure, one line each.
pub fn assert_all_pass(program: &Path, probes: &[Probe], dir: &Path) {
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let clock = Instant::now();
    let failures = run_all(program, probes, dir, threads);
    eprintln!(
        "{} probes in {:.1} s",
        probes.len(),
        clock.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} of {} probes failed:\n{}",
        failures.len(),
        probes.len(),
        failures.join("\n")
    );
}

/// How a probe ended.
#[derive(Debug)]
pub struct Outcome {
    /// The exit code (`None`: killed by a signal, or by us after the timeout).
    pub code: Option<i32>,
    /// Still running at the timeout.
    pub hung: bool,
    /// Its standard error.
    pub stderr: String,
    /// Wall time.
    pub seconds: f64,
}

/// Run `program args` in a fresh folder `dir/run-{index}` (removed afterwards, so no probe sees
/// another's files) with standard input closed, killed after [`TIMEOUT`].
pub fn run(program: &Path, args: &[String], dir: &Path, index: usize) -> Outcome {
    run_for(program, args, dir, index, TIMEOUT)
}

/// [`run`] with its own timeout.
fn run_for(
    program: &Path,
    args: &[String],
    dir: &Path,
    index: usize,
    timeout: Duration,
) -> Outcome {
    let start = Instant::now();
    let cwd = dir.join(format!("run-{index}"));
    std::fs::create_dir_all(&cwd).unwrap();
    let err_path = dir.join(format!(".stderr-{index}"));
    let err_file = std::fs::File::create(&err_path).unwrap();
    let mut child = Command::new(program)
        .args(args)
        .current_dir(&cwd)
        .env("ENTRYNAV_PROGRESS", "off")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(err_file)
        .spawn()
        .expect("start the program");
    let (code, hung) = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break (status.code(), false);
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            break (None, true);
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let bytes = std::fs::read(&err_path).unwrap_or_default();
    let _ = std::fs::remove_file(&err_path);
    let _ = std::fs::remove_dir_all(&cwd);
    Outcome {
        code,
        hung,
        stderr: String::from_utf8_lossy(&bytes).into_owned(),
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// What is wrong with how `probe` ended, if anything.
pub fn verdict(probe: &Probe, out: &Outcome) -> Option<String> {
    let last = out
        .stderr
        .lines()
        .filter(|l| !l.trim().is_empty())
        .take(3)
        .collect::<Vec<_>>()
        .join(" | ");
    let last: String = last.chars().take(300).collect();
    if out.hung {
        return Some(format!(
            "hang (still running after {} s, and after {} s when run again)",
            TIMEOUT.as_secs(),
            ALONE_TIMEOUT.as_secs()
        ));
    }
    if out.stderr.contains("panicked at") || out.code == Some(101) {
        return Some(format!("panic: {last}"));
    }
    match out.code {
        None => Some(format!("killed by a signal: {last}")),
        Some(0) => None,
        Some(_)
            if probe
                .option
                .names
                .iter()
                .any(|n| names_word(&out.stderr, n)) =>
        {
            None
        }
        Some(1) if out.stderr.contains("warning: the optimum") => None,
        Some(c) => Some(format!(
            "exit {c} without naming {}: {last}",
            probe.option.shown
        )),
    }
}

/// Whether `text` holds `word` as a whole word (not inside a longer name: `k` is not found in
/// `ekf`, `step` not in `search_step`).
pub fn names_word(text: &str, word: &str) -> bool {
    let part = |c: char| c.is_alphanumeric() || c == '_' || c == '-';
    text.match_indices(word).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + word.len()..].chars().next();
        // `--step` starts with '-': only what precedes the dashes counts.
        let before_ok = word.starts_with('-') || before.is_none_or(|c| !part(c));
        before_ok && after.is_none_or(|c| !part(c))
    })
}

/// Run every probe on `threads` workers; the failures, one line each.
pub fn run_all(program: &Path, probes: &[Probe], dir: &Path, threads: usize) -> Vec<String> {
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let alone = Mutex::new(());
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(p) = probes.get(i) else { break };
                    let mut out = run(program, &p.args, dir, i);
                    if out.hung {
                        // Again, one retry at a time, with more time.
                        let _alone = alone.lock().unwrap();
                        out = run_for(program, &p.args, dir, i, ALONE_TIMEOUT);
                    }
                    if let Some(why) = verdict(p, &out) {
                        let mut value: String = p.value.chars().take(40).collect();
                        if p.value.chars().count() > 40 {
                            value.push('…');
                        }
                        failures
                            .lock()
                            .unwrap()
                            .push(format!("{} {} '{value}': {why}", p.command, p.option.shown,));
                    }
                }
            });
        }
    });
    let mut f = failures.into_inner().unwrap();
    f.sort();
    f
}
