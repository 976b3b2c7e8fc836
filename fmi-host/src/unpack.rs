//! Unpacking one of our `.fmu` files: its archive, its model description (which must be what
//! this build generates for the model its library is bound to) and its loaded library.

use crate::api::Api;
use crate::slave::file_uri;
use crate::{HostError, Result};
use entrynav::scenario::BUILTIN_NAMES;
use entrynav_fmu::binding::{Binding, read_library};
use entrynav_fmu::instance::resolve_spec;
use entrynav_fmu::vars::{Model, ModelSpec};
use entrynav_fmu::xml::description_of;
use entrynav_fmu::xml3::description3_of;
use quick_xml::events::Event;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// An unpacked FMU: its folder (removed on drop), model and loaded library.
pub struct Unpacked {
    /// Where it was extracted.
    pub dir: PathBuf,
    /// Which of our models it is (the base model of a specific FMU).
    pub model: Model,
    /// The model with its table and GUID.
    pub spec: Arc<ModelSpec>,
    /// The library's binding (`None`: an unbound development library).
    pub binding: Option<Binding>,
    /// Size of the shared library in bytes.
    pub library_bytes: u64,
    /// The FMI version of the description: 2 or 3 (the library exports both interfaces).
    pub fmi_version: u8,
    /// The unpacked library.
    pub library: PathBuf,
    /// Its fmi2 functions.
    pub api: Api,
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// The `modelIdentifier` of a co-simulation model description: the attribute of its
/// `<CoSimulation>` element (FMI 2.0 §4.3.1), unescaped; `None` when there is none.
fn model_identifier(xml: &str) -> std::result::Result<Option<String>, quick_xml::Error> {
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

/// Whether `id` can name the library file: non-empty, letters, digits and `_` only.
/// The `fmiVersion` attribute of the description's root element.
fn fmi_version(xml: &str) -> std::result::Result<Option<String>, quick_xml::Error> {
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

fn usable_identifier(id: &str) -> bool {
    !id.is_empty() && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Unpack `file` into a fresh temporary folder and load its library; the FMU must be one of ours
/// with the model description this build generates for the model its library is bound to (and,
/// for a generic model, every built-in scenario in `resources/`).
pub fn unpack(file: &Path) -> Result<Unpacked> {
    let io = |what, path: &Path| {
        let path = path.display().to_string();
        move |source| HostError::Io { what, path, source }
    };
    let path = || file.display().to_string();
    let archive = |what| {
        move |source| HostError::Archive {
            path: path(),
            what,
            source,
        }
    };
    let f = std::fs::File::open(file).map_err(io("cannot open", file))?;
    let mut zip = zip::ZipArchive::new(f).map_err(archive("not a zip"))?;
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .map_err(archive("no modelDescription.xml"))?
        .read_to_string(&mut xml)
        .map_err(io("cannot read modelDescription.xml of", file))?;
    let id = model_identifier(&xml)
        .map_err(|source| HostError::Xml {
            path: path(),
            source,
        })?
        .filter(|id| usable_identifier(id))
        .ok_or_else(|| HostError::ModelIdentifier { path: path() })?;
    let version = match fmi_version(&xml)
        .map_err(|source| HostError::Xml {
            path: path(),
            source,
        })?
        .as_deref()
    {
        Some("2.0") => 2u8,
        Some("3.0") => 3u8,
        _ => return Err(HostError::StaleModelDescription(id)),
    };
    let platform = if version == 3 {
        "x86_64-linux"
    } else {
        "linux64"
    };
    let dir = std::env::temp_dir().join(format!(
        "entrynav fmu check {} {id} {}",
        std::process::id(),
        file.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(io("cannot create", &dir))?;
    zip.extract(&dir)
        .map_err(archive("cannot extract to the temporary folder"))?;
    let so = dir.join("binaries").join(platform).join(format!("{id}.so"));
    let bytes = std::fs::read(&so)
        .map_err(|_| HostError::MissingFile(format!("binaries/{platform}/{id}.so")))?;
    let binding = read_library(&bytes)?;
    let spec = match &binding {
        Some(b) => resolve_spec(Some(b), &b.guid, Some(&file_uri(&dir.join("resources"))))?,
        None => Arc::new(ModelSpec::generic(
            Model::from_identifier(&id)
                .ok_or_else(|| HostError::StaleModelDescription(id.clone()))?,
        )),
    };
    let expected = match version {
        3 => description3_of(&spec),
        _ => description_of(&spec),
    };
    if expected != xml {
        return Err(HostError::StaleModelDescription(id));
    }
    if spec.specific().is_none() {
        for name in BUILTIN_NAMES {
            if !dir.join(format!("resources/{name}.toml")).exists() {
                return Err(HostError::MissingFile(format!("resources/{name}.toml")));
            }
        }
    }
    let api = Api::load(&so)?;
    Ok(Unpacked {
        dir,
        model: spec.model(),
        spec,
        binding,
        library_bytes: bytes.len() as u64,
        fmi_version: version,
        library: so,
        api,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
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
