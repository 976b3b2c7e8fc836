//! The FMU packer (`entrynav fmu pack`, Python's `fmu_pack`): the `.fmu` archives (model description, a stripped copy of the FMU
//! crate's cdylib bound to its model, resources, documentation). Without `--scenario` the four
//! generic FMUs; with a scenario S the combined model specific to S, which embeds the scenario
//! (and the files it refers to) in `resources/` and names its state outputs after its states.

use crate::error::{StudyError, StudyResult};
use crate::fmu_pack::archive_error::ZipOrStudy;
use crate::fmu_pack::options::PackOptions;
use crate::fmu_pack::ssp::write_ssps;
use crate::output::atomic_file::AtomicFile;
use crate::scenario::ScenarioInput;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{BUILTIN_NAMES, builtin_toml};
use entrynav_fmu::ModelSpec;
use entrynav_fmu::binding::{Binding, patch};
use entrynav_fmu::vars::Model;
use entrynav_fmu::{description_of, description3_of};
use std::cell::RefCell;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

/// One packed FMU.
#[derive(Debug, Clone)]
pub struct PackedFmu {
    /// Where it was written.
    pub path: PathBuf,
    /// Its FMI version (2 or 3).
    pub fmi: u8,
    /// Its model identifier.
    pub identifier: String,
    /// Its GUID (instantiation token).
    pub guid: String,
    /// Size of the library in it \[bytes\].
    pub library_bytes: u64,
}

/// What the packer wrote.
#[derive(Debug, Clone, Default)]
pub struct Packed {
    /// The FMUs, in model order.
    pub fmus: Vec<PackedFmu>,
    /// The SSP packages, with `ssp`.
    pub ssps: Vec<PathBuf>,
}

/// The library's bytes, stripped unless `keep`.
fn library(lib: &Path, keep: bool, out: &Path) -> StudyResult<Vec<u8>> {
    let so = std::fs::read(lib).map_err(|e| {
        StudyError::Refused(format!(
            "cannot read the FMU library {} (build it with `cargo build --release -p entrynav-fmu`): {e}",
            lib.display()
        ))
    })?;
    if keep {
        return Ok(so);
    }
    let tmp = out.join(format!(".stripped-{}.so", std::process::id()));
    // `./-1`, not `-1`: a relative name starting with `-` would be read as an option of strip.
    let lib_arg = if lib.is_relative() {
        Path::new(".").join(lib)
    } else {
        lib.to_path_buf()
    };
    let status = Command::new("strip")
        .arg("--strip-all")
        .arg("-o")
        .arg(&tmp)
        .arg(&lib_arg)
        .status()
        .map_err(|e| {
            StudyError::Refused(format!(
                "cannot run `strip` (install binutils, or pass --keep-symbols): {e}"
            ))
        })?;
    if !status.success() {
        return Err(StudyError::Refused(format!(
            "`strip --strip-all {}` failed: {status}",
            lib.display()
        )));
    }
    let stripped = std::fs::read(&tmp)
        .map_err(|e| StudyError::Failed(format!("cannot read {}: {e}", tmp.display())));
    let _ = std::fs::remove_file(&tmp);
    stripped
}

/// The files of `resources/` for `spec`: the built-in scenarios (generic), or the embedded
/// scenario and the files it refers to (specific).
type Resources = Vec<(String, String)>;

/// The specific model of `input` with default filter `filter`, and its resources: the
/// built-in's own text (comments kept) or the file's canonical TOML, and every file it refers to.
fn specific(input: &ScenarioInput, filter: Option<&str>) -> StudyResult<(ModelSpec, Resources)> {
    let builtin = input
        .name
        .as_deref()
        .map(str::trim)
        .filter(|n| BUILTIN_NAMES.contains(n));
    let referenced: RefCell<Vec<(String, String)>> = RefCell::new(Vec::new());
    let read = entrynav_loader::file_loader(&input.dir);
    let record = |p: &str| {
        let text = read(p)?;
        referenced.borrow_mut().push((p.to_string(), text.clone()));
        Ok(text)
    };
    let scenario = Arc::new(entrynav::scenario::Scenario::build(
        input.config.clone(),
        &record,
    )?);
    let file = format!(
        "{}.toml",
        entrynav_fmu::vars::specific_identifier(&input.config.name)
    );
    let text = builtin
        .and_then(builtin_toml)
        .map(str::to_string)
        .unwrap_or_else(|| input.config.to_toml_string());
    let kind = default_filter(&scenario, filter)?;
    let toml = scenario.config.to_toml_string();
    let spec = ModelSpec::for_scenario(scenario, &file, &toml, kind)
        .map_err(|e| StudyError::Refused(e.to_string()))?;
    let mut resources = vec![(file, text)];
    for (p, text) in referenced.into_inner() {
        let plain = Path::new(&p)
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_)));
        if !plain {
            return Err(StudyError::Refused(format!(
                "the scenario refers to '{p}', which cannot be embedded (only files in the scenario's folder or below)"
            )));
        }
        resources.push((p, text));
    }
    Ok((spec, resources))
}

/// The specific FMU's default filter: `filter`, else dcifaif if it fits, else the first that does.
fn default_filter(
    scenario: &entrynav::scenario::Scenario,
    filter: Option<&str>,
) -> StudyResult<FilterKind> {
    match filter {
        Some(f) => FilterKind::parse(f).map_err(|e| StudyError::Refused(e.to_string())),
        None => {
            let fits: Vec<FilterKind> = FilterKind::ALL
                .into_iter()
                .filter(|k| k.misfit(&scenario.onboard).is_none())
                .collect();
            fits.iter()
                .find(|k| k.name() == entrynav_fmu::vars::DEFAULT_FILTER)
                .or(fits.first())
                .copied()
                .ok_or_else(|| StudyError::Refused("no filter fits this scenario".into()))
        }
    }
}

/// The built-in scenario files (`msl-guided.toml` among them: the guidance FMU's default, also
/// for the truth and filter FMUs of the guided SSP).
fn generic_resources() -> Resources {
    BUILTIN_NAMES
        .iter()
        .map(|n| {
            (
                format!("{n}.toml"),
                builtin_toml(n).unwrap_or_default().to_string(),
            )
        })
        .collect()
}

/// Write `spec`'s `.fmu` into `out` with the library `so` bound to it; returns its path.
fn write_fmu(
    out: &Path,
    spec: &ModelSpec,
    so: &[u8],
    resources: &Resources,
    options: &PackOptions,
) -> StudyResult<PathBuf> {
    let id = spec.identifier();
    let binding = Binding {
        identifier: id.to_string(),
        base: spec.model(),
        guid: spec.guid().to_string(),
        scenario: spec
            .specific()
            .map(|s| (s.scenario_file.clone(), s.filter.name().to_string())),
    };
    let bound = patch(so, &binding).map_err(|e| StudyError::Refused(e.to_string()))?;
    let (path, xml, platform) = match options.fmi {
        3 => (
            out.join(format!("{id}-fmi3.fmu")),
            description3_of(spec, options.fmi3_arrays()),
            "x86_64-linux",
        ),
        _ => (
            out.join(format!("{id}.fmu")),
            description_of(spec),
            "linux64",
        ),
    };
    let archive = FmuArchive {
        spec,
        xml: &xml,
        platform,
        library: &bound,
        resources,
    };
    archive.write(&path).map_err(|e| e.at(&path))?;
    Ok(path)
}

/// Pack the FMUs into `out` with the library at `library`: the generic ones, or with `scenario`
/// the combined model specific to it (and with `ssp` the SSP packages). Each packed FMU is read
/// back (model description, binding, resources) and must be the model it was packed for.
pub fn pack_fmus(
    library_path: &Path,
    out: &Path,
    scenario: Option<&ScenarioInput>,
    options: &PackOptions,
) -> StudyResult<Packed> {
    options.validate()?;
    if options.ssp && scenario.is_some() {
        return Err(StudyError::Refused(
            "ssp packs the generic FMUs: give no scenario".into(),
        ));
    }
    crate::input::check_file(library_path, "library")?;
    crate::output::check_output_dir(out, "out")?;
    let so = library(library_path, options.keep_symbols, out)?;
    let models: Vec<(ModelSpec, Resources)> = match scenario {
        Some(s) => vec![specific(s, options.filter.as_deref())?],
        None => Model::ALL
            .into_iter()
            .map(|m| (ModelSpec::generic(m), generic_resources()))
            .collect(),
    };
    let mut packed = Packed::default();
    for (spec, resources) in &models {
        let path = write_fmu(out, spec, &so, resources, options)?;
        packed.fmus.push(read_back(&path, spec, options.fmi)?);
    }
    if options.ssp {
        let (_, stop, _) = ModelSpec::generic(Model::Combined).default_experiment();
        packed.ssps = write_ssps(out, stop)?;
    }
    Ok(packed)
}

/// The packed FMU at `path` read back: it must unpack to the model it was packed for (binding,
/// description and, for a specific FMU, the embedded scenario).
fn read_back(path: &Path, spec: &ModelSpec, fmi: u8) -> StudyResult<PackedFmu> {
    let u = entrynav_fmu_archive::open(path).map_err(|e| {
        StudyError::Failed(format!("the packed {} does not check: {e}", path.display()))
    })?;
    if u.spec.guid() != spec.guid() {
        return Err(StudyError::Failed(format!(
            "{}: GUID changed when unpacked",
            path.display()
        )));
    }
    if u.fmi_version != fmi {
        return Err(StudyError::Failed(format!(
            "{}: FMI version changed when unpacked",
            path.display()
        )));
    }
    Ok(PackedFmu {
        path: path.to_path_buf(),
        fmi,
        identifier: spec.identifier().to_string(),
        guid: spec.guid().to_string(),
        library_bytes: u.library_bytes as u64,
    })
}

/// One `.fmu` archive's contents.
struct FmuArchive<'a> {
    spec: &'a ModelSpec,
    xml: &'a str,
    platform: &'a str,
    library: &'a [u8],
    resources: &'a Resources,
}

impl FmuArchive<'_> {
    /// Write the archive to `path`, whole or not at all.
    fn write(&self, path: &Path) -> Result<(), ZipOrStudy> {
        let (id, platform) = (self.spec.identifier(), self.platform);
        let file = AtomicFile::create(path)?;
        let mut zip = zip::ZipWriter::new(file);
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .unix_permissions(0o644);
        zip.start_file("modelDescription.xml", opts)?;
        zip.write_all(self.xml.as_bytes())?;
        zip.add_directory("binaries/", opts)?;
        zip.add_directory(format!("binaries/{platform}/"), opts)?;
        zip.start_file(
            format!("binaries/{platform}/{id}.so"),
            opts.unix_permissions(0o755),
        )?;
        zip.write_all(self.library)?;
        zip.add_directory("resources/", opts)?;
        for (name, text) in self.resources {
            zip.start_file(format!("resources/{name}"), opts)?;
            zip.write_all(text.as_bytes())?;
        }
        zip.add_directory("documentation/", opts)?;
        zip.start_file("documentation/index.html", opts)?;
        zip.write_all(documentation(self.spec).as_bytes())?;
        zip.finish()?.commit()?;
        Ok(())
    }
}

/// The FMU's `documentation/index.html`: its variables and, for a specific FMU, its scenario.
pub fn documentation(spec: &ModelSpec) -> String {
    let rows: String = spec
        .vars()
        .iter()
        .map(|v| {
            format!(
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                v.vr,
                v.name,
                v.causality.xml(),
                v.xml_type(),
                v.unit.unwrap_or(""),
                v.description.replace('&', "&amp;").replace('<', "&lt;")
            )
        })
        .collect();
    let scenario = match spec.specific() {
        Some(s) => format!(
            "<p>Scenario <code>{}</code> is embedded as <code>resources/{}</code>; the state outputs are named after its states.</p>",
            s.scenario.config.name, s.scenario_file
        ),
        None => "<p>The <code>scenario</code> parameter names a built-in scenario or a file in resources/; a file elsewhere is read only with <code>allow_external_files = true</code>.</p>".to_string(),
    };
    format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{id}</title></head><body>\n<h1>{id}</h1>\n<p>{d}</p>\n{scenario}\n<p>GUID {guid}; the library accepts only this GUID.</p>\n<table border=\"1\"><tr><th>vr</th><th>name</th><th>causality</th><th>type</th><th>unit</th><th>description</th></tr>\n{rows}</table></body></html>\n",
        id = spec.identifier(),
        d = spec.description(),
        guid = spec.guid(),
    )
}
