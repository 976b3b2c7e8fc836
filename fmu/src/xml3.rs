//! The FMI 3.0 `modelDescription.xml` of a model, from the same variable table as the FMI 2.0
//! description ([`crate::xml`]) plus the FMI 3.0-only variables ([`crate::vars::fmi3`]).
//!
//! Differences from the FMI 2.0 description, all dictated by FMI 3.0: one element per variable
//! named after its type (`Float64`, `Int32`, `Enumeration`, `Boolean`, `String`, `UInt64`) with
//! the attributes on it; String start values as `<Start value=…/>` children; Enumerations declared
//! as `EnumerationType`; the independent variable `time`; arrays with a `<Dimension>` referring
//! to the structural parameter; `ModelStructure` by value reference; the instantiation token is
//! the model's GUID (the FMU's library accepts the same token through either interface).
//!
//! The arrays are optional ([`Arrays`]): OMSimulator 3.0 cannot load an FMU with a structural
//! parameter and reads arrays as scalars (OpenModelica/OMSimulator#1310, #1418), so the default
//! description declares the scalars only, which every FMI 3.0 tool reads. The library answers
//! the arrays' value references either way; only the description differs.

use crate::vars::fmi3::{Extra, Var3, extras, state_slots};
use crate::vars::{Causality, ENUM_TYPES, EnumType, ModelSpec, TABLE_DATE, Type, Var};
use crate::xml::{fmt_f64, write_log_categories, write_units};
use quick_xml::Writer;
use quick_xml::events::{BytesDecl, Event};
use std::io;

/// Whether an FMI 3.0 description declares the filter's arrays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Arrays {
    /// The scalars of the FMI 2.0 table and `time` only: loads in every FMI 3.0 tool,
    /// OMSimulator 3.0 included (the default of `entrynav fmu pack --fmi 3`).
    #[default]
    Omitted,
    /// Also `est_x`, `est_sigma` (slots) and `est_covariance` (slots x slots), sized by the
    /// structural parameter `n_state_slots` (`entrynav fmu pack --fmi 3 --arrays`).
    Declared,
}

/// The FMI 3.0 `modelDescription.xml` text of `spec`, with or without the arrays.
pub fn description3_of(spec: &ModelSpec, arrays: Arrays) -> String {
    // Writing to a Vec cannot fail and the bytes are UTF-8 (every piece is a Rust string).
    write(spec, arrays).unwrap_or_default()
}

fn write(spec: &ModelSpec, arrays: Arrays) -> io::Result<String> {
    let vars = spec.vars();
    let mut x = extras(spec);
    if arrays == Arrays::Omitted {
        x.retain(|v| v.extra == Extra::Time);
    }
    let slots = state_slots(spec);
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let description = spec.description();
    let used_enums: Vec<_> = ENUM_TYPES
        .iter()
        .filter(|e| {
            vars.iter()
                .any(|v| v.declared.is_some_and(|d| std::ptr::eq(d, **e)))
        })
        .collect();
    w.create_element("fmiModelDescription")
        .with_attribute(("fmiVersion", "3.0"))
        .with_attribute(("modelName", spec.identifier()))
        .with_attribute(("instantiationToken", spec.guid()))
        .with_attribute(("description", description.as_str()))
        .with_attribute(("author", "entrynav"))
        .with_attribute(("version", env!("CARGO_PKG_VERSION")))
        .with_attribute(("license", "MIT OR Apache-2.0"))
        .with_attribute((
            "generationTool",
            match arrays {
                Arrays::Omitted => "entrynav fmu pack --fmi 3",
                Arrays::Declared => "entrynav fmu pack --fmi 3 --arrays",
            },
        ))
        .with_attribute(("generationDateAndTime", TABLE_DATE))
        .with_attribute(("variableNamingConvention", "flat"))
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
            let slots_vr = x.iter().find(|v| v.extra == Extra::Slots).map(|v| v.vr);
            w.create_element("ModelVariables")
                .write_inner_content(|w| {
                    for v in vars {
                        write_var(w, v)?;
                    }
                    for v in &x {
                        write_extra(w, v, slots, slots_vr)?;
                    }
                    Ok(())
                })?;
            write_model_structure(w, vars, &x)?;
            Ok(())
        })?;
    let mut text = String::from_utf8(w.into_inner()).map_err(io::Error::other)?;
    text.push('\n');
    Ok(text)
}

/// The `CoSimulation` element: the capabilities of the FMI 3.0 co-simulation interface.
fn write_cosimulation(w: &mut Writer<Vec<u8>>, spec: &ModelSpec) -> io::Result<()> {
    w.create_element("CoSimulation")
        .with_attribute(("modelIdentifier", spec.identifier()))
        .with_attribute(("needsExecutionTool", "false"))
        .with_attribute(("canBeInstantiatedOnlyOncePerProcess", "false"))
        .with_attribute(("canGetAndSetFMUState", "true"))
        .with_attribute(("canSerializeFMUState", "true"))
        .with_attribute(("providesDirectionalDerivatives", "false"))
        .with_attribute(("providesAdjointDerivatives", "false"))
        .with_attribute(("providesPerElementDependencies", "false"))
        .with_attribute(("canHandleVariableCommunicationStepSize", "true"))
        .with_attribute(("maxOutputDerivativeOrder", "0"))
        .with_attribute(("providesIntermediateUpdate", "false"))
        .with_attribute(("mightReturnEarlyFromDoStep", "false"))
        .with_attribute(("canReturnEarlyAfterIntermediateUpdate", "false"))
        .with_attribute(("hasEventMode", "false"))
        .with_attribute(("providesEvaluateDiscreteStates", "false"))
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
                    w.create_element("EnumerationType")
                        .with_attribute(("name", e.name))
                        .with_attribute(("description", e.description))
                        .write_inner_content(|w| {
                            for (k, (name, d)) in e.items.iter().enumerate() {
                                w.create_element("Item")
                                    .with_attribute(("name", *name))
                                    .with_attribute(("value", k.to_string().as_str()))
                                    .with_attribute(("description", *d))
                                    .write_empty()?;
                            }
                            Ok(())
                        })?;
                }
                Ok(())
            })?;
    }
    Ok(())
}

/// One FMI 3.0-only variable: `time`, the structural parameter (its start the model's `slots`),
/// or an array whose dimensions refer to the structural parameter (value reference `slots_vr`).
fn write_extra(
    w: &mut Writer<Vec<u8>>,
    v: &Var3,
    slots: usize,
    slots_vr: Option<u32>,
) -> io::Result<()> {
    let vr = v.vr.to_string();
    let (element, causality, variability) = match v.extra {
        Extra::Time => ("Float64", "independent", "continuous"),
        Extra::Slots => ("UInt64", "structuralParameter", "fixed"),
        _ => ("Float64", "output", "discrete"),
    };
    let mut e = w
        .create_element(element)
        .with_attribute(("name", v.name))
        .with_attribute(("valueReference", vr.as_str()))
        .with_attribute(("description", v.description))
        .with_attribute(("causality", causality))
        .with_attribute(("variability", variability));
    if v.extra == Extra::Time {
        e = e.with_attribute(("unit", "s"));
    }
    let start = slots.to_string();
    if v.extra == Extra::Slots {
        e = e.with_attribute(("start", start.as_str()));
    }
    match (v.is_array(), slots_vr) {
        (true, Some(d)) => {
            let d = d.to_string();
            let dims = if v.extra == Extra::Covariance { 2 } else { 1 };
            e.write_inner_content(|w| {
                for _ in 0..dims {
                    w.create_element("Dimension")
                        .with_attribute(("valueReference", d.as_str()))
                        .write_empty()?;
                }
                Ok(())
            })?;
        }
        _ => {
            e.write_empty()?;
        }
    }
    Ok(())
}

/// `ModelStructure` by value reference: every output and array, none of which feeds through from
/// an input.
fn write_model_structure(w: &mut Writer<Vec<u8>>, vars: &[Var], x: &[Var3]) -> io::Result<()> {
    // Value references of the outputs and of the parameters. No input feeds through
    // (dependencies=""); in Initialization Mode the outputs follow from the parameters.
    let mut outputs: Vec<u32> = vars
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .map(|v| v.vr)
        .collect();
    outputs.extend(x.iter().filter(|v| v.is_array()).map(|v| v.vr));
    let parameters = vars
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
        .map(|v| v.vr.to_string())
        .collect::<Vec<_>>()
        .join(" ");
    w.create_element("ModelStructure")
        .write_inner_content(|w| {
            for (element, deps) in [("Output", ""), ("InitialUnknown", parameters.as_str())] {
                for vr in &outputs {
                    w.create_element(element)
                        .with_attribute(("valueReference", vr.to_string().as_str()))
                        .with_attribute(("dependencies", deps))
                        .write_empty()?;
                }
            }
            Ok(())
        })?;
    Ok(())
}

/// The FMI 3.0 element of a scalar of the shared table.
fn element(v: &Var) -> &'static str {
    match (v.ty, v.declared) {
        (Type::Real, _) => "Float64",
        (Type::Integer, Some(_)) => "Enumeration",
        (Type::Integer, None) => "Int32",
        (Type::Boolean, _) => "Boolean",
        (Type::String, _) => "String",
    }
}

fn write_var(w: &mut Writer<Vec<u8>>, v: &Var) -> io::Result<()> {
    let vr = v.vr.to_string();
    let mut e = w
        .create_element(element(v))
        .with_attribute(("name", v.name.as_str()))
        .with_attribute(("valueReference", vr.as_str()))
        .with_attribute(("description", v.description.as_str()))
        .with_attribute(("causality", v.causality.xml()))
        .with_attribute(("variability", v.variability.xml()));
    if v.causality == Causality::Parameter {
        e = e.with_attribute(("initial", "exact"));
    }
    if let Some(d) = v.declared {
        e = e.with_attribute(("declaredType", d.name));
    }
    if let Some(u) = v.unit {
        e = e.with_attribute(("unit", u));
    }
    let start = v.start.as_ref().map(|s| s.xml());
    match (v.ty, start) {
        (Type::String, Some(s)) => {
            e.write_inner_content(|w| {
                w.create_element("Start")
                    .with_attribute(("value", s.as_str()))
                    .write_empty()?;
                Ok(())
            })?;
        }
        (_, Some(s)) => {
            e.with_attribute(("start", s.as_str())).write_empty()?;
        }
        (_, None) => {
            e.write_empty()?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vars::Model;

    #[test]
    fn every_scalar_keeps_its_name_and_reference_and_the_arrays_have_dimensions() {
        for m in Model::ALL {
            let spec = ModelSpec::generic(m);
            let xml = description3_of(&spec, Arrays::Declared);
            let scalars = description3_of(&spec, Arrays::Omitted);
            assert!(xml.contains("fmiVersion=\"3.0\""));
            assert!(xml.contains(&format!("instantiationToken=\"{}\"", spec.guid())));
            for v in spec.vars() {
                assert!(
                    xml.contains(&format!("name=\"{}\" valueReference=\"{}\"", v.name, v.vr)),
                    "{}",
                    v.name
                );
            }
            assert_eq!(xml.matches("causality=\"independent\"").count(), 1);
            let dims = xml.matches("<Dimension ").count();
            assert_eq!(dims, if m.has_filter() { 4 } else { 0 });
            assert!(!scalars.contains("<Dimension ") && !scalars.contains("structuralParameter"));
            for v in spec.vars() {
                assert!(
                    scalars.contains(&format!("name=\"{}\" valueReference=\"{}\"", v.name, v.vr))
                );
            }
            assert_eq!(scalars.matches("causality=\"independent\"").count(), 1);
        }
    }
}
