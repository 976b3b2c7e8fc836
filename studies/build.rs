//! Records the git commit of the build (`git rev-parse HEAD`) for the `provenance` block of a
//! trade JSON, and the build's target folder, where `fmu pack` looks for the FMU library. Outside a git checkout, or without git, the commit is simply unknown: the build
//! never fails because of it.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    // The target profile folder of this build (`<target>/release`), where the FMU library of the
    // same build lands: OUT_DIR is `<target>/<profile>/build/<package>-<hash>/out`.
    if let Some(dir) = std::env::var_os("OUT_DIR")
        .map(std::path::PathBuf::from)
        .and_then(|p| p.ancestors().nth(3).map(std::path::Path::to_path_buf))
    {
        println!(
            "cargo:rustc-env=ENTRYNAV_BUILD_PROFILE_DIR={}",
            dir.display()
        );
    }
    if let Some(commit) = git(&["rev-parse", "HEAD"]) {
        println!("cargo:rustc-env=ENTRYNAV_GIT_COMMIT={commit}");
        // Rebuild when HEAD moves (a commit, a checkout); `--git-path` also works in linked
        // worktrees. A path that does not exist (a packed ref) would rerun every build: skip it.
        let mut watch = vec!["HEAD".to_string()];
        if let Some(r) = git(&["symbolic-ref", "-q", "HEAD"]) {
            watch.push(r);
        }
        for p in &watch {
            if let Some(path) = git(&["rev-parse", "--git-path", p]) {
                if std::path::Path::new(&path).exists() {
                    println!("cargo:rerun-if-changed={path}");
                }
            }
        }
    }
}
