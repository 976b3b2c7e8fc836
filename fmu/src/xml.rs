//! `modelDescription.xml` from the variable table (quick-xml).

use crate::vars::{Causality, ENUM_TYPES, EnumType, Model, ModelSpec, TABLE_DATE, UNITS, Var};
use quick_xml::Writer;
use quick_xml::events::{BytesDecl, Event};
use std::io;

/// Log categories the FMUs use.
pub const LOG_CATEGORIES: [(&str, &str); 5] = [
    (
        "logStatusError",
        "Errors: illegal calls, bad arguments, refused requests, failed steps, caught panics",
    ),
    (
        "logStatusWarning",
        "Warnings: filter failures, dropped measurements, a full replay log",
    ),
    (
        "logStatusDiscard",
        "Status queries this FMU cannot answer (fmi2Discard)",
    ),
    (
        "logEvents",
        "Initialisation, termination, state save and restore",
    ),
    ("logAll", "Every message"),
];

pub(crate) fn fmt_f64(v: f64) -> String {
    format!("{v:?}")
}

/// The `modelDescription.xml` text of the generic `model`.
pub fn model_description(model: Model) -> String {
    description_of(&ModelSpec::generic(model))
}

/// The `modelDescription.xml` text of `spec`.
pub fn description_of(spec: &ModelSpec) -> String {
    // Writing to a Vec cannot fail and the bytes are UTF-8 (every piece is a Rust string).
    write(spec).unwrap_or_default()
}

fn write(spec: &ModelSpec) -> io::Result<String> {
    let vars = spec.vars();
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let version = env!("CARGO_PKG_VERSION");
    let description = spec.description();
    let used_enums: Vec<_> = ENUM_TYPES
        .iter()
        .filter(|e| {
            vars.iter()
                .any(|v| v.declared.is_some_and(|d| std::ptr::eq(d, **e)))
        })
        .collect();
    w.create_element("fmiModelDescription")
        .with_attribute(("fmiVersion", "2.0"))
        .with_attribute(("modelName", spec.identifier()))
        .with_attribute(("guid", spec.guid()))
        .with_attribute(("description", description.as_str()))
        .with_attribute(("author", "entrynav"))
        .with_attribute(("version", version))
        .with_attribute(("license", "MIT OR Apache-2.0"))
        .with_attribute(("generationTool", "entrynav fmu pack"))
        .with_attribute(("generationDateAndTime", TABLE_DATE))
        .with_attribute(("variableNamingConvention", "flat"))
        .with_attribute(("numberOfEventIndicators", "0"))
        .write_inner_content(|w| {
            write_cosimulation(w, spec)?;
            write_units(w)?;
            write_type_definitions(w, &used_enums)?;
            write_log_categories(w)?;
            let (start, stop, step) = spec.default_experiment();
            w.create_element("DefaultExperiment")
                .with_attribute(("startTime", fmt_f64(start).as_str()))
                .with_attribute(("stopTime", fmt_f64(stop).as_str()))
                .with_attribute(("stepSize", fmt_f64(step).as_str()))
                .write_empty()?;
            w.create_element("ModelVariables")
                .write_inner_content(|w| {
                    for v in vars {
                        write_var(w, v)?;
                    }
                    Ok(())
                })?;
            write_model_structure(w, vars)?;
            Ok(())
        })?;
    let mut text = String::from_utf8(w.into_inner()).map_err(io::Error::other)?;
    text.push('\n');
    Ok(text)
}

/// The `CoSimulation` element: the capabilities of the FMI 2.0 co-simulation interface.
fn write_cosimulation(w: &mut Writer<Vec<u8>>, spec: &ModelSpec) -> io::Result<()> {
    w.create_element("CoSimulation")
        .with_attribute(("modelIdentifier", spec.identifier()))
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
    Ok(())
}

/// `TypeDefinitions` of the Enumerations `used` (none at all when there are none: the schema
/// needs at least one type in the element).
fn write_type_definitions(w: &mut Writer<Vec<u8>>, used: &[&&EnumType]) -> io::Result<()> {
    if !used.is_empty() {
        w.create_element("TypeDefinitions")
            .write_inner_content(|w| {
                for e in used {
                    w.create_element("SimpleType")
                        .with_attribute(("name", e.name))
                        .with_attribute(("description", e.description))
                        .write_inner_content(|w| {
                            w.create_element("Enumeration").write_inner_content(|w| {
                                for (k, (name, d)) in e.items.iter().enumerate() {
                                    w.create_element("Item")
                                        .with_attribute(("name", *name))
                                        .with_attribute(("value", k.to_string().as_str()))
                                        .with_attribute(("description", *d))
                                        .write_empty()?;
                                }
                                Ok(())
                            })?;
                            Ok(())
                        })?;
                }
                Ok(())
            })?;
    }
    Ok(())
}

/// `ModelStructure`: every output, none of which feeds through from an input.
fn write_model_structure(w: &mut Writer<Vec<u8>>, vars: &[Var]) -> io::Result<()> {
    // ScalarVariable indices (1-based) of the outputs and of the parameters.
    let indices = |c: Causality| -> Vec<usize> {
        vars.iter()
            .enumerate()
            .filter(|(_, v)| v.causality == c)
            .map(|(i, _)| i + 1)
            .collect()
    };
    let outputs = indices(Causality::Output);
    let parameters = indices(Causality::Parameter)
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(" ");
    // No input feeds through: an output at a communication point depends on the inputs
    // held during the steps before it, never on the current ones (dependencies="").
    // In Initialization Mode the outputs are computed from the parameters only.
    w.create_element("ModelStructure")
        .write_inner_content(|w| {
            for (list, deps) in [("Outputs", ""), ("InitialUnknowns", parameters.as_str())] {
                w.create_element(list).write_inner_content(|w| {
                    for i in &outputs {
                        w.create_element("Unknown")
                            .with_attribute(("index", i.to_string().as_str()))
                            .with_attribute(("dependencies", deps))
                            .write_empty()?;
                    }
                    Ok(())
                })?;
            }
            Ok(())
        })?;
    Ok(())
}

/// `UnitDefinitions` (the same in FMI 2.0 and 3.0).
pub(crate) fn write_units(w: &mut Writer<Vec<u8>>) -> io::Result<()> {
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
    Ok(())
}

/// `LogCategories` (the same in FMI 2.0 and 3.0).
pub(crate) fn write_log_categories(w: &mut Writer<Vec<u8>>) -> io::Result<()> {
    w.create_element("LogCategories").write_inner_content(|w| {
        for (name, d) in LOG_CATEGORIES {
            w.create_element("Category")
                .with_attribute(("name", name))
                .with_attribute(("description", d))
                .write_empty()?;
        }
        Ok(())
    })?;
    Ok(())
}

fn write_var(w: &mut Writer<Vec<u8>>, v: &Var) -> io::Result<()> {
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
    e.write_inner_content(|w| {
        let mut t = w.create_element(v.xml_type());
        if let Some(d) = v.declared {
            t = t.with_attribute(("declaredType", d.name));
        }
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
