//! The FMU library carries only the FMU: no crate of ours that it is built from may depend on
//! the host's libloading or zip (the host lives in `entrynav-fmi-host`). Reads the manifests with
//! the `toml` crate and follows every path dependency of the workspace.

use std::path::{Path, PathBuf};
use toml::Table;

/// Crates the FMU library must not link.
const HOST_ONLY: [&str; 2] = ["libloading", "zip"];

fn read(path: &Path) -> Table {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The `[dependencies]` tables of a manifest, the target-specific ones included (not
/// `[dev-dependencies]` or `[build-dependencies]`: they are not linked into the library).
fn normal_dependencies(manifest: &Table) -> Vec<(String, toml::Value)> {
    let mut tables: Vec<&Table> = manifest
        .get("dependencies")
        .and_then(toml::Value::as_table)
        .into_iter()
        .collect();
    if let Some(targets) = manifest.get("target").and_then(toml::Value::as_table) {
        for t in targets.values() {
            tables.extend(t.get("dependencies").and_then(toml::Value::as_table));
        }
    }
    tables
        .into_iter()
        .flat_map(|t| t.iter().map(|(k, v)| (k.clone(), v.clone())))
        .collect()
}

/// The normal dependencies of `crate_dir` and of every path crate it depends on, as
/// (dependent manifest, dependency name).
fn closure(crate_dir: &Path, workspace: &Table, root: &Path) -> Vec<(PathBuf, String)> {
    let ws_deps = workspace["workspace"]["dependencies"].as_table().unwrap();
    let mut todo = vec![crate_dir.to_path_buf()];
    let mut seen = Vec::new();
    let mut out = Vec::new();
    while let Some(dir) = todo.pop() {
        if seen.contains(&dir) {
            continue;
        }
        seen.push(dir.clone());
        let manifest = dir.join("Cargo.toml");
        for (name, spec) in normal_dependencies(&read(&manifest)) {
            let inherited = spec.get("workspace").and_then(toml::Value::as_bool) == Some(true);
            let spec = if inherited { &ws_deps[&name] } else { &spec };
            let real = spec
                .get("package")
                .and_then(toml::Value::as_str)
                .unwrap_or(&name)
                .to_string();
            if let Some(path) = spec.get("path").and_then(toml::Value::as_str) {
                let base = if inherited { root } else { dir.as_path() };
                todo.push(base.join(path));
            }
            out.push((manifest.clone(), real));
        }
    }
    out
}

#[test]
fn the_fmu_library_depends_on_no_host_crate() {
    let fmu = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = fmu.parent().unwrap();
    let deps = closure(fmu, &read(&root.join("Cargo.toml")), root);
    assert!(
        deps.iter().any(|(_, d)| d == "entrynav"),
        "the walk must reach the core crate: {deps:?}"
    );
    let bad: Vec<_> = deps
        .iter()
        .filter(|(_, d)| HOST_ONLY.contains(&d.as_str()))
        .collect();
    assert!(
        bad.is_empty(),
        "the FMU library would link host-only crates (move that code to fmi-host/): {bad:?}"
    );
}
