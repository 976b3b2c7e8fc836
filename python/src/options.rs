//! Keyword arguments as a study's options struct: the dictionary becomes the struct through
//! serde (unknown keywords and wrong types are `TypeError`s naming the keyword), then the study
//! layer's own check runs, so a value out of range gets exactly the message the command line
//! prints for it ("threads = 1000000 is out of range: must be from 1 to 1024").
//!
//! A Python integer the struct's type cannot hold (a negative count, one beyond 2^64) reaches
//! that check too: it is replaced by a stand-in the type holds, and the message of the check,
//! which names the option, gets the value given back.

use entrynav_studies::options::OptionError;
use entrynav_studies::{StudyError, StudyResult};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde::de::DeserializeOwned;
use serde_json::{Map, Value, json};

/// A Python value as JSON, or the text of a number JSON cannot hold for the struct.
enum Converted {
    Json(Value),
    /// A number the options' types cannot hold: its text, and the stand-ins to try.
    OutOfType(String, [Value; 2]),
}

fn convert(v: &Bound<'_, PyAny>) -> PyResult<Converted> {
    use Converted::{Json, OutOfType};
    if v.is_none() {
        return Ok(Json(Value::Null));
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(Json(Value::Bool(v.extract()?)));
    }
    if v.is_instance_of::<PyInt>() {
        if let Ok(n) = v.extract::<u64>() {
            return Ok(Json(json!(n)));
        }
        // Negative, or beyond 2^64: no count, size or seed takes it.
        return Ok(OutOfType(v.str()?.to_string(), [json!(0), json!(u64::MAX)]));
    }
    if v.is_instance_of::<PyFloat>() {
        let x: f64 = v.extract()?;
        return Ok(match serde_json::Number::from_f64(x) {
            Some(n) => Json(Value::Number(n)),
            None => OutOfType(format!("{x}"), [json!(f64::MAX), json!(-f64::MAX)]),
        });
    }
    if v.is_instance_of::<PyString>() {
        return Ok(Json(Value::String(v.extract()?)));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for item in v.try_iter()? {
            let item = item?;
            // A negative whole number is a fine list entry (a region's -34 deg).
            if item.is_instance_of::<PyInt>()
                && !item.is_instance_of::<PyBool>()
                && let Ok(n) = item.extract::<i64>()
            {
                items.push(json!(n));
                continue;
            }
            match convert(&item)? {
                Json(j) => items.push(j),
                OutOfType(text, _) => {
                    return Err(PyValueError::new_err(format!(
                        "{text} is out of range for a list entry"
                    )));
                }
            }
        }
        return Ok(Json(Value::Array(items)));
    }
    // numpy scalars and other numbers that know their Python value.
    if let Ok(item) = v.call_method0("item")
        && !item.is(v)
    {
        return convert(&item);
    }
    Err(PyTypeError::new_err(format!(
        "cannot take a {} here",
        v.get_type().name()?
    )))
}

/// The keyword whose value alone fails to deserialise (every other field takes its default).
fn offending_key<T: DeserializeOwned>(map: &Map<String, Value>) -> Option<String> {
    map.iter()
        .find(|(k, v)| {
            let one: Map<String, Value> = [((*k).clone(), (*v).clone())].into_iter().collect();
            serde_json::from_value::<T>(Value::Object(one)).is_err()
        })
        .map(|(k, _)| k.clone())
}

/// The options of `what` (the Python function's name) from `kwargs`, checked by `validate`.
pub fn options<T: DeserializeOwned>(
    what: &str,
    kwargs: Option<&Bound<'_, PyDict>>,
    validate: impl Fn(&T) -> StudyResult<()>,
) -> PyResult<T> {
    let mut map = Map::new();
    let mut out_of_type: Vec<(String, String, [Value; 2])> = Vec::new();
    if let Some(d) = kwargs {
        for (k, v) in d.iter() {
            let key: String = k.extract()?;
            let value = convert(&v).map_err(|e| {
                PyTypeError::new_err(format!("{what}(): {key}: {}", e.value(v.py())))
            })?;
            match value {
                Converted::Json(j) => {
                    map.insert(key, j);
                }
                Converted::OutOfType(text, probes) => {
                    map.insert(key.clone(), probes[0].clone());
                    out_of_type.push((key, text, probes));
                }
            }
        }
    }
    let parsed = parse::<T>(what, &map, &out_of_type)?;
    match validate(&parsed) {
        Err(StudyError::Option(e)) => Err(given_back(e, &out_of_type)),
        Err(e) => Err(crate::errors::study_err(e)),
        Ok(()) => match out_of_type.first() {
            None => Ok(parsed),
            // The first stand-in passed: the other end of the type must name the range.
            Some((key, text, probes)) => {
                let mut probe = map.clone();
                probe.insert(key.clone(), probes[1].clone());
                let range = parse::<T>(what, &probe, &out_of_type)
                    .ok()
                    .and_then(|p| match validate(&p) {
                        Err(StudyError::Option(e)) if e.option == *key => Some(e.allowed),
                        _ => None,
                    })
                    .unwrap_or_else(|| format!("from 0 to {}", u64::MAX));
                Err(PyValueError::new_err(
                    OptionError::new(key, text, range).to_string(),
                ))
            }
        },
    }
}

/// Deserialise, naming the keyword that fails (with the value given, not its stand-in).
fn parse<T: DeserializeOwned>(
    what: &str,
    map: &Map<String, Value>,
    out_of_type: &[(String, String, [Value; 2])],
) -> PyResult<T> {
    serde_json::from_value::<T>(Value::Object(map.clone())).map_err(|e| {
        let text = e.to_string();
        if let Some(rest) = text.strip_prefix("unknown field `") {
            let name = rest.split('`').next().unwrap_or(rest);
            return PyTypeError::new_err(format!(
                "{what}() got an unexpected keyword argument '{name}'"
            ));
        }
        match offending_key::<T>(map) {
            Some(k) => {
                let given = out_of_type
                    .iter()
                    .find(|(o, _, _)| *o == k)
                    .map_or_else(|| map[&k].to_string(), |(_, t, _)| t.clone());
                match expected_in_words(&text) {
                    Some(kind) => PyTypeError::new_err(format!(
                        "{what}(): {k} = {given} has the wrong type: must be {kind}"
                    )),
                    None => PyTypeError::new_err(format!("{what}(): {k} = {given}: {text}")),
                }
            }
            None => PyTypeError::new_err(format!("{what}(): {text}")),
        }
    })
}

/// What serde's "invalid type: …, expected T" asks for, in a Python user's words.
fn expected_in_words(serde_text: &str) -> Option<&'static str> {
    let expected = serde_text.split("expected ").nth(1)?;
    let t = expected.split([' ', ',']).next().unwrap_or(expected);
    Some(match t {
        "u8" | "u16" | "u32" | "u64" | "usize" | "i32" | "i64" => "a whole number (an int)",
        "f32" | "f64" => "a number (an int or a float)",
        "a" if expected.starts_with("a string") => "a string",
        "a" if expected.starts_with("a boolean") => "True or False",
        "a" if expected.starts_with("a sequence") => "a list",
        _ => return None,
    })
}

/// The range check's error with the value the user gave in place of its stand-in.
fn given_back(mut e: OptionError, out_of_type: &[(String, String, [Value; 2])]) -> PyErr {
    if let Some((_, text, _)) = out_of_type.iter().find(|(k, _, _)| *k == e.option) {
        e.value = text.clone();
    }
    PyValueError::new_err(e.to_string())
}
