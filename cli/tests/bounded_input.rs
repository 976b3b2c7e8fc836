//! No hang, no unbounded work from what a user points us at: a FIFO (or any non-regular file)
//! as a scenario or an atmosphere table, and a truth step that implies billions of steps, are
//! refused at once with a message naming the file or the fields.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("entrynav-bounded-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Run `entrynav args` in `dir`; its exit code and standard error, or a failure if it has not
/// ended after 20 s (it is killed then).
fn run_bounded(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read;
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            return (status.code(), err);
        }
        if start.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            panic!("entrynav {args:?} still running after 20 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn mkfifo(dir: &Path, name: &str) {
    let ok = Command::new("mkfifo").arg(dir.join(name)).status().unwrap();
    assert!(ok.success());
}

#[test]
fn a_fifo_as_scenario_or_atmosphere_table_is_refused_at_once() {
    let d = folder("fifo");
    mkfifo(&d, "s.toml");
    mkfifo(&d, "table.txt");
    let (code, err) = run_bounded(&d, &["trade", "--scenario", "s.toml", "--runs", "2"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("s.toml") && err.contains("not a regular file"),
        "{err}"
    );
    let args = [
        "trade",
        "--scenario",
        "msl-airdata",
        "--runs",
        "2",
        "--atmosphere-file",
        "table.txt",
    ];
    let (code, err) = run_bounded(&d, &args);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("table.txt") && err.contains("not a regular file"),
        "{err}"
    );
    // The same table named inside a scenario file.
    let text = entrynav::scenario::builtin_toml("four-beacon-fusion").unwrap();
    let exponential = "model = \"exponential\"\nrho_ref_kgm3 = 2e-4\nref_radius_km = 3437.2\nscale_height_km = 7.5";
    assert!(text.contains(exponential));
    let text = text.replacen(
        exponential,
        "model = \"table\"\nfile = \"table.txt\"\nformat = \"csv\"",
        1,
    );
    std::fs::write(d.join("t.toml"), text).unwrap();
    let (code, err) = run_bounded(&d, &["trade", "--scenario", "t.toml", "--runs", "2"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("table.txt") && err.contains("not a regular file"),
        "{err}"
    );
}

#[test]
fn a_truth_step_that_implies_unbounded_work_is_refused_naming_the_fields() {
    let d = folder("step");
    for step in ["1e-300", "1e-5"] {
        let set = format!("timing.truth_step_s={step}");
        let args = [
            "trade",
            "--scenario",
            "four-beacon-fusion",
            "--runs",
            "2",
            "--set",
            &set,
        ];
        let (code, err) = run_bounded(&d, &args);
        assert_eq!(code, Some(2), "{err}");
        assert!(
            err.contains("timing.truth_step_s")
                && err.contains("timing.duration_s / 1e6 = 3e-4")
                && err.contains("at most 1e6 truth steps per run"),
            "{err}"
        );
    }
}
