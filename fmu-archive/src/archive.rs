//! [`open`]: one of our `.fmu` files extracted into a fresh temporary folder and checked against
//! this build ([`Archive`], the folder removed on drop).

use crate::description::{fmi_version, model_identifier, usable_identifier};
use crate::error::{ArchiveError, Result};
use crate::uri::file_uri;
use entrynav::scenario::BUILTIN_NAMES;
use entrynav_fmu::binding::{Binding, read_library};
use entrynav_fmu::instance::resolve_spec;
use entrynav_fmu::vars::{Model, ModelSpec};
use entrynav_fmu::xml::description_of;
use entrynav_fmu::xml3::{Arrays, description3_of};
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use zip::ZipArchive;

/// An opened FMU: its folder (removed on drop), its model and its library's binding.
pub struct Archive {
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
    /// The extracted library (`binaries/<platform>/<modelIdentifier>.so`).
    pub library: PathBuf,
}

impl Drop for Archive {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// A temporary folder removed on drop unless [`Extracted::keep`] hands it over.
struct Extracted(Option<PathBuf>);

impl Extracted {
    fn keep(mut self) -> PathBuf {
        self.0.take().unwrap_or_default()
    }
}

impl Drop for Extracted {
    fn drop(&mut self) {
        if let Some(d) = &self.0 {
            let _ = std::fs::remove_dir_all(d);
        }
    }
}

/// The model description of `file`, the model identifier it names and its FMI version (2 or 3).
fn read_description(file: &Path, zip: &mut ZipArchive<File>) -> Result<(String, String, u8)> {
    let path = || file.display().to_string();
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .map_err(|source| ArchiveError::Archive {
            path: path(),
            what: "no modelDescription.xml",
            source,
        })?
        .read_to_string(&mut xml)
        .map_err(|source| ArchiveError::Io {
            what: "cannot read modelDescription.xml of",
            path: path(),
            source,
        })?;
    let xml_error = |source| ArchiveError::Xml {
        path: path(),
        source,
    };
    let id = model_identifier(&xml)
        .map_err(xml_error)?
        .filter(|id| usable_identifier(id))
        .ok_or_else(|| ArchiveError::ModelIdentifier { path: path() })?;
    let version = match fmi_version(&xml).map_err(xml_error)?.as_deref() {
        Some("2.0") => 2u8,
        Some("3.0") => 3u8,
        _ => return Err(ArchiveError::StaleModelDescription(id)),
    };
    Ok((xml, id, version))
}

/// Extract `zip` (the archive `file` of model `id`) into a fresh temporary folder.
fn extract(file: &Path, id: &str, zip: &mut ZipArchive<File>) -> Result<Extracted> {
    let dir = std::env::temp_dir().join(format!(
        "entrynav fmu archive {} {id} {}",
        std::process::id(),
        file.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(|source| ArchiveError::Io {
        what: "cannot create",
        path: dir.display().to_string(),
        source,
    })?;
    let guard = Extracted(Some(dir.clone()));
    zip.extract(&dir).map_err(|source| ArchiveError::Archive {
        path: file.display().to_string(),
        what: "cannot extract to the temporary folder",
        source,
    })?;
    Ok(guard)
}

/// The model the library of the FMU extracted to `dir` is bound to (an unbound development
/// library: the generic model `id`); its description must be `xml`, and a generic model must
/// ship every built-in scenario.
fn check_model(
    dir: &Path,
    id: &str,
    version: u8,
    xml: &str,
    binding: Option<&Binding>,
) -> Result<Arc<ModelSpec>> {
    let spec = match binding {
        Some(b) => resolve_spec(Some(b), &b.guid, Some(&file_uri(&dir.join("resources"))))?,
        None => Arc::new(ModelSpec::generic(
            Model::from_identifier(id)
                .ok_or_else(|| ArchiveError::StaleModelDescription(id.to_string()))?,
        )),
    };
    // An FMI 3.0 archive holds either description (with or without the arrays).
    let expected = match version {
        3 => vec![
            description3_of(&spec, Arrays::Omitted),
            description3_of(&spec, Arrays::Declared),
        ],
        _ => vec![description_of(&spec)],
    };
    if !expected.iter().any(|e| e == xml) {
        return Err(ArchiveError::StaleModelDescription(id.to_string()));
    }
    if spec.specific().is_none() {
        for name in BUILTIN_NAMES {
            if !dir.join(format!("resources/{name}.toml")).exists() {
                return Err(ArchiveError::MissingFile(format!("resources/{name}.toml")));
            }
        }
    }
    Ok(spec)
}

/// Extract `file` into a fresh temporary folder; the FMU must be one of ours with the model
/// description this build generates for the model its library is bound to (and, for a generic
/// model, every built-in scenario in `resources/`).
pub fn open(file: &Path) -> Result<Archive> {
    let f = File::open(file).map_err(|source| ArchiveError::Io {
        what: "cannot open",
        path: file.display().to_string(),
        source,
    })?;
    let mut zip = ZipArchive::new(f).map_err(|source| ArchiveError::Archive {
        path: file.display().to_string(),
        what: "not a zip",
        source,
    })?;
    let (xml, id, version) = read_description(file, &mut zip)?;
    let platform = if version == 3 {
        "x86_64-linux"
    } else {
        "linux64"
    };
    let extracted = extract(file, &id, &mut zip)?;
    let dir = extracted.0.clone().unwrap_or_default();
    let so = dir.join("binaries").join(platform).join(format!("{id}.so"));
    let bytes = std::fs::read(&so)
        .map_err(|_| ArchiveError::MissingFile(format!("binaries/{platform}/{id}.so")))?;
    let binding = read_library(&bytes)?;
    let spec = check_model(&dir, &id, version, &xml, binding.as_ref())?;
    Ok(Archive {
        dir: extracted.keep(),
        model: spec.model(),
        spec,
        binding,
        library_bytes: bytes.len() as u64,
        fmi_version: version,
        library: so,
    })
}
