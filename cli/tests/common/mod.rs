//! Helpers shared by the CLI integration tests: run the built `entrynav`, make a scratch folder.

#![allow(dead_code)]

use std::path::PathBuf;
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
