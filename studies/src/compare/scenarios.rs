//! What differs between two resolved scenarios (`provenance.scenario` of two trade summaries),
//! as `path: A -> B` lines with the paths `--set` takes (`beacons.0.position_km.1`), for
//! `trade compare`.

use serde_json::Value;

/// At most this many differences are listed (the count is always exact).
const MAX_LISTED: usize = 60;

fn show(v: Option<&Value>) -> String {
    match v {
        None => "(absent)".to_string(),
        Some(Value::String(s)) => format!("{s:?}"),
        Some(v) => {
            let t = v.to_string();
            if t.len() > 80 {
                format!(
                    "{}…",
                    &t[..t.char_indices().nth(77).map_or(t.len(), |(i, _)| i)]
                )
            } else {
                t
            }
        }
    }
}

fn walk(path: &str, a: Option<&Value>, b: Option<&Value>, out: &mut Vec<String>) {
    match (a, b) {
        (Some(Value::Object(x)), Some(Value::Object(y))) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            for k in keys {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                walk(&p, x.get(k), y.get(k), out);
            }
        }
        (Some(Value::Array(x)), Some(Value::Array(y))) if x.len() == y.len() => {
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                walk(&format!("{path}.{i}"), Some(u), Some(v), out);
            }
        }
        _ if a == b => {}
        _ => out.push(format!("{path}: {} -> {}", show(a), show(b))),
    }
}

/// The differences between scenarios `a` and `b`, in path order; past `MAX_LISTED` (60) the rest is
/// summarised in a last line.
pub fn differences(a: &Value, b: &Value) -> Vec<String> {
    let mut out = Vec::new();
    walk("", Some(a), Some(b), &mut out);
    if out.len() > MAX_LISTED {
        let more = out.len() - MAX_LISTED;
        out.truncate(MAX_LISTED);
        out.push(format!("… and {more} more"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn nested_fields_and_array_elements_are_named() {
        let a = json!({"name": "a", "beacons": [{"position_km": [1.0, 2.0]}], "x": {"y": 1}});
        let b = json!({"name": "b", "beacons": [{"position_km": [1.0, 3.0]}], "x": {"y": 1, "z": true}});
        assert_eq!(
            differences(&a, &b),
            vec![
                "beacons.0.position_km.1: 2.0 -> 3.0",
                "name: \"a\" -> \"b\"",
                "x.z: (absent) -> true",
            ]
        );
    }
}
