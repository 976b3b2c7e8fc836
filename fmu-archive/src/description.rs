//! What is read from a model description as XML (never as text): the co-simulation model
//! identifier and the FMI version.

use quick_xml::events::Event;

/// The `modelIdentifier` of a co-simulation model description: the attribute of its
/// `<CoSimulation>` element (FMI 2.0 §4.3.1), unescaped; `None` when there is none.
pub(crate) fn model_identifier(xml: &str) -> std::result::Result<Option<String>, quick_xml::Error> {
    let mut reader = quick_xml::Reader::from_str(xml);
    loop {
        match reader.read_event()? {
            Event::Start(e) | Event::Empty(e) if e.name().as_ref() == b"CoSimulation" => {
                return match e.try_get_attribute("modelIdentifier")? {
                    Some(a) => Ok(Some(a.unescape_value()?.into_owned())),
                    None => Ok(None),
                };
            }
            Event::Eof => return Ok(None),
            _ => {}
        }
    }
}

/// The `fmiVersion` attribute of the description's root element.
pub(crate) fn fmi_version(xml: &str) -> std::result::Result<Option<String>, quick_xml::Error> {
    let mut reader = quick_xml::Reader::from_str(xml);
    loop {
        match reader.read_event()? {
            Event::Start(e) | Event::Empty(e) if e.name().as_ref() == b"fmiModelDescription" => {
                return match e.try_get_attribute("fmiVersion")? {
                    Some(a) => Ok(Some(a.unescape_value()?.into_owned())),
                    None => Ok(None),
                };
            }
            Event::Eof => return Ok(None),
            _ => {}
        }
    }
}

/// Whether `id` can name the library file: non-empty, letters, digits and `_` only.
pub(crate) fn usable_identifier(id: &str) -> bool {
    !id.is_empty() && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;
    use entrynav_fmu::Model;
    use entrynav_fmu::xml::model_description;

    #[test]
    fn the_model_identifier_is_the_cosimulation_elements_attribute() {
        for m in Model::ALL {
            let xml = model_description(m);
            assert_eq!(
                model_identifier(&xml).unwrap().as_deref(),
                Some(m.identifier())
            );
        }
    }

    #[test]
    fn the_model_identifier_is_read_as_xml_not_as_text() {
        // Attribute order, quotes, escapes, comments and other elements do not fool the parser
        // (a text search for `modelIdentifier="` gets each of these wrong).
        let cases = [
            (
                r#"<fmiModelDescription><!-- modelIdentifier="Comment" --><CoSimulation modelIdentifier="Real"/></fmiModelDescription>"#,
                Some("Real"),
            ),
            (
                r#"<fmiModelDescription description='modelIdentifier="Quoted"'><CoSimulation modelIdentifier='Single'></CoSimulation></fmiModelDescription>"#,
                Some("Single"),
            ),
            (
                r#"<fmiModelDescription><ModelExchange modelIdentifier="Me"/><CoSimulation needsExecutionTool="false" modelIdentifier="A&amp;B"/></fmiModelDescription>"#,
                Some("A&B"),
            ),
            (
                r#"<fmiModelDescription><CoSimulation canHandleVariableCommunicationStepSize="true"/></fmiModelDescription>"#,
                None,
            ),
        ];
        for (xml, want) in cases {
            assert_eq!(model_identifier(xml).unwrap().as_deref(), want, "{xml}");
        }
        assert!(!usable_identifier("A&B"));
        assert!(!usable_identifier("../x"));
        assert!(usable_identifier("MarsEntryNav_msl_airdata"));
    }

    #[test]
    fn malformed_xml_is_an_error() {
        assert!(model_identifier(r#"<a><CoSimulation modelIdentifier="x></a>"#).is_err());
    }
}
