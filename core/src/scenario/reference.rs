//! The scenario field reference (`docs/scenario-reference.md`, `entrynav scenario schema`),
//! generated from the configuration types themselves: their JSON schema (field names as a file
//! writes them, types, defaults and the doc comments of this crate, via `schemars`) and the
//! ranges validation checks on the built-in scenarios. A field added to the types appears here
//! without anyone writing it down.

use super::{BUILTIN_NAMES, ScenarioConfig};
use serde_json::Value;
use std::collections::BTreeMap;

/// One row of the reference.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldDoc {
    /// Dotted path (`[]` marks an array element, `<name>` a table key chosen by the user).
    pub path: String,
    /// Type as a file writes it.
    pub ty: String,
    /// Default, when the field may be left out.
    pub default: Option<String>,
    /// The doc comment.
    pub description: String,
    /// Allowed range, where validation checks one on a built-in scenario.
    pub range: Option<String>,
}

fn resolve<'a>(root: &'a Value, v: &'a Value) -> &'a Value {
    match v.get("$ref").and_then(Value::as_str) {
        Some(r) => r
            .strip_prefix("#/$defs/")
            .and_then(|name| root.get("$defs")?.get(name))
            .map(|d| resolve(root, d))
            .unwrap_or(v),
        None => v,
    }
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The non-null alternatives of a schema (`anyOf`/`oneOf`, nested ones flattened, `null`
/// removed).
fn alternatives<'a>(root: &'a Value, v: &'a Value) -> Vec<&'a Value> {
    let v = resolve(root, v);
    for key in ["anyOf", "oneOf"] {
        if let Some(list) = v.get(key).and_then(Value::as_array) {
            return list
                .iter()
                .flat_map(|x| alternatives(root, x))
                .filter(|x| x.get("type") != Some(&Value::String("null".into())))
                .collect();
        }
    }
    vec![v]
}

fn type_name(root: &Value, v: &Value) -> String {
    let alts = alternatives(root, v);
    let names: Vec<String> = alts
        .iter()
        .map(|a| {
            if let Some(c) = a.get("const") {
                return c.to_string();
            }
            if let Some(e) = a.get("enum").and_then(Value::as_array) {
                return e
                    .iter()
                    .map(|x| x.to_string())
                    .collect::<Vec<_>>()
                    .join(" | ");
            }
            match a.get("type") {
                Some(Value::String(t)) if t == "array" => {
                    let item = a
                        .get("items")
                        .map(|i| type_name(root, i))
                        .unwrap_or_default();
                    match (a.get("minItems"), a.get("maxItems")) {
                        (Some(n), Some(m)) if n == m => format!("[{item}; {n}]"),
                        _ => format!("[{item}]"),
                    }
                }
                Some(Value::String(t)) if t == "number" => "number".into(),
                Some(Value::String(t)) if t == "integer" => "integer".into(),
                Some(Value::String(t)) => t.clone(),
                Some(Value::Array(ts)) => ts
                    .iter()
                    .filter(|t| *t != "null")
                    .map(|t| t.as_str().unwrap_or("?").to_string())
                    .collect::<Vec<_>>()
                    .join(" | "),
                _ if a.get("properties").is_some() => "table".into(),
                _ => "value".into(),
            }
        })
        .collect();
    let mut unique: Vec<String> = Vec::new();
    for n in names {
        if !unique.contains(&n) {
            unique.push(n);
        }
    }
    unique.join(" | ")
}

fn walk(root: &Value, v: &Value, path: &str, out: &mut Vec<FieldDoc>) {
    for alt in alternatives(root, v) {
        // A table: its fields, and for a tagged enum each variant's.
        if let Some(props) = alt.get("properties").and_then(Value::as_object) {
            for (name, p) in props {
                let child = if path.is_empty() {
                    name.clone()
                } else {
                    format!("{path}.{name}")
                };
                let description = p
                    .get("description")
                    .or_else(|| resolve(root, p).get("description"))
                    .and_then(Value::as_str)
                    .map(one_line)
                    .unwrap_or_default();
                let required = alt
                    .get("required")
                    .and_then(Value::as_array)
                    .is_some_and(|r| r.iter().any(|x| x == name));
                let default = p.get("default").map(|d| d.to_string());
                let ty = type_name(root, p);
                if let Some(f) = out.iter_mut().find(|f| f.path == child) {
                    // The same field in another variant of a tagged enum: list its type too.
                    if !f.ty.split(" | ").any(|t| t == ty) {
                        f.ty = format!("{} | {ty}", f.ty);
                    }
                } else {
                    out.push(FieldDoc {
                        path: child.clone(),
                        ty,
                        default: if required {
                            None
                        } else {
                            default.or(Some("(none)".into()))
                        },
                        description,
                        range: None,
                    });
                }
                walk(root, p, &child, out);
            }
        }
        // Arrays of tables (beacons) and maps (filter.tuned.<name>).
        if let Some(items) = alt.get("items") {
            let item = resolve(root, items);
            if item.get("properties").is_some() || item.get("oneOf").is_some() {
                walk(root, items, &format!("{path}[]"), out);
            }
        }
        if let Some(extra) = alt.get("additionalProperties").filter(|x| x.is_object()) {
            walk(root, extra, &format!("{path}.<name>"), out);
        }
    }
}

/// A range check's field with its indices generalised: `beacons[2].range_sigma_m` →
/// `beacons[].range_sigma_m`, `filter.q_diag[3]` → `filter.q_diag`.
fn general(field: &str) -> String {
    let mut out = String::new();
    let mut chars = field.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '[' {
            for d in chars.by_ref() {
                if d == ']' {
                    break;
                }
            }
            if chars.peek() == Some(&'.') {
                out.push_str("[]");
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// Every field of a scenario file, in schema order, with the ranges validation checks.
pub fn field_reference() -> Vec<FieldDoc> {
    let schema = schemars::schema_for!(ScenarioConfig);
    let root = schema.as_value();
    let mut out = Vec::new();
    walk(root, root, "", &mut out);
    let mut ranges: BTreeMap<String, String> = BTreeMap::new();
    for name in BUILTIN_NAMES {
        if let Ok(checks) = ScenarioConfig::builtin(name).and_then(|c| c.range_checks()) {
            for c in checks {
                let mut key = general(&c.field);
                // A filter's own tuning is checked as the shared field it replaces.
                if let Some((_, field)) = key
                    .strip_prefix("filter.tuned.")
                    .and_then(|rest| rest.split_once('.'))
                {
                    ranges
                        .entry(format!("filter.tuned.<name>.{field}"))
                        .or_insert_with(|| c.range.to_string());
                    key = format!("filter.{field}");
                }
                if !out.iter().any(|f| f.path == key) {
                    key = key.replace("[]", "");
                }
                ranges.entry(key).or_insert_with(|| c.range.to_string());
            }
        }
    }
    for f in &mut out {
        f.range = ranges.get(&f.path).cloned();
    }
    out
}

/// The reference as Markdown (`docs/scenario-reference.md`).
pub fn markdown() -> String {
    let esc = |s: &str| s.replace('|', "\\|");
    let mut md = String::from(
        "# Scenario file reference\n\n\
         Generated by `entrynav scenario schema` from the configuration types (their doc comments) \
         and the ranges validation checks; do not edit by hand (`cargo test -p entrynav --test \
         scenario_reference` fails when this file and the types disagree; \
         `ENTRYNAV_BLESS=1` rewrites it).\n\n\
         Units are in the field names (`_km`, `_m`, `_mps`, `_deg`, `_s`, `_kgm3`, …). `[]` marks \
         an element of an array of tables (`[[beacons]]`); `<name>` a key you choose (a filter \
         name under `filter.tuned`). A field with a default may be left out; \"(none)\" means \
         absent unless given. The allowed column lists the ranges validation checks on the \
         built-in scenarios; fields without one there (beacons, sensors, files) are validated \
         too, with their own messages. \
         `--set PATH=VALUE` reaches any field by its path (a numeric key indexes an array: \
         `beacons.0.lat_deg`).\n\n\
         | field | type | default | allowed | description |\n|---|---|---|---|---|\n",
    );
    for f in field_reference() {
        md += &format!(
            "| `{}` | {} | {} | {} | {} |\n",
            f.path,
            esc(&f.ty),
            esc(f.default.as_deref().unwrap_or("required")),
            esc(f.range.as_deref().unwrap_or("")),
            esc(&f.description)
        );
    }
    md
}
