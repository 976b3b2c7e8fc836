//! `entrynav fmu pack`: the `.fmu` archives (model description, a stripped copy of the FMU
//! crate's cdylib bound to its model, resources, documentation). Without `--scenario` the four
//! generic FMUs; with `--scenario S` the combined model specific to S, which embeds the scenario
//! (and the files it refers to) in `resources/` and names its state outputs after its states.

use anyhow::{Context, Result, ensure};
use clap::Args;
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

/// Arguments of `entrynav fmu pack`.
#[derive(Args)]
pub(super) struct PackArgs {
    /// Output folder.
    #[arg(long, default_value = "target/fmu")]
    out: PathBuf,
    /// The FMU shared library (build it with `cargo build --release -p entrynav-fmu`). Default:
    /// $ENTRYNAV_FMU_LIB, else libentrynav_fmu.so next to this executable, in ../lib, or in
    /// the target folder it was built in.
    #[arg(long, visible_alias = "library")]
    lib: Option<PathBuf>,
    /// Pack the combined model specific to this scenario (a built-in name or a TOML file) instead
    /// of the five generic FMUs.
    #[arg(long)]
    scenario: Option<String>,
    /// Default filter of the scenario-specific FMU (default: dcifaif if it fits the scenario,
    /// else the first filter that does).
    #[arg(long, requires = "scenario")]
    filter: Option<String>,
    /// Also write SSP 1.0 packages of the generic FMUs: `MarsEntrySplit.ssp` (truth -> filter,
    /// the filter one step late), `MarsEntryNav.ssp` (the combined FMU) and `MarsEntryGuided.ssp`
    /// (truth -> filter -> guidance -> truth bank on msl-guided.toml), each with its parameters
    /// in an .ssv.
    #[arg(long, conflicts_with = "scenario")]
    ssp: bool,
    /// FMI version of the packed FMUs: 2 (FMI 2.0, `<id>.fmu`) or 3 (FMI 3.0, `<id>-fmi3.fmu`:
    /// the same variables and value references, plus `time`, the structural parameter
    /// `n_state_slots` and the arrays `est_x`, `est_sigma`, `est_covariance`). The library is
    /// the same and exports both interfaces.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
    fmi: u8,
    /// Ship the library with its symbols and debug information (by default it is stripped with
    /// binutils' `strip --strip-all`).
    #[arg(long)]
    keep_symbols: bool,
}

/// The library's bytes, stripped unless `keep`.
fn library(lib: &Path, keep: bool, out: &Path) -> Result<Vec<u8>> {
    let so = std::fs::read(lib).with_context(|| {
        format!(
            "cannot read the FMU library {} (build it with `cargo build --release -p entrynav-fmu`)",
            lib.display()
        )
    })?;
    if keep {
        return Ok(so);
    }
    let tmp = out.join(format!(".stripped-{}.so", std::process::id()));
    let status = Command::new("strip")
        .arg("--strip-all")
        .arg("-o")
        .arg(&tmp)
        .arg(lib)
        .status()
        .context("cannot run `strip` (install binutils, or pass --keep-symbols)")?;
    ensure!(
        status.success(),
        "`strip --strip-all {}` failed: {status}",
        lib.display()
    );
    let stripped = std::fs::read(&tmp).with_context(|| format!("cannot read {}", tmp.display()));
    let _ = std::fs::remove_file(&tmp);
    stripped
}

/// The files of `resources/` for `spec`: the built-in scenarios (generic), or the embedded
/// scenario and the files it refers to (specific).
type Resources = Vec<(String, String)>;

/// The specific model of scenario `name` with default filter `filter`, and its resources.
fn specific(name: &str, filter: Option<&str>) -> Result<(ModelSpec, Resources)> {
    let src = entrynav_loader::resolve(name, entrynav_loader::Base::CurrentDir)?;
    let builtin = matches!(src.origin, entrynav_loader::Origin::Builtin(_));
    let referenced: RefCell<Vec<(String, String)>> = RefCell::new(Vec::new());
    let read = entrynav_loader::file_loader(&src.dir);
    let record = |p: &str| {
        let text = read(p)?;
        referenced.borrow_mut().push((p.to_string(), text.clone()));
        Ok(text)
    };
    let scenario = Arc::new(entrynav::scenario::Scenario::build(
        src.config.clone(),
        &record,
    )?);
    let file = format!(
        "{}.toml",
        entrynav_fmu::vars::specific_identifier(&src.config.name)
    );
    let text = match builtin {
        true => builtin_toml(name.trim()).map(str::to_string),
        false => None,
    }
    .unwrap_or_else(|| src.config.to_toml_string());
    let kind = match filter {
        Some(f) => FilterKind::parse(f)?,
        None => {
            let fits: Vec<FilterKind> = FilterKind::ALL
                .into_iter()
                .filter(|k| k.misfit(&scenario.onboard).is_none())
                .collect();
            fits.iter()
                .find(|k| k.name() == entrynav_fmu::vars::DEFAULT_FILTER)
                .or(fits.first())
                .copied()
                .context("no filter fits this scenario")?
        }
    };
    let toml = scenario.config.to_toml_string();
    let spec = ModelSpec::for_scenario(scenario, &file, &toml, kind)?;
    let mut resources = vec![(file, text)];
    for (p, text) in referenced.into_inner() {
        let plain = Path::new(&p)
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_)));
        ensure!(
            plain,
            "the scenario refers to '{p}', which cannot be embedded (only files in the scenario's folder or below)"
        );
        resources.push((p, text));
    }
    Ok((spec, resources))
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
    fmi: u8,
) -> Result<PathBuf> {
    let id = spec.identifier();
    let binding = Binding {
        identifier: id.to_string(),
        base: spec.model(),
        guid: spec.guid().to_string(),
        scenario: spec
            .specific()
            .map(|s| (s.scenario_file.clone(), s.filter.name().to_string())),
    };
    let bound = patch(so, &binding)?;
    let (path, xml, platform) = match fmi {
        3 => (
            out.join(format!("{id}-fmi3.fmu")),
            description3_of(spec),
            "x86_64-linux",
        ),
        _ => (
            out.join(format!("{id}.fmu")),
            description_of(spec),
            "linux64",
        ),
    };
    let file = entrynav_studies::output::atomic_file::AtomicFile::create(&path)?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    zip.start_file("modelDescription.xml", opts)?;
    zip.write_all(xml.as_bytes())?;
    zip.add_directory("binaries/", opts)?;
    zip.add_directory(format!("binaries/{platform}/"), opts)?;
    zip.start_file(
        format!("binaries/{platform}/{id}.so"),
        opts.unix_permissions(0o755),
    )?;
    zip.write_all(&bound)?;
    zip.add_directory("resources/", opts)?;
    for (name, text) in resources {
        zip.start_file(format!("resources/{name}"), opts)?;
        zip.write_all(text.as_bytes())?;
    }
    zip.add_directory("documentation/", opts)?;
    zip.start_file("documentation/index.html", opts)?;
    zip.write_all(documentation(spec).as_bytes())?;
    zip.finish()?.commit()?;
    Ok(path)
}

pub(super) fn pack(a: &PackArgs) -> Result<()> {
    ensure!(
        !(a.ssp && a.fmi == 3),
        "--ssp systems hold the FMI 2.0 FMUs (OMSimulator and SSP 1.0 tools import those); pack them without --fmi 3"
    );
    let lib = super::library::Search::of_process(a.lib.as_deref()).find()?;
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let so = library(&lib, a.keep_symbols, &a.out)?;
    let models: Vec<(ModelSpec, Resources)> = match &a.scenario {
        Some(s) => vec![specific(s, a.filter.as_deref())?],
        None => Model::ALL
            .into_iter()
            .map(|m| (ModelSpec::generic(m), generic_resources()))
            .collect(),
    };
    for (spec, resources) in &models {
        let path = write_fmu(&a.out, spec, &so, resources, a.fmi)?;
        // The packed FMU must unpack to the model it was packed for (binding, description and,
        // for a specific FMU, the embedded scenario).
        let u = entrynav_fmu_archive::open(&path)
            .with_context(|| format!("the packed {} does not check", path.display()))?;
        ensure!(
            u.spec.guid() == spec.guid(),
            "{}: GUID changed when unpacked",
            path.display()
        );
        ensure!(
            u.fmi_version == a.fmi,
            "{}: FMI version changed when unpacked",
            path.display()
        );
        println!(
            "{}  FMI {}.0  {}  {}  library {:.2} MiB{}",
            path.display(),
            a.fmi,
            spec.identifier(),
            spec.guid(),
            u.library_bytes as f64 / (1024.0 * 1024.0),
            if a.keep_symbols {
                " (symbols kept)"
            } else {
                " (stripped)"
            }
        );
    }
    if a.ssp {
        let (_, stop, _) = ModelSpec::generic(Model::Combined).default_experiment();
        for path in super::ssp::write_ssps(&a.out, stop)? {
            println!("{}  SSP 1.0 system", path.display());
        }
    }
    Ok(())
}

pub(super) fn documentation(spec: &ModelSpec) -> String {
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
