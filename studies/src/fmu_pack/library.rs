//! Where the FMU packer finds the FMU shared library (`libentrynav_fmu.so`, the cdylib of
//! the `entrynav-fmu` crate). `cargo install --path cli` installs only the `entrynav` binary, so
//! the library is looked for, in this order:
//!
//! 1. `--lib PATH` (alias `--library`), which must exist;
//! 2. the `ENTRYNAV_FMU_LIB` environment variable, which must exist;
//! 3. next to the running executable (`target/release/` in a checkout; the `bin/` folder of a
//!    `cargo install --root R` if the library was copied there);
//! 4. `../lib/` of the executable's folder (`R/lib/` of an install root);
//! 5. the target folder this binary was built in (recorded at build time by `build.rs`).
//!
//! When nothing is found the error lists every place looked and how to build the library.

use crate::error::{StudyError, StudyResult};
use std::path::{Path, PathBuf};

/// File name of the FMU library.
pub const LIB_NAME: &str = "libentrynav_fmu.so";

/// Environment variable naming the FMU library.
pub const LIB_ENV: &str = "ENTRYNAV_FMU_LIB";

/// What the search starts from.
pub struct Search {
    /// `--lib PATH`.
    pub flag: Option<PathBuf>,
    /// The value of `ENTRYNAV_FMU_LIB`.
    pub env: Option<PathBuf>,
    /// The running executable.
    pub exe: Option<PathBuf>,
    /// The target profile folder of the build (`target/release`).
    pub build_dir: Option<PathBuf>,
}

impl Search {
    /// The search of this process: its flag, environment, executable and the target folder the
    /// study layer was built in.
    pub fn of_process(flag: Option<&Path>) -> Search {
        Search {
            flag: flag.map(Path::to_path_buf),
            env: std::env::var_os(LIB_ENV)
                .filter(|v| !v.is_empty())
                .map(PathBuf::from),
            exe: std::env::current_exe().ok(),
            build_dir: option_env!("ENTRYNAV_BUILD_PROFILE_DIR").map(PathBuf::from),
        }
    }

    /// The library: the first candidate that is a file.
    pub fn find(&self) -> StudyResult<PathBuf> {
        let usage = StudyError::Refused;
        if let Some(p) = &self.flag {
            return match p.is_file() {
                true => Ok(p.clone()),
                false => Err(usage(format!("--lib {}: no such file", p.display()))),
            };
        }
        if let Some(p) = &self.env {
            return match p.is_file() {
                true => Ok(p.clone()),
                false => Err(usage(format!("{LIB_ENV}={}: no such file", p.display()))),
            };
        }
        let candidates = self.candidates();
        if let Some(found) = candidates.iter().find(|p| p.is_file()) {
            return Ok(found.clone());
        }
        let looked: Vec<String> = candidates
            .iter()
            .map(|p| format!("  {}", p.display()))
            .collect();
        Err(usage(format!(
            "cannot find the FMU library {LIB_NAME}; looked in:\n{}\nbuild it with `cargo build --release -p entrynav-fmu` (it lands in target/release/), then copy it next to the entrynav executable or into ../lib of its folder, set {LIB_ENV}=PATH, or pass --lib PATH",
            looked.join("\n")
        )))
    }

    /// The places searched after `--lib` and `ENTRYNAV_FMU_LIB`, in order, without repeats.
    pub fn candidates(&self) -> Vec<PathBuf> {
        let mut out: Vec<PathBuf> = Vec::new();
        if let Some(dir) = self.exe.as_deref().and_then(Path::parent) {
            out.push(dir.join(LIB_NAME));
            if let Some(up) = dir.parent() {
                out.push(up.join("lib").join(LIB_NAME));
            }
        }
        if let Some(dir) = &self.build_dir {
            out.push(dir.join(LIB_NAME));
        }
        let mut seen = Vec::new();
        out.retain(|p| {
            let key = p.canonicalize().unwrap_or_else(|_| p.clone());
            let fresh = !seen.contains(&key);
            seen.push(key);
            fresh
        });
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("entrynav-fmulib-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("bin")).unwrap();
        std::fs::create_dir_all(d.join("lib")).unwrap();
        std::fs::create_dir_all(d.join("build")).unwrap();
        d
    }

    fn search(r: &Path) -> Search {
        Search {
            flag: None,
            env: None,
            exe: Some(r.join("bin").join("entrynav")),
            build_dir: Some(r.join("build")),
        }
    }

    fn touch(p: &Path) {
        std::fs::write(p, b"\x7fELF").unwrap();
    }

    #[test]
    fn an_installed_binary_finds_the_library_next_to_it_then_in_lib_then_the_build() {
        let r = root("order");
        let s = search(&r);
        touch(&r.join("build").join(LIB_NAME));
        assert_eq!(s.find().unwrap(), r.join("build").join(LIB_NAME));
        touch(&r.join("lib").join(LIB_NAME));
        assert_eq!(s.find().unwrap(), r.join("lib").join(LIB_NAME));
        touch(&r.join("bin").join(LIB_NAME));
        assert_eq!(s.find().unwrap(), r.join("bin").join(LIB_NAME));
    }

    #[test]
    fn the_flag_and_the_environment_come_first_and_must_exist() {
        let r = root("explicit");
        touch(&r.join("bin").join(LIB_NAME));
        let mine = r.join("mine.so");
        touch(&mine);
        let env = Search {
            env: Some(mine.clone()),
            ..search(&r)
        };
        assert_eq!(env.find().unwrap(), mine);
        let flag = Search {
            flag: Some(r.join("bin").join(LIB_NAME)),
            ..env
        };
        assert_eq!(flag.find().unwrap(), r.join("bin").join(LIB_NAME));
        let missing = Search {
            env: Some(r.join("nope.so")),
            ..search(&r)
        };
        let e = missing.find().unwrap_err().to_string();
        assert!(e.contains(LIB_ENV) && e.contains("nope.so"), "{e}");
        assert_eq!(
            missing.find().unwrap_err().kind(),
            crate::ErrorKind::Refused
        );
    }

    #[test]
    fn nothing_found_lists_every_place_looked() {
        let r = root("none");
        let e = search(&r).find().unwrap_err();
        let msg = e.to_string();
        for p in [
            r.join("bin").join(LIB_NAME),
            r.join("lib").join(LIB_NAME),
            r.join("build").join(LIB_NAME),
        ] {
            assert!(
                msg.contains(&p.display().to_string()),
                "{p:?} not in: {msg}"
            );
        }
        assert!(
            msg.contains("cargo build --release -p entrynav-fmu"),
            "{msg}"
        );
        assert_eq!(e.kind(), crate::ErrorKind::Refused);
    }
}
