//! `entrynav fmu pack --ssp`: System Structure and Parameterization (SSP 1.0) packages of the
//! packed FMUs, the form in which systems of FMUs travel between tools:
//!
//! * `MarsEntrySplit.ssp` — the split pair: `truth` (MarsEntryTruth) flies the system inputs
//!   `bank_angle` and `beacon_available_*`; its measurement outputs and `truth_bank_angle` (the
//!   bank it flew over its last step) feed `navfilter` (MarsEntryNavFilter). A master transfers them
//!   after each step, so the filter receives each step's measurements with the bank they were flown
//!   with, one step late, and its estimate is the combined FMU's one step late.
//! * `MarsEntryNav.ssp` — the combined FMU alone with the same system inputs.
//! * `MarsEntryGuided.ssp` — the closed guidance loop on `msl-guided.toml`: `truth` → `navfilter`
//!   (EKF) as in the split pair, the filter's `est_x_1..12`, `est_sigma_1..6`, `nav_time`,
//!   `nav_status_code` and the truth's accelerometer triad → `guidance` (MarsEntryGuidance), whose
//!   `bank_command` → the truth's `bank_angle`. System inputs `beacon_available_*` only.
//!
//! Each holds `SystemStructure.ssd`, the FMUs under `resources/`, and the parameters (scenario,
//! seed, dispersion, filter; the FMUs' defaults) in `resources/<system>.ssv`, bound at system
//! level with names `<component>.<variable>`, so a user sets a study in one file. The truth and the
//! filter must share seed and dispersion (the filter's start is drawn from the truth's seed).

use crate::error::{StudyError, StudyResult};
use crate::fmu_pack::archive_error::ZipOrStudy;
use crate::output::atomic_file::AtomicFile;
use entrynav_fmu::vars::{Causality, MAX_BEACONS, Model, Type, Value, Var, variables};
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Why `ssp` needs `fmi` 2. SSP 1.0 (2019-03-05) predates FMI 3.0 (2022-05-10): its connector
/// types (SSP 1.0, SystemStructureCommon type choice: Real, Integer, Boolean, String, Enumeration,
/// Binary) and connector kinds cover FMI 1.0/2.0 variables only, and an SSD of `version` 1.0 "must
/// also conform fully to the 1.0 standard" (SSP 2.0, SSD `version` attribute). FMI 3.0
/// components came with SSP 2.0 (2024-12-20; modelica/ssp-standard v2.0 release notes: "provides
/// support for FMI 3.0": Float64, Int32/Int64/UInt64, arrays, structural parameters), and the
/// FMI 3.0 FMUs with a filter declare exactly those (`n_state_slots`, `est_x`, `est_covariance`).
/// OMSimulator 3.0.0, the SSP tool the project tests against, implements neither SSP 2.0
/// (OpenModelica/OMSimulator#1310, open) nor FMI 3.0 structural parameters (its Python layer
/// refuses `structuralParameter`, tests/python/test_fmu_alone.py).
pub const SSP_FMI3_REFUSAL: &str = "ssp packages are SSP 1.0, whose components are FMI 1.0/2.0 FMUs: SSP 1.0 has no connector types for FMI 3.0 variables (Float64, Int32/Int64/UInt64, arrays, structural parameters; SSP 1.0 connector types are Real, Integer, Boolean, String, Enumeration, Binary), and FMI 3.0 components need SSP 2.0, which OMSimulator 3 does not read; pack the SSP packages with fmi 2";

const SSD_NS: &str = r#"xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription""#;
const SSV_NS: &str = r#"xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues""#;

/// The filter's component name. Not `filter`: OMSimulator 3 cannot resolve a component named
/// like one of its own variables (the filter FMU has a `filter` parameter) and crashes.
const FILTER: &str = "navfilter";

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// One component of a system.
struct Element {
    name: &'static str,
    model: Model,
}

/// A system: its components and the connections between them (start element, connector, end
/// element, connector; `None` is the system itself).
struct SystemSpec {
    name: &'static str,
    description: &'static str,
    elements: Vec<Element>,
    connections: Vec<(Option<&'static str>, String, Option<&'static str>, String)>,
    /// The system's inputs.
    inputs: Vec<String>,
    /// Parameters set to other values than the FMUs' defaults: (component, variable, value).
    params: Vec<(&'static str, &'static str, Value)>,
    /// Stop time of the default experiment \[s\].
    stop: f64,
}

fn ssc_type(v: &Var) -> &'static str {
    match v.ty {
        Type::Real => "<ssc:Real/>",
        Type::Integer => "<ssc:Integer/>",
        Type::Boolean => "<ssc:Boolean/>",
        Type::String => "<ssc:String/>",
    }
}

fn kind(v: &Var) -> &'static str {
    match v.causality {
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Parameter => "parameter",
    }
}

/// The system inputs every system has: the bank command and the beacon availability.
fn system_inputs() -> Vec<String> {
    std::iter::once("bank_angle".to_string())
        .chain((1..=MAX_BEACONS).map(|i| format!("beacon_available_{i}")))
        .collect()
}

/// The connections truth → filter of the split pair and the guided loop: every measurement and
/// the flown bank.
fn truth_to_filter() -> Vec<(Option<&'static str>, String, Option<&'static str>, String)> {
    let truth = variables(Model::Truth);
    let mut connections = Vec::new();
    for v in variables(Model::Filter)
        .iter()
        .filter(|v| v.causality == Causality::Input && v.name.starts_with("meas_"))
    {
        if truth
            .iter()
            .any(|t| t.name == v.name && t.causality == Causality::Output)
        {
            connections.push((Some("truth"), v.name.clone(), Some(FILTER), v.name.clone()));
        }
    }
    connections.push((
        Some("truth"),
        "truth_bank_angle".into(),
        Some(FILTER),
        "bank_angle".into(),
    ));
    connections
}

fn split_system(stop: f64) -> SystemSpec {
    let mut connections: Vec<_> = system_inputs()
        .into_iter()
        .map(|n| (None, n.clone(), Some("truth"), n))
        .collect();
    connections.extend(truth_to_filter());
    SystemSpec {
        name: "MarsEntrySplit",
        description: "Mars entry truth and navigation filter as two FMUs: the filter receives the truth's measurements and flown bank angle one step late",
        elements: vec![
            Element {
                name: "truth",
                model: Model::Truth,
            },
            Element {
                name: FILTER,
                model: Model::Filter,
            },
        ],
        connections,
        inputs: system_inputs(),
        params: Vec::new(),
        stop,
    }
}

/// The guidance component's name.
const GUIDANCE: &str = "guidance";

/// The closed loop truth → filter → guidance → truth (issue 28) on the guided scenario: the
/// split pair, the filter's estimate (kinematic states, 1σ, epoch, status) and the truth's
/// accelerometer triad into the guidance FMU, whose limited bank drives the truth. Every
/// transfer is one step late; the filter is the EKF (the default dcifaif needs beacons).
fn guided_system() -> StudyResult<SystemSpec> {
    let guidance = variables(Model::Guidance);
    let filter = variables(Model::Filter);
    let truth = variables(Model::Truth);
    let mut connections: Vec<_> = (1..=MAX_BEACONS)
        .map(|i| format!("beacon_available_{i}"))
        .map(|n| (None, n.clone(), Some("truth"), n))
        .collect();
    connections.extend(truth_to_filter());
    for v in guidance.iter().filter(|v| v.causality == Causality::Input) {
        let from = |vars: &[Var]| {
            vars.iter()
                .any(|o| o.name == v.name && o.causality == Causality::Output)
        };
        let source = if from(&filter) {
            FILTER
        } else if from(&truth) {
            "truth"
        } else {
            return Err(StudyError::Failed(format!(
                "no FMU of the guided loop outputs the guidance input {}",
                v.name
            )));
        };
        connections.push((Some(source), v.name.clone(), Some(GUIDANCE), v.name.clone()));
    }
    connections.push((
        Some(GUIDANCE),
        "bank_command".into(),
        Some("truth"),
        "bank_angle".into(),
    ));
    let scenario = entrynav_fmu::vars::guided_scenario()?;
    let file = entrynav_fmu::vars::GUIDED_SCENARIO_FILE;
    Ok(SystemSpec {
        name: "MarsEntryGuided",
        description: "Mars entry guided in closed loop as three FMUs: truth -> navigation filter -> guidance -> truth bank angle, each transfer one step late",
        elements: vec![
            Element {
                name: "truth",
                model: Model::Truth,
            },
            Element {
                name: FILTER,
                model: Model::Filter,
            },
            Element {
                name: GUIDANCE,
                model: Model::Guidance,
            },
        ],
        connections,
        inputs: (1..=MAX_BEACONS)
            .map(|i| format!("beacon_available_{i}"))
            .collect(),
        params: vec![
            ("truth", "scenario", Value::String(file.into())),
            (FILTER, "scenario", Value::String(file.into())),
            (FILTER, "filter", Value::String("ekf".into())),
        ],
        stop: scenario.config.timing.duration_s,
    })
}

fn combined_system(stop: f64) -> SystemSpec {
    SystemSpec {
        name: "MarsEntryNav",
        description: "Mars entry truth and navigation filter in one FMU",
        elements: vec![Element {
            name: "nav",
            model: Model::Combined,
        }],
        connections: system_inputs()
            .into_iter()
            .map(|n| (None, n.clone(), Some("nav"), n))
            .collect(),
        inputs: system_inputs(),
        params: Vec::new(),
        stop,
    }
}

/// `SystemStructure.ssd` of `sys`.
fn ssd(sys: &SystemSpec) -> String {
    let stop = sys.stop;
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<ssd:SystemStructureDescription {SSD_NS} version="1.0" name="{}" description="{}" generationTool="entrynav {}">"#,
        sys.name,
        esc(sys.description),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(x, r#"  <ssd:System name="{}">"#, sys.name);
    let _ = writeln!(x, "    <ssd:Connectors>");
    for n in &sys.inputs {
        let ty = if n == "bank_angle" {
            "<ssc:Real/>"
        } else {
            "<ssc:Boolean/>"
        };
        let _ = writeln!(
            x,
            r#"      <ssd:Connector name="{n}" kind="input">{ty}</ssd:Connector>"#
        );
    }
    let _ = writeln!(x, "    </ssd:Connectors>");
    let _ = writeln!(x, "    <ssd:ParameterBindings>");
    let _ = writeln!(
        x,
        r#"      <ssd:ParameterBinding source="resources/{}.ssv"/>"#,
        sys.name
    );
    let _ = writeln!(x, "    </ssd:ParameterBindings>");
    let _ = writeln!(x, "    <ssd:Elements>");
    for e in &sys.elements {
        let _ = writeln!(
            x,
            r#"      <ssd:Component name="{}" type="application/x-fmu-sharedlibrary" source="resources/{}.fmu">"#,
            e.name,
            e.model.identifier()
        );
        let _ = writeln!(x, "        <ssd:Connectors>");
        for v in variables(e.model) {
            let _ = writeln!(
                x,
                r#"          <ssd:Connector name="{}" kind="{}">{}</ssd:Connector>"#,
                esc(&v.name),
                kind(&v),
                ssc_type(&v)
            );
        }
        let _ = writeln!(x, "        </ssd:Connectors>");
        let _ = writeln!(x, "      </ssd:Component>");
    }
    let _ = writeln!(x, "    </ssd:Elements>");
    let _ = writeln!(x, "    <ssd:Connections>");
    for (se, sc, ee, ec) in &sys.connections {
        let start = se
            .map(|s| format!(r#" startElement="{s}""#))
            .unwrap_or_default();
        let end = ee
            .map(|s| format!(r#" endElement="{s}""#))
            .unwrap_or_default();
        let _ = writeln!(
            x,
            r#"      <ssd:Connection{start} startConnector="{}"{end} endConnector="{}"/>"#,
            esc(sc),
            esc(ec)
        );
    }
    let _ = writeln!(x, "    </ssd:Connections>");
    let _ = writeln!(x, "  </ssd:System>");
    let _ = writeln!(
        x,
        r#"  <ssd:DefaultExperiment startTime="0.0" stopTime="{stop:?}"/>"#
    );
    let _ = writeln!(x, "</ssd:SystemStructureDescription>");
    x
}

/// `<system>.ssv`: every parameter of every component, at the FMU's default unless the system
/// sets it.
fn ssv(sys: &SystemSpec) -> String {
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<ssv:ParameterSet {SSV_NS} version="1.0" name="{}">"#,
        sys.name
    );
    let _ = writeln!(x, "  <ssv:Parameters>");
    for e in &sys.elements {
        for v in variables(e.model)
            .iter()
            .filter(|v| v.causality == Causality::Parameter && v.name != "allow_external_files")
        {
            let set = sys
                .params
                .iter()
                .find(|(c, n, _)| *c == e.name && *n == v.name)
                .map(|p| &p.2);
            let value = match set.or(v.start.as_ref()) {
                Some(Value::Real(r)) => format!(r#"<ssv:Real value="{r:?}"/>"#),
                Some(Value::Integer(i)) => format!(r#"<ssv:Integer value="{i}"/>"#),
                Some(Value::Boolean(b)) => format!(r#"<ssv:Boolean value="{b}"/>"#),
                Some(Value::String(s)) => format!(r#"<ssv:String value="{}"/>"#, esc(s)),
                None => continue,
            };
            let _ = writeln!(
                x,
                r#"    <ssv:Parameter name="{}.{}">{value}</ssv:Parameter>"#,
                e.name,
                esc(&v.name)
            );
        }
    }
    let _ = writeln!(x, "  </ssv:Parameters>");
    let _ = writeln!(x, "</ssv:ParameterSet>");
    x
}

/// Write `<out>/<system>.ssp` for the split pair and the combined FMU from the packed `.fmu`
/// files in `out`; `stop` is the default experiment's stop time.
pub fn write_ssps(out: &Path, stop: f64) -> StudyResult<Vec<PathBuf>> {
    let mut written = Vec::new();
    for sys in [split_system(stop), combined_system(stop), guided_system()?] {
        let path = out.join(format!("{}.ssp", sys.name));
        write_ssp(out, &sys, &path).map_err(|e| e.at(&path))?;
        written.push(path);
    }
    Ok(written)
}

/// The system structure, its parameters and its FMUs (read from `out`) as the archive `path`.
fn write_ssp(out: &Path, sys: &SystemSpec, path: &Path) -> Result<(), ZipOrStudy> {
    let file = AtomicFile::create(path)?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    zip.start_file("SystemStructure.ssd", opts)?;
    zip.write_all(ssd(sys).as_bytes())?;
    zip.add_directory("resources/", opts)?;
    zip.start_file(format!("resources/{}.ssv", sys.name), opts)?;
    zip.write_all(ssv(sys).as_bytes())?;
    for e in &sys.elements {
        let fmu = out.join(format!("{}.fmu", e.model.identifier()));
        let bytes = std::fs::read(&fmu)
            .map_err(|err| StudyError::Failed(format!("cannot read {}: {err}", fmu.display())))?;
        zip.start_file(format!("resources/{}.fmu", e.model.identifier()), opts)?;
        zip.write_all(&bytes)?;
    }
    zip.finish()?.commit()?;
    Ok(())
}
