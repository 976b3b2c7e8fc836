//! The architecture rules ARCHITECTURE.md states, checked on the source tree:
//!
//! * **layers import downward only** — every `crate::module` path in a core module names a module
//!   of a lower layer (the table below is ARCHITECTURE.md's layer table);
//! * **workspace crates depend downward only** — core ← loader ← optimizer, fmu ← cli, and the
//!   shipped FMU library carries no FMI host (`libloading`, `zip`); neither do the `entrynav`
//!   command and the Python package, even through other crates (the FMI host is the developer
//!   crate's, and nothing depends on that);
//! * **no `include_str!`/`include_bytes!` reaches outside its crate** (`cargo package` would
//!   break);
//! * **no file-level import cycle** in any workspace crate (a file that imports one that imports
//!   it back, directly or through others; `import_graph/` reads the `use` paths), and no
//!   `use super::*` outside test code, which would hide such edges from a reader.
//!
//! A failure names the file, the line and the rule.

use std::path::{Path, PathBuf};

mod import_graph;

/// Layer rank of each top-level module of `core/src`, as in ARCHITECTURE.md's table: numerics
/// (0, may import each other), physics in list order (atmosphere, dynamics, beacons, sensors),
/// estimation and guidance (beside each other, neither imports the other), scenario, simulation,
/// analysis. A module may import modules of a lower rank only.
const LAYERS: &[(&str, u32)] = &[
    ("math", 0),
    ("planet", 0),
    ("frames", 0),
    ("state_dim", 0),
    ("files", 0),
    ("fixed_len", 0),
    ("pcrlb_recursion", 0),
    ("lincov", 0),
    ("atmosphere", 1),
    ("dynamics", 2),
    ("beacons", 3),
    ("sensors", 4),
    ("estimation", 5),
    ("guidance", 5),
    ("scenario", 6),
    ("sim", 7),
    ("observability", 8),
];

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("core sits in the workspace")
        .to_path_buf()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n == "target") {
                continue;
            }
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

fn rank(module: &str) -> Option<u32> {
    LAYERS.iter().find(|(m, _)| *m == module).map(|(_, r)| *r)
}

/// The top-level modules a line of code names through `crate::module` (comments excluded).
fn crate_paths(line: &str) -> Vec<String> {
    let code = line.split("//").next().unwrap_or("");
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        let name: String = after
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        // `crate::{a, b}` would hide its modules from this check: refuse it outright.
        if after.starts_with('{') {
            out.push("{".to_string());
        } else if !name.is_empty() {
            out.push(name);
        }
        rest = after;
    }
    out
}

/// Every upward import in `core/src`, as "file:line: module -> imported".
fn upward_imports(src: &Path) -> Vec<String> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut bad = Vec::new();
    for file in files {
        let rel = file.strip_prefix(src).expect("under src");
        let first = rel.components().next().expect("a component");
        let module = first
            .as_os_str()
            .to_string_lossy()
            .trim_end_matches(".rs")
            .to_string();
        if module == "lib" {
            continue;
        }
        let Some(own) = rank(&module) else {
            bad.push(format!(
                "{}: module `{module}` is not in the layer table of this test and ARCHITECTURE.md",
                rel.display()
            ));
            continue;
        };
        let text = std::fs::read_to_string(&file).expect("readable source");
        for (n, line) in text.lines().enumerate() {
            for target in crate_paths(line) {
                if target == module {
                    continue;
                }
                let ok = match rank(&target) {
                    Some(r) => r < own || (r == 0 && own == 0),
                    // Crate-root items (`crate::Planet`) belong to numerics.
                    None => target
                        .chars()
                        .next()
                        .is_some_and(|c| c.is_ascii_uppercase()),
                };
                if !ok {
                    bad.push(format!(
                        "{}:{}: `{module}` (layer {own}) imports `crate::{target}`",
                        rel.display(),
                        n + 1
                    ));
                }
            }
        }
    }
    bad
}

#[test]
fn core_layers_import_downward_only() {
    let bad = upward_imports(&workspace().join("core/src"));
    assert!(
        bad.is_empty(),
        "imports that run up ARCHITECTURE.md's layer table:\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_layer_check_sees_an_upward_import() {
    // The check itself must fail on the defect it exists for (estimation importing sim).
    let dir = std::env::temp_dir().join(format!("entrynav-layers-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("estimation")).unwrap();
    std::fs::write(
        dir.join("estimation/leak.rs"),
        "use crate::sim::engine::TruthSample; // the truth in a filter\nuse crate::math::V3;\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("math.rs"),
        "// crate::sim in a comment is no import\n",
    )
    .unwrap();
    let bad = upward_imports(&dir);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(bad[0].contains("estimation/leak.rs:1") && bad[0].contains("crate::sim"));
}

/// The `[dependencies]` of a workspace crate that are workspace crates or named here.
fn dependencies(manifest: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(manifest).expect("manifest");
    let doc: toml::Table = toml::from_str(&text).expect("valid manifest");
    doc.get("dependencies")
        .and_then(|d| d.as_table())
        .map(|t| t.keys().cloned().collect())
        .unwrap_or_default()
}

#[test]
fn workspace_crates_depend_downward_only() {
    let ws = workspace();
    // crate folder, package name, the workspace crates it may depend on.
    let allowed: &[(&str, &[&str])] = &[
        ("core", &[]),
        ("loader", &["entrynav"]),
        ("optimizer", &["entrynav", "entrynav-loader"]),
        ("fmu", &["entrynav", "entrynav-loader"]),
        ("fmu-archive", &["entrynav", "entrynav-fmu"]),
        ("fmi-host", &["entrynav-fmu", "entrynav-fmu-archive"]),
        (
            "studies",
            &[
                "entrynav",
                "entrynav-loader",
                "entrynav-optimizer",
                "entrynav-fmu",
                "entrynav-fmu-archive",
            ],
        ),
        ("render", &["entrynav", "entrynav-studies"]),
        // The front ends: the study layer and what its results are made of, never each other.
        (
            "cli",
            &[
                "entrynav",
                "entrynav-loader",
                "entrynav-optimizer",
                "entrynav-studies",
                "entrynav-render",
            ],
        ),
        (
            "python",
            &[
                "entrynav",
                "entrynav-loader",
                "entrynav-studies",
                "entrynav-render",
            ],
        ),
        (
            "devtools",
            &[
                "entrynav",
                "entrynav-loader",
                "entrynav-fmu",
                "entrynav-fmi-host",
                "entrynav-studies",
            ],
        ),
    ];
    let workspace_crates = [
        "entrynav",
        "entrynav-loader",
        "entrynav-optimizer",
        "entrynav-fmu",
        "entrynav-fmu-archive",
        "entrynav-studies",
        "entrynav-render",
        "entrynav-cli",
        "entrynav-fmi-host",
        "entrynav-devtools",
        "entrynav-python",
    ];
    let mut bad = Vec::new();
    for (dir, ok) in allowed {
        for dep in dependencies(&ws.join(dir).join("Cargo.toml")) {
            if workspace_crates.contains(&dep.as_str()) && !ok.contains(&dep.as_str()) {
                bad.push(format!("{dir}/Cargo.toml depends on {dep}"));
            }
        }
    }
    // The shipped FMU library contains the FMU only: no FMI host (loading libraries, unzipping).
    for dep in dependencies(&ws.join("fmu/Cargo.toml")) {
        if ["libloading", "zip"].contains(&dep.as_str()) {
            bad.push(format!(
                "fmu/Cargo.toml depends on {dep}: the FMI host belongs outside the FMU"
            ));
        }
    }
    // The developer tools are never shipped: nothing depends on them.
    for (dir, _) in workspace_packages() {
        if dependencies(&ws.join(&dir).join("Cargo.toml")).contains(&"entrynav-devtools".into()) {
            bad.push(format!(
                "{dir}/Cargo.toml depends on the developer crate entrynav-devtools"
            ));
        }
    }
    // The shipped command and Python package carry no FMI host and no library loader, not even
    // through another crate (the FMU test tools that need one are entrynav-dev's).
    for package in ["entrynav-cli", "entrynav-python"] {
        let needs = normal_closure(package);
        for host in ["entrynav-fmi-host", "libloading"] {
            if needs.contains(host) {
                bad.push(format!(
                    "{package} depends on {host} (through its dependencies)"
                ));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// The workspace's packages: (crate folder, package name).
fn workspace_packages() -> Vec<(String, String)> {
    let ws = workspace();
    let mut out = Vec::new();
    for entry in std::fs::read_dir(&ws).expect("workspace") {
        let dir = entry.expect("entry").path();
        let Ok(text) = std::fs::read_to_string(dir.join("Cargo.toml")) else {
            continue;
        };
        let doc: toml::Table = toml::from_str(&text).expect("valid manifest");
        if let Some(name) = doc
            .get("package")
            .and_then(|p| p.get("name"))
            .and_then(|n| n.as_str())
        {
            let folder = dir.file_name().unwrap().to_string_lossy().to_string();
            out.push((folder, name.to_string()));
        }
    }
    out.sort();
    out
}

/// Every package `package` needs to build, transitively: a workspace crate's `[dependencies]`
/// from its manifest (its dev-dependencies are not part of it), any other package's from
/// `Cargo.lock` (which lists only what a registry package builds with).
fn normal_closure(package: &str) -> std::collections::BTreeSet<String> {
    let ws = workspace();
    let folders: std::collections::BTreeMap<String, String> = workspace_packages()
        .into_iter()
        .map(|(dir, name)| (name, dir))
        .collect();
    let lock: toml::Table =
        toml::from_str(&std::fs::read_to_string(ws.join("Cargo.lock")).expect("Cargo.lock"))
            .expect("valid Cargo.lock");
    let mut locked: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    for p in lock["package"].as_array().expect("packages") {
        let deps = p.get("dependencies").and_then(|d| d.as_array());
        locked
            .entry(p["name"].as_str().unwrap().to_string())
            .or_default()
            .extend(
                deps.into_iter()
                    .flatten()
                    .filter_map(|d| d.as_str())
                    // "name" or "name version" when several versions are locked.
                    .map(|d| d.split(' ').next().unwrap_or(d).to_string()),
            );
    }
    let mut seen = std::collections::BTreeSet::new();
    let mut todo = vec![package.to_string()];
    while let Some(p) = todo.pop() {
        let deps = match folders.get(&p) {
            Some(dir) => dependencies(&ws.join(dir).join("Cargo.toml")),
            None => locked.get(&p).cloned().unwrap_or_default(),
        };
        for d in deps {
            if seen.insert(d.clone()) {
                todo.push(d);
            }
        }
    }
    seen
}

#[test]
fn the_dependency_closure_sees_a_crate_two_steps_away() {
    // The developer crate reaches libloading only through the FMI host.
    let dev = normal_closure("entrynav-devtools");
    assert!(
        dev.contains("entrynav-fmi-host") && dev.contains("libloading"),
        "{dev:?}"
    );
    assert!(!normal_closure("entrynav-fmu").contains("libloading"));
}

/// The crate folder (nearest ancestor with a Cargo.toml) of `file`.
fn crate_dir(file: &Path) -> PathBuf {
    let mut d = file.parent().expect("a folder");
    while !d.join("Cargo.toml").exists() {
        d = d.parent().expect("inside a crate");
    }
    d.to_path_buf()
}

#[test]
fn embedded_files_stay_inside_their_crate() {
    let ws = workspace();
    let mut files = Vec::new();
    for entry in std::fs::read_dir(&ws).expect("workspace") {
        let p = entry.expect("entry").path();
        if p.is_dir() && p.join("Cargo.toml").exists() {
            rust_files(&p, &mut files);
        }
    }
    assert!(files.len() > 100, "found only {} Rust files", files.len());
    let mut bad = Vec::new();
    let mut seen = 0;
    for file in &files {
        // This file names the macros in string literals.
        if file.ends_with("core/tests/architecture.rs") {
            continue;
        }
        let text = std::fs::read_to_string(file).expect("readable source");
        for mac in ["include_str!(", "include_bytes!("] {
            for (i, _) in text.match_indices(mac) {
                // The path literal may sit on the next line (rustfmt breaks long calls).
                let arg = text[i + mac.len()..].trim_start();
                let Some(arg) = arg.strip_prefix('"') else {
                    continue;
                };
                let rel = arg.split('"').next().unwrap_or("");
                let line = text[..i].matches('\n').count() + 1;
                seen += 1;
                let target = file.parent().expect("folder").join(rel);
                let target = target
                    .canonicalize()
                    .unwrap_or_else(|e| panic!("{}:{line}: {rel}: {e}", file.display()));
                let home = crate_dir(file).canonicalize().expect("crate folder");
                if !target.starts_with(&home) {
                    bad.push(format!(
                        "{}:{line}: embeds {} from outside its crate {}",
                        file.display(),
                        target.display(),
                        home.display()
                    ));
                }
            }
        }
    }
    assert!(seen >= 10, "found only {seen} embedded files");
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn guidance_never_reaches_the_truth() {
    // Guidance is onboard, like a filter: the layer table keeps `scenario` and `sim` (where the
    // truth model, its draws and samples live) above it. The check must see such a leak ...
    let dir = std::env::temp_dir().join(format!("entrynav-guidance-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("guidance")).unwrap();
    std::fs::write(
        dir.join("guidance/leak.rs"),
        "use crate::sim::engine::TruthSample;\nuse crate::scenario::TruthDraw;\nuse crate::dynamics::EntryModel;\n",
    )
    .unwrap();
    let bad = upward_imports(&dir);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(bad.len(), 2, "{bad:?}");
    // ... and the real guidance layer has none, nor names a truth-only type.
    let src = workspace().join("core/src");
    let mut files = Vec::new();
    rust_files(&src.join("guidance"), &mut files);
    assert!(files.len() >= 6, "guidance files: {files:?}");
    let bad = upward_imports(&src);
    for file in &files {
        let rel = file.strip_prefix(&src).unwrap().display().to_string();
        assert!(!bad.iter().any(|b| b.starts_with(&rel)), "{bad:?}");
        let text = std::fs::read_to_string(file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for name in [
                "TruthSample",
                "TruthDraw",
                "TruthPropagator",
                "truth_model",
                "Scenario",
            ] {
                assert!(
                    !code.contains(name),
                    "{rel}:{}: guidance names the truth-side `{name}`",
                    n + 1
                );
            }
        }
    }
}

/// The `src` folder of every workspace crate: (crate folder, its `src`).
fn crate_sources() -> Vec<(String, PathBuf)> {
    let ws = workspace();
    let mut out: Vec<(String, PathBuf)> = std::fs::read_dir(&ws)
        .expect("workspace")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("Cargo.toml").exists() && p.join("src").is_dir())
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            (name, p.join("src"))
        })
        .collect();
    out.sort();
    out
}

#[test]
fn no_crate_has_a_file_level_import_cycle() {
    let crates = crate_sources();
    assert!(crates.len() >= 7, "found only {crates:?}");
    let mut bad = Vec::new();
    for (name, src) in &crates {
        for cycle in import_graph::cycles(&import_graph::graph(src)) {
            bad.push(format!(
                "{name}: a cycle of imports:\n    {}",
                cycle.join("\n    ")
            ));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_cycle_check_sees_a_planted_cycle() {
    // A two-file cycle through `crate::` and `super::`, and a three-file one through a parent
    // that re-exports a child's item while another child takes the parent's own item; a
    // downward chain beside them is no cycle.
    let dir = std::env::temp_dir().join(format!("entrynav-cycles-{}", std::process::id()));
    let files: &[(&str, &str)] = &[
        ("lib.rs", "mod a;\nmod b;\nmod sim;\nmod down;\nmod leaf;\n"),
        (
            "a.rs",
            "use crate::b::Thing; // crate::leaf in a comment is no import\n",
        ),
        ("b.rs", "pub struct Thing;\nfn f() { super::a::g(); }\n"),
        (
            "sim/mod.rs",
            "mod run;\nmod bound;\npub use run::run;\npub struct TradeError;\n",
        ),
        ("sim/run.rs", "use super::bound::sum;\npub fn run() {}\n"),
        ("sim/bound.rs", "use super::TradeError;\npub fn sum() {}\n"),
        (
            "down.rs",
            "use crate::leaf::X;\nconst S: &str = \"crate::a::\";\n",
        ),
        (
            "leaf.rs",
            "pub struct X;\n#[cfg(test)]\nmod tests {\n    use crate::down::*;\n}\n",
        ),
    ];
    for (path, text) in files {
        let p = dir.join(path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    let cycles = import_graph::cycles(&import_graph::graph(&dir));
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(cycles.len(), 2, "{cycles:?}");
    let all = cycles.concat().join("\n");
    for edge in [
        "a.rs:1 -> ",
        "b.rs:2 -> ",
        "sim/mod.rs:3 -> ",
        "run.rs:1 -> ",
        "bound.rs:1 -> ",
    ] {
        assert!(all.contains(edge), "{edge} missing from {all}");
    }
    assert!(
        !all.contains("down.rs") && !all.contains("leaf.rs"),
        "{all}"
    );
}

#[test]
fn no_glob_import_of_a_parent_outside_tests() {
    let mut bad = Vec::new();
    for (name, src) in crate_sources() {
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        for file in files {
            if file.file_name().is_some_and(|n| n == "tests.rs")
                || file.components().any(|c| c.as_os_str() == "tests")
            {
                continue;
            }
            let text = std::fs::read_to_string(&file).expect("readable source");
            let code = import_graph::without_test_modules(&import_graph::code_only(&text));
            for (n, line) in code.lines().enumerate() {
                if line.contains("use super::*") {
                    bad.push(format!(
                        "{name}/{}:{}: `use super::*` hides what the file imports",
                        file.strip_prefix(&src).unwrap().display(),
                        n + 1
                    ));
                }
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
