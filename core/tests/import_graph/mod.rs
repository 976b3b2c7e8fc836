#![allow(dead_code)] // each test crate that includes this module uses part of it
//! A reader of `use` paths: which source file of a crate imports which, so that a test can refuse
//! file-level import cycles (a file that imports one that imports it back, directly or through
//! others).
//!
//! A file is a module: `src/lib.rs` (or `src/main.rs`) is the crate root, `src/a/b.rs` and
//! `src/a/b/mod.rs` are `crate::a::b`. An edge goes from a file to the file of the deepest module a
//! path of it names: `use crate::a::b::Item` and `crate::a::b::f()` name `a/b.rs`;
//! `use super::Item` names the parent module's file (so a child that takes an item its parent
//! re-exports depends on the parent, which depends on the file it re-exports from); `child::f()`
//! names a module the file declares. Paths into other crates are not edges. Comments, string
//! literals and `#[cfg(test)]` modules written inline are not read.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

mod lexer;

pub use lexer::{code_only, ident_char, without_test_modules};

/// The module path of every file under `src` (`[]` for the crate root).
fn modules(src: &Path) -> BTreeMap<Vec<String>, PathBuf> {
    let mut files = Vec::new();
    collect(src, &mut files);
    let mut out = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(src).expect("under src");
        let mut parts: Vec<String> = rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy().to_string())
            .collect();
        let last = parts.pop().expect("a file name");
        let stem = last.trim_end_matches(".rs").to_string();
        if parts.is_empty() && (stem == "lib" || stem == "main") {
            // A crate with both: the binary's root is its own crate (it names the library by its
            // crate name), so only the library's root is the module `[]`.
            if stem == "main" && src.join("lib.rs").exists() {
                continue;
            }
        } else if stem != "mod" {
            parts.push(stem);
        }
        out.insert(parts, f);
    }
    out
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            collect(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The modules a file declares with `mod name;` (children in their own files).
fn declared_children(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in code.lines() {
        let t = line.trim_start();
        let t = t
            .strip_prefix("pub(crate) ")
            .or_else(|| t.strip_prefix("pub(super) "))
            .or_else(|| t.strip_prefix("pub "))
            .unwrap_or(t);
        if let Some(rest) = t.strip_prefix("mod ") {
            let name: String = rest.chars().take_while(|c| ident_char(*c)).collect();
            if rest[name.len()..].trim_start().starts_with(';') && !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

/// Every path a `use` tree names, flattened (`a::{b, c::d}` gives `a::b` and `a::c::d`; a glob
/// `a::*` gives `a`).
fn flatten_use(tree: &str) -> Vec<Vec<String>> {
    fn split_top(s: &str) -> Vec<&str> {
        let (mut depth, mut start, mut out) = (0, 0, Vec::new());
        for (i, c) in s.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    out.push(&s[start..i]);
                    start = i + 1;
                }
                _ => {}
            }
        }
        out.push(&s[start..]);
        out
    }
    fn walk(prefix: &[String], s: &str, out: &mut Vec<Vec<String>>) {
        let s = s.trim();
        if s.is_empty() {
            return;
        }
        if let Some(inner) = s.strip_prefix('{').and_then(|r| r.strip_suffix('}')) {
            for part in split_top(inner) {
                walk(prefix, part, out);
            }
            return;
        }
        match s.find("::") {
            Some(i) if !s[..i].contains('{') => {
                let mut p = prefix.to_vec();
                p.push(s[..i].trim().to_string());
                walk(&p, &s[i + 2..], out);
            }
            _ => {
                let name = s.split_whitespace().next().unwrap_or("");
                let mut p = prefix.to_vec();
                if name != "*" && name != "self" {
                    p.push(name.to_string());
                }
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(&[], tree, &mut out);
    out
}

/// The `use` trees of `code` (`use …;`, visibility and line breaks allowed), each with its line.
fn use_trees(code: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let bytes = code.as_bytes();
    let mut search = 0;
    while let Some(k) = code[search..].find("use ") {
        let at = search + k;
        search = at + 4;
        if at > 0 && ident_char(bytes[at - 1] as char) {
            continue;
        }
        // Only at the start of a statement: after a line start, `;`, `{`, `}` or a visibility.
        let before = code[..at].trim_end();
        let ok = before.is_empty()
            || before.ends_with([';', '{', '}', ']'])
            || before.ends_with("pub")
            || before.ends_with(')');
        if !ok {
            continue;
        }
        let Some(end) = code[at..].find(';') else {
            break;
        };
        let line = code[..at].matches('\n').count() + 1;
        out.push((line, code[at + 4..at + end].to_string()));
        search = at + end;
    }
    out
}

/// Every `a::b::…` path written in code outside `use` trees whose first segment is `crate`,
/// `super`, `self` or a declared child module.
fn inline_paths(code: &str, children: &BTreeSet<String>) -> Vec<(usize, Vec<String>)> {
    let chars: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < chars.len() {
        if chars[i] == '\n' {
            line += 1;
        }
        let starts = ident_char(chars[i])
            && !chars[i].is_ascii_digit()
            && (i == 0 || !(ident_char(chars[i - 1]) || chars[i - 1] == ':'));
        if !starts {
            i += 1;
            continue;
        }
        let mut segs = Vec::new();
        let mut j = i;
        loop {
            let s = j;
            while j < chars.len() && ident_char(chars[j]) {
                j += 1;
            }
            segs.push(chars[s..j].iter().collect::<String>());
            if chars.get(j) == Some(&':') && chars.get(j + 1) == Some(&':') {
                j += 2;
                if !chars.get(j).is_some_and(|c| ident_char(*c)) {
                    break;
                }
            } else {
                break;
            }
        }
        let first = segs[0].as_str();
        if segs.len() > 1
            && (matches!(first, "crate" | "super" | "self") || children.contains(first))
        {
            out.push((line, segs));
        }
        i = j.max(i + 1);
    }
    out
}

/// The absolute module path `segs` names from module `here`, or `None` for another crate.
fn absolute(here: &[String], segs: &[String], children: &BTreeSet<String>) -> Option<Vec<String>> {
    let mut path: Vec<String>;
    let mut rest = segs;
    match segs.first().map(String::as_str) {
        Some("crate") => {
            path = Vec::new();
            rest = &segs[1..];
        }
        Some("self") => {
            path = here.to_vec();
            rest = &segs[1..];
        }
        Some("super") => {
            path = here.to_vec();
            while rest.first().map(String::as_str) == Some("super") {
                path.pop();
                rest = &rest[1..];
            }
        }
        Some(first) if children.contains(first) => path = here.to_vec(),
        _ => return None,
    }
    path.extend(rest.iter().cloned());
    Some(path)
}

/// One import of a file: the line and the file it names.
#[derive(Debug, Clone)]
pub struct Edge {
    pub line: usize,
    pub to: PathBuf,
}

/// The import graph of the crate whose sources are under `src`: for each file, the files it
/// imports (no self edges).
pub fn graph(src: &Path) -> BTreeMap<PathBuf, Vec<Edge>> {
    let mods = modules(src);
    let mut out = BTreeMap::new();
    for (here, file) in &mods {
        let text = std::fs::read_to_string(file).expect("readable source");
        let code = without_test_modules(&code_only(&text));
        let children = declared_children(&code);
        let mut edges = Vec::new();
        let mut add = |line: usize, segs: &[String]| {
            let Some(abs) = absolute(here, segs, &children) else {
                return;
            };
            let mut p = abs.as_slice();
            loop {
                if let Some(target) = mods.get(p) {
                    if target != file {
                        edges.push(Edge {
                            line,
                            to: target.clone(),
                        });
                    }
                    return;
                }
                if p.is_empty() {
                    return;
                }
                p = &p[..p.len() - 1];
            }
        };
        let mut outside_use = code.clone();
        for (line, tree) in use_trees(&code) {
            for segs in flatten_use(&tree) {
                add(line, &segs);
            }
            outside_use = outside_use.replacen(&format!("use {tree};"), "", 1);
        }
        for (line, segs) in inline_paths(&outside_use, &children) {
            add(line, &segs);
        }
        out.insert(file.clone(), edges);
    }
    out
}

/// The import cycles of a graph: each strongly connected set of two or more files, with one
/// import per file that keeps it in the cycle ("a.rs:12 -> b.rs").
pub fn cycles(g: &BTreeMap<PathBuf, Vec<Edge>>) -> Vec<Vec<String>> {
    let nodes: Vec<&PathBuf> = g.keys().collect();
    let index: BTreeMap<&PathBuf, usize> = nodes.iter().enumerate().map(|(i, p)| (*p, i)).collect();
    let adj: Vec<Vec<usize>> = nodes
        .iter()
        .map(|n| {
            g[*n]
                .iter()
                .filter_map(|e| index.get(&e.to).copied())
                .collect()
        })
        .collect();
    let comp = strongly_connected(&adj);
    let mut groups: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (v, c) in comp.iter().enumerate() {
        groups.entry(*c).or_default().push(v);
    }
    let mut out = Vec::new();
    for members in groups.values().filter(|m| m.len() > 1) {
        let mut lines = Vec::new();
        for &v in members {
            for e in &g[nodes[v]] {
                if let Some(&w) = index.get(&e.to)
                    && comp[w] == comp[v]
                {
                    lines.push(format!(
                        "{}:{} -> {}",
                        nodes[v].display(),
                        e.line,
                        e.to.display()
                    ));
                }
            }
        }
        lines.dedup();
        out.push(lines);
    }
    out
}

/// The strongly connected component of every node (Tarjan's algorithm, iterative).
fn strongly_connected(adj: &[Vec<usize>]) -> Vec<usize> {
    let n = adj.len();
    let (mut index, mut low, mut comp) = (vec![usize::MAX; n], vec![0; n], vec![usize::MAX; n]);
    let (mut on_stack, mut stack) = (vec![false; n], Vec::new());
    let (mut next, mut ncomp) = (0, 0);
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        let mut work: Vec<(usize, usize)> = vec![(root, 0)];
        index[root] = next;
        low[root] = next;
        next += 1;
        stack.push(root);
        on_stack[root] = true;
        while let Some(&mut (v, ref mut k)) = work.last_mut() {
            if *k < adj[v].len() {
                let w = adj[v][*k];
                *k += 1;
                if index[w] == usize::MAX {
                    index[w] = next;
                    low[w] = next;
                    next += 1;
                    stack.push(w);
                    on_stack[w] = true;
                    work.push((w, 0));
                } else if on_stack[w] {
                    low[v] = low[v].min(index[w]);
                }
            } else {
                work.pop();
                if let Some(&(u, _)) = work.last() {
                    low[u] = low[u].min(low[v]);
                }
                if low[v] == index[v] {
                    while let Some(w) = stack.pop() {
                        on_stack[w] = false;
                        comp[w] = ncomp;
                        if w == v {
                            break;
                        }
                    }
                    ncomp += 1;
                }
            }
        }
    }
    comp
}
