//! Helpers shared by the CLI integration tests: run the built `entrynav`, make a scratch folder.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Run `entrynav args…`; returns (exit code, stdout, stderr).
pub fn entrynav(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args(args)
        .output()
        .expect("run entrynav");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh per-process scratch folder `entrynav-<suite>-<pid>-<name>` under the temp dir.
pub fn scratch_dir(suite: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("entrynav-{suite}-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A running `entrynav` with `ENTRYNAV_PROGRESS=lines` whose standard error is read line by
/// line, so a test can wait for runs to finish instead of sleeping.
pub struct Running {
    child: std::process::Child,
    stderr: std::io::BufReader<std::process::ChildStderr>,
    /// Standard error read so far.
    pub err: String,
    /// The run count of the last `progress: DONE/TOTAL runs` line read.
    pub last_progress: Option<u64>,
}

/// Start `entrynav args…` with line progress on a piped standard error; `stdout` says where its
/// standard output goes (`Stdio::null()`, or `Stdio::piped()` left unread to hold the process
/// in its first large write).
pub fn spawn_with_progress(args: &[&str], stdout: std::process::Stdio) -> Running {
    let mut child = Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args(args)
        .env("ENTRYNAV_PROGRESS", "lines")
        .stdout(stdout)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start entrynav");
    let stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    Running {
        child,
        stderr,
        err: String::new(),
        last_progress: None,
    }
}

impl Running {
    /// Read standard error up to and including the next line that satisfies `wanted`; panics,
    /// with what was read, if the process closes standard error first.
    pub fn wait_for_line(&mut self, wanted: impl Fn(&str) -> bool) -> String {
        use std::io::BufRead;
        loop {
            let mut line = String::new();
            let n = self.stderr.read_line(&mut line).unwrap();
            assert!(
                n > 0,
                "entrynav ended before the line awaited:\n{}",
                self.err
            );
            self.err.push_str(&line);
            if let Some(done) = progress_runs(&line) {
                self.last_progress = Some(done);
            }
            if wanted(line.trim_end()) {
                return line.trim_end().to_string();
            }
        }
    }

    /// Wait for a progress line reporting more than `after` finished runs; returns its count.
    pub fn wait_for_runs(&mut self, after: u64) -> u64 {
        let line = self.wait_for_line(|l| progress_runs(l).is_some_and(|d| d > after));
        progress_runs(&line).unwrap()
    }

    /// Send SIGINT (Ctrl-C) to the process.
    pub fn interrupt(&self) {
        let sent = Command::new("kill")
            .args(["-INT", &self.child.id().to_string()])
            .status()
            .unwrap();
        assert!(sent.success(), "kill -INT failed");
    }

    /// Kill the process outright (SIGKILL, as a power loss or the OOM killer would) and reap it.
    pub fn kill(mut self) -> String {
        self.child.kill().expect("kill entrynav");
        self.child.wait().expect("reap entrynav");
        self.err
    }

    /// Read the rest of standard error and wait for the process to end; panics (and kills it)
    /// if it is still running after `limit_s` seconds.
    pub fn finish(mut self, limit_s: u64) -> Finished {
        use std::io::BufRead;
        let mut stderr = self.stderr;
        let reader = std::thread::spawn(move || {
            let (mut rest, mut last) = (String::new(), None);
            let mut line = String::new();
            while stderr.read_line(&mut line).unwrap_or(0) > 0 {
                if let Some(done) = progress_runs(&line) {
                    last = Some(done);
                }
                rest.push_str(&line);
                line.clear();
            }
            (rest, last)
        });
        let clock = std::time::Instant::now();
        let status = loop {
            if let Some(s) = self.child.try_wait().unwrap() {
                break s;
            }
            if clock.elapsed().as_secs() >= limit_s {
                let _ = self.child.kill();
                panic!("entrynav still running {limit_s} s after being told to stop");
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        };
        let (rest, last) = reader.join().unwrap();
        self.err.push_str(&rest);
        Finished {
            status,
            err: self.err,
            last_progress: last.or(self.last_progress),
        }
    }
}

/// How a [`Running`] process ended.
pub struct Finished {
    /// Its exit status.
    pub status: std::process::ExitStatus,
    /// All of its standard error.
    pub err: String,
    /// The run count of its last progress line.
    pub last_progress: Option<u64>,
}

/// The run count of a `progress: DONE/TOTAL runs` line.
pub fn progress_runs(line: &str) -> Option<u64> {
    let rest = line.trim_end().strip_prefix("progress: ")?;
    let (done, _) = rest.strip_suffix(" runs")?.split_once('/')?;
    done.parse().ok()
}

/// The filters' blocks of `trade --scenario SCENARIO --filters FILTERS --runs RUNS --seed SEED
/// --no-pcrlb --json JSON` (which must succeed).
pub fn trade_filters(
    scenario: &Path,
    filters: &str,
    runs: u32,
    seed: u64,
    json: &Path,
) -> Vec<serde_json::Value> {
    let (runs, seed) = (runs.to_string(), seed.to_string());
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        scenario.to_str().unwrap(),
        "--filters",
        filters,
        "--runs",
        &runs,
        "--seed",
        &seed,
        "--no-pcrlb",
        "--quiet",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    v["filters"].as_array().unwrap().clone()
}

/// A number of a filter's JSON block.
pub fn num(f: &serde_json::Value, key: &str) -> f64 {
    f[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {f}"))
}

/// `tune --scenario SCENARIO --filter FILTERS --threads 2 --out OUT --quiet` with every other
/// option at its default: (exit code, stdout, stderr).
pub fn tune_defaults(scenario: &Path, filters: &str, out: &Path) -> (i32, String, String) {
    entrynav(&[
        "tune",
        "--scenario",
        scenario.to_str().unwrap(),
        "--filter",
        filters,
        "--threads",
        "2",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ])
}
