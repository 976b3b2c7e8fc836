//! `modelDescription.xml` from the variable table (quick-xml).

use crate::vars::{Causality, Model, UNITS, Var, guid_of, variables};
use entrynav::scenario::{Scenario, ScenarioConfig};
use quick_xml::Writer;
use quick_xml::events::{BytesDecl, Event};
use std::io;

/// Log categories the FMUs use.
pub const LOG_CATEGORIES: [(&str, &str); 4] = [
    (
        "logStatusError",
        "Errors: illegal calls, bad arguments, failed steps",
    ),
    (
        "logStatusWarning",
        "Warnings: filter failures, dropped measurements",
    ),
    (
        "logEvents",
        "Initialisation, termination, state save and restore",
    ),
    ("logAll", "Every message"),
];

/// Start time, stop time and step size of the default experiment: the default scenario's
/// duration, with one step per fastest sensor sample.
pub fn default_experiment() -> (f64, f64, f64) {
    let cfg = ScenarioConfig::builtin(crate::vars::DEFAULT_SCENARIO).expect("built-in scenario");
    let stop = cfg.timing.duration_s;
    let truth_step = cfg.timing.truth_step_s;
    let step = Scenario::build(cfg, &entrynav::files::no_files)
        .ok()
        .and_then(|s| {
            s.channels
                .iter()
                .map(|c| c.period_s)
                .min_by(|a, b| a.total_cmp(b))
        })
        .unwrap_or(truth_step);
    (0.0, stop, step)
}

fn fmt_f64(v: f64) -> String {
    format!("{v:?}")
}

/// The `modelDescription.xml` text of `model`.
pub fn model_description(model: Model) -> String {
    write(model).expect("writing XML to memory cannot fail")
}

fn write(model: Model) -> io::Result<String> {
    let vars = variables(model);
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let guid = guid_of(model);
    let version = env!("CARGO_PKG_VERSION");
    let n_vars = vars.len().to_string();
    w.create_element("fmiModelDescription")
        .with_attribute(("fmiVersion", "2.0"))
        .with_attribute(("modelName", model.identifier()))
        .with_attribute(("guid", guid.as_str()))
        .with_attribute(("description", model.description()))
        .with_attribute(("author", "entrynav"))
        .with_attribute(("version", version))
        .with_attribute(("license", "MIT OR Apache-2.0"))
        .with_attribute(("generationTool", "entrynav fmu pack"))
        .with_attribute(("variableNamingConvention", "flat"))
        .with_attribute(("numberOfEventIndicators", "0"))
        .write_inner_content(|w| {
            w.create_element("CoSimulation")
                .with_attribute(("modelIdentifier", model.identifier()))
                .with_attribute(("needsExecutionTool", "false"))
                .with_attribute(("canHandleVariableCommunicationStepSize", "true"))
                .with_attribute(("canInterpolateInputs", "false"))
                .with_attribute(("maxOutputDerivativeOrder", "0"))
                .with_attribute(("canRunAsynchronuously", "false"))
                .with_attribute(("canBeInstantiatedOnlyOncePerProcess", "false"))
                .with_attribute(("canNotUseMemoryManagementFunctions", "true"))
                .with_attribute(("canGetAndSetFMUstate", "true"))
                .with_attribute(("canSerializeFMUstate", "true"))
                .with_attribute(("providesDirectionalDerivative", "false"))
                .write_empty()?;
            w.create_element("UnitDefinitions")
                .write_inner_content(|w| {
                    for (name, exps, display) in UNITS {
                        w.create_element("Unit")
                            .with_attribute(("name", name))
                            .write_inner_content(|w| {
                                let mut base = w.create_element("BaseUnit");
                                for (k, e) in ["kg", "m", "s", "rad"].iter().zip(exps) {
                                    if e != 0 {
                                        base = base.with_attribute((*k, e.to_string().as_str()));
                                    }
                                }
                                base.write_empty()?;
                                if let Some((dn, factor)) = display {
                                    w.create_element("DisplayUnit")
                                        .with_attribute(("name", dn))
                                        .with_attribute(("factor", fmt_f64(factor).as_str()))
                                        .write_empty()?;
                                }
                                Ok(())
                            })?;
                    }
                    Ok(())
                })?;
            w.create_element("LogCategories").write_inner_content(|w| {
                for (name, d) in LOG_CATEGORIES {
                    w.create_element("Category")
                        .with_attribute(("name", name))
                        .with_attribute(("description", d))
                        .write_empty()?;
                }
                Ok(())
            })?;
            let (start, stop, step) = default_experiment();
            w.create_element("DefaultExperiment")
                .with_attribute(("startTime", fmt_f64(start).as_str()))
                .with_attribute(("stopTime", fmt_f64(stop).as_str()))
                .with_attribute(("stepSize", fmt_f64(step).as_str()))
                .write_empty()?;
            w.create_element("ModelVariables")
                .write_inner_content(|w| {
                    for (i, v) in vars.iter().enumerate() {
                        write_var(w, i + 1, v)?;
                    }
                    Ok(())
                })?;
            let outputs: Vec<usize> = vars
                .iter()
                .enumerate()
                .filter(|(_, v)| v.causality == Causality::Output)
                .map(|(i, _)| i + 1)
                .collect();
            w.create_element("ModelStructure")
                .write_inner_content(|w| {
                    for list in ["Outputs", "InitialUnknowns"] {
                        w.create_element(list).write_inner_content(|w| {
                            for i in &outputs {
                                w.create_element("Unknown")
                                    .with_attribute(("index", i.to_string().as_str()))
                                    .write_empty()?;
                            }
                            Ok(())
                        })?;
                    }
                    Ok(())
                })?;
            Ok(())
        })?;
    let _ = n_vars;
    let mut text = String::from_utf8(w.into_inner()).map_err(io::Error::other)?;
    text.push('\n');
    Ok(text)
}

fn write_var(w: &mut Writer<Vec<u8>>, index: usize, v: &Var) -> io::Result<()> {
    let vr = v.vr.to_string();
    let mut e = w
        .create_element("ScalarVariable")
        .with_attribute(("name", v.name.as_str()))
        .with_attribute(("valueReference", vr.as_str()))
        .with_attribute(("description", v.description.as_str()))
        .with_attribute(("causality", v.causality.xml()))
        .with_attribute(("variability", v.variability.xml()));
    if v.causality == Causality::Parameter {
        e = e.with_attribute(("initial", "exact"));
    }
    let _ = index;
    e.write_inner_content(|w| {
        let mut t = w.create_element(v.ty.xml());
        if let Some(u) = v.unit {
            t = t.with_attribute(("unit", u));
        }
        let start = v.start.as_ref().map(|s| s.xml());
        if let Some(s) = &start {
            t = t.with_attribute(("start", s.as_str()));
        }
        t.write_empty()?;
        Ok(())
    })?;
    Ok(())
}

/// File name of `model`'s committed description in the repository's `modelDescription/` folder.
pub fn committed_file_name(model: Model) -> String {
    match model {
        Model::Combined => "modelDescription.xml".into(),
        m => format!("{}.xml", m.identifier()),
    }
}
