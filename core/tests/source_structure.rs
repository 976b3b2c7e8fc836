//! The sizes ARCHITECTURE.md sets, checked on every workspace crate's `src`: a file holds at most
//! [`MAX_FILE_LINES`] lines and a function at most [`MAX_FN_LINES`] (test code and the generated
//! tables in [`GENERATED`] excepted). A failure names the file, the function and its length.

use std::path::{Path, PathBuf};

mod import_graph;

/// Longest source file, in lines.
const MAX_FILE_LINES: usize = 400;
/// Longest function, in lines from its `fn` to its closing brace.
const MAX_FN_LINES: usize = 100;
/// Files that are data written by a program, not code a person reads (relative to the workspace).
const GENERATED: &[&str] = &[];

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
    for p in entries.filter_map(|e| e.ok().map(|e| e.path())) {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// Every non-test source file of the workspace's crates, relative to the workspace.
fn sources() -> Vec<PathBuf> {
    let ws = workspace();
    let mut files = Vec::new();
    for entry in std::fs::read_dir(&ws).expect("workspace") {
        let p = entry.expect("entry").path();
        if p.join("Cargo.toml").exists() {
            rust_files(&p.join("src"), &mut files);
        }
    }
    files.sort();
    files
        .into_iter()
        .filter(|f| f.file_name().is_none_or(|n| n != "tests.rs"))
        .map(|f| f.strip_prefix(&ws).expect("in the workspace").to_path_buf())
        .filter(|f| !GENERATED.iter().any(|g| f == Path::new(g)))
        .collect()
}

/// Each function of `code` (comments, literals and inline test modules already removed): its
/// name, first line and length in lines.
fn functions(code: &str) -> Vec<(String, usize, usize)> {
    let b = code.as_bytes();
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(k) = code[from..].find("fn ") {
        let at = from + k;
        from = at + 3;
        if at > 0 && import_graph::ident_char(b[at - 1] as char) {
            continue;
        }
        let name: String = code[at + 3..]
            .chars()
            .take_while(|c| import_graph::ident_char(*c))
            .collect();
        if name.is_empty() {
            continue; // `fn(` types
        }
        // The body starts at the first `{` outside the signature's parentheses and brackets; a
        // `;` before it is a declaration without a body.
        let (mut depth, mut open) = (0i32, None);
        for (i, c) in code[at..].char_indices() {
            match c {
                '(' | '[' | '<' => depth += 1,
                ')' | ']' | '>' => depth -= 1,
                '{' if depth <= 0 => {
                    open = Some(at + i);
                    break;
                }
                ';' if depth <= 0 => break,
                _ => {}
            }
        }
        let Some(open) = open else { continue };
        let mut braces = 0;
        let mut close = code.len();
        for (i, c) in code[open..].char_indices() {
            match c {
                '{' => braces += 1,
                '}' => {
                    braces -= 1;
                    if braces == 0 {
                        close = open + i;
                        break;
                    }
                }
                _ => {}
            }
        }
        let first = code[..at].matches('\n').count() + 1;
        let last = code[..close].matches('\n').count() + 1;
        out.push((name, first, last - first + 1));
    }
    out
}

#[test]
fn source_files_and_functions_stay_short() {
    let ws = workspace();
    let files = sources();
    assert!(files.len() > 300, "found only {} source files", files.len());
    let mut bad = Vec::new();
    for rel in &files {
        let text = std::fs::read_to_string(ws.join(rel)).expect("readable source");
        let lines = text.lines().count();
        if lines > MAX_FILE_LINES {
            bad.push(format!(
                "{}: {lines} lines (at most {MAX_FILE_LINES})",
                rel.display()
            ));
        }
        let code = import_graph::without_test_modules(&import_graph::code_only(&text));
        for (name, line, len) in functions(&code) {
            if len > MAX_FN_LINES {
                bad.push(format!(
                    "{}:{line}: fn {name} is {len} lines (at most {MAX_FN_LINES})",
                    rel.display()
                ));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "{} too long:\n{}",
        bad.len(),
        bad.join("\n")
    );
}

#[test]
fn the_function_measure_counts_from_fn_to_its_closing_brace() {
    let code = "fn short(x: [u8; 2]) -> Vec<u8> {\n    x.to_vec()\n}\ntrait T {\n    fn decl(&self);\n}\nfn long() {\n    if true {\n    }\n\n}\n";
    let f = functions(code);
    assert_eq!(
        f,
        vec![("short".to_string(), 1, 3), ("long".to_string(), 7, 5)]
    );
}
