//! `entrynav fmu`: build the FMI 2.0 co-simulation FMUs (`pack`), check a `.fmu` through our own
//! FMI host against the in-process library (`check`, with `--bench`), and drive random call
//! sequences through the host (`fuzz`).
//!
//! The host loads `binaries/linux64/<modelIdentifier>.so` with libloading and calls the 34 fmi2
//! functions. Its logger is declared without the C varargs (stable Rust cannot define variadic
//! functions); on x86-64 System V a variadic call to it is ABI-compatible, and our FMUs never pass
//! format arguments (messages are pre-formatted, `%` escaped as `%%`).

#![allow(non_snake_case)]

use anyhow::{Context, Result, bail, ensure};
use clap::{Args, Subcommand};
use entrynav::scenario::{BUILTIN_NAMES, ScenarioConfig, builtin_toml};
use entrynav::sim::cosim::TruthSensors;
use mars_entry_nav::instance::{Instance, Status};
use mars_entry_nav::vars::{Causality, Key, MAX_BEACONS, Model, Slot, Type, Value, Var, variables};
use mars_entry_nav::xml::model_description;
use mars_entry_nav::{guid_of, xml};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Arguments of `entrynav fmu`.
#[derive(Args)]
pub struct FmuArgs {
    #[command(subcommand)]
    action: FmuAction,
}

#[derive(Subcommand)]
enum FmuAction {
    /// Build MarsEntryNav.fmu, MarsEntryNavFilter.fmu and MarsEntryTruth.fmu.
    Pack {
        /// Output folder.
        #[arg(long, default_value = "target/fmu")]
        out: PathBuf,
        /// The FMU shared library (default: libmars_entry_nav.so next to this executable; build
        /// it with `cargo build --release -p entrynav-fmu`).
        #[arg(long)]
        lib: Option<PathBuf>,
    },
    /// Unzip a .fmu, run a scenario through its fmi2 API with our host and compare every output
    /// with the in-process library, bit for bit.
    Check(CheckArgs),
    /// Run a model in process (no FFI) with an input table and write every output as CSV: the
    /// reference the Python tests compare external FMI tools with.
    Run(RunArgs),
    /// Random fmi2 call sequences and values through our host: no crash, and every illegal call
    /// answered with fmi2Error.
    Fuzz {
        /// The .fmu file.
        file: PathBuf,
        /// Number of random call sequences.
        #[arg(long, default_value_t = 200)]
        cases: usize,
        /// Calls per sequence.
        #[arg(long, default_value_t = 60)]
        calls: usize,
        /// Seed of the random sequences.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
}

#[derive(Args)]
struct RunArgs {
    /// Model identifier: MarsEntryNav, MarsEntryNavFilter or MarsEntryTruth.
    #[arg(long, default_value = "MarsEntryNav")]
    model: String,
    /// Parameter or input start value NAME=VALUE (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
    /// Input table (CSV with a `time` column and one column per input; the row at or before each
    /// communication point applies, as fmpy applies discrete inputs).
    #[arg(long)]
    input: Option<PathBuf>,
    /// Stop time [s].
    #[arg(long)]
    stop: f64,
    /// Communication step [s].
    #[arg(long)]
    step: f64,
    /// Folder scenario files are read from (the FMU's resources).
    #[arg(long)]
    resources: Option<PathBuf>,
    /// Output CSV.
    #[arg(long)]
    out: PathBuf,
}

#[derive(Args)]
struct CheckArgs {
    /// The .fmu file.
    file: PathBuf,
    /// Scenario parameter (built-in name or a file in the FMU's resources).
    #[arg(long, default_value = "four-beacon-fusion")]
    scenario: String,
    /// Filter parameter.
    #[arg(long, default_value = "dcifaif")]
    filter: String,
    /// Seed parameter.
    #[arg(long, default_value_t = 1)]
    seed: i32,
    /// Nominal truth instead of a dispersed one.
    #[arg(long)]
    nominal: bool,
    /// Communication step [s] (default: the fastest sensor period of the scenario).
    #[arg(long)]
    step: Option<f64>,
    /// Also time doStep through the host against the in-process engine.
    #[arg(long)]
    bench: bool,
    /// Repetitions of the benchmark.
    #[arg(long, default_value_t = 15)]
    reps: usize,
}

/// Run the command.
pub fn run(args: &FmuArgs) -> Result<()> {
    match &args.action {
        FmuAction::Pack { out, lib } => pack(out, lib.as_deref()),
        FmuAction::Check(a) => check(a),
        FmuAction::Run(a) => run_reference(a),
        FmuAction::Fuzz {
            file,
            cases,
            calls,
            seed,
        } => fuzz(file, *cases, *calls, *seed),
    }
}

// ---------------------------------------------------------------------------------------------
// pack

fn default_lib() -> Result<PathBuf> {
    let exe = std::env::current_exe()?;
    let dir = exe.parent().context("executable has no folder")?;
    Ok(dir.join("libmars_entry_nav.so"))
}

fn pack(out: &Path, lib: Option<&Path>) -> Result<()> {
    let lib = match lib {
        Some(l) => l.to_path_buf(),
        None => default_lib()?,
    };
    let so = std::fs::read(&lib).with_context(|| {
        format!(
            "cannot read the FMU library {} (build it with `cargo build --release -p entrynav-fmu`, or pass --lib)",
            lib.display()
        )
    })?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    for m in Model::ALL {
        let path = out.join(format!("{}.fmu", m.identifier()));
        let file = std::fs::File::create(&path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        let mut zip = zip::ZipWriter::new(file);
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .unix_permissions(0o644);
        zip.start_file("modelDescription.xml", opts)?;
        zip.write_all(model_description(m).as_bytes())?;
        zip.add_directory("binaries/", opts)?;
        zip.add_directory("binaries/linux64/", opts)?;
        zip.start_file(
            format!("binaries/linux64/{}.so", m.identifier()),
            opts.unix_permissions(0o755),
        )?;
        zip.write_all(&so)?;
        zip.add_directory("resources/", opts)?;
        for name in BUILTIN_NAMES {
            zip.start_file(format!("resources/{name}.toml"), opts)?;
            zip.write_all(builtin_toml(name).unwrap_or_default().as_bytes())?;
        }
        zip.add_directory("documentation/", opts)?;
        zip.start_file("documentation/index.html", opts)?;
        zip.write_all(documentation(m).as_bytes())?;
        zip.finish()?;
        println!("{}  {}  {}", path.display(), m.identifier(), guid_of(m));
    }
    Ok(())
}

fn documentation(m: Model) -> String {
    let rows: String = variables(m)
        .iter()
        .map(|v| {
            format!(
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                v.vr,
                v.name,
                v.causality.xml(),
                v.ty.xml(),
                v.unit.unwrap_or(""),
                v.description.replace('&', "&amp;").replace('<', "&lt;")
            )
        })
        .collect();
    format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{id}</title></head><body>\n<h1>{id}</h1>\n<p>{d}</p>\n<p>Scenario files in resources/ may be named by the <code>scenario</code> parameter.</p>\n<table border=\"1\"><tr><th>vr</th><th>name</th><th>causality</th><th>type</th><th>unit</th><th>description</th></tr>\n{rows}</table></body></html>\n",
        id = m.identifier(),
        d = m.description()
    )
}

// ---------------------------------------------------------------------------------------------
// The host

type Comp = *mut c_void;
type HostLogger = extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

#[repr(C)]
struct Callbacks {
    logger: Option<HostLogger>,
    allocate: Option<extern "C" fn(usize, usize) -> *mut c_void>,
    free: Option<extern "C" fn(*mut c_void)>,
    step_finished: Option<extern "C" fn(*mut c_void, c_int)>,
    env: *mut c_void,
}

extern "C" fn host_logger(
    env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    _category: *const c_char,
    msg: *const c_char,
) {
    if env.is_null() || msg.is_null() {
        return;
    }
    // SAFETY: env is the `Mutex<Vec<..>>` the host passed in Callbacks and keeps alive while the
    // instance exists; msg is a C string from the FMU.
    let (log, text) = unsafe {
        (
            &*(env as *const Mutex<Vec<(i32, String)>>),
            CStr::from_ptr(msg).to_string_lossy().replace("%%", "%"),
        )
    };
    if let Ok(mut l) = log.lock() {
        l.push((status, text));
    }
}

macro_rules! api {
    ($($name:ident : $ty:ty;)*) => {
        /// The 34 fmi2 functions of a loaded FMU library.
        #[allow(dead_code)]
        struct Api {
            _lib: libloading::Library,
            $($name: $ty,)*
        }

        impl Api {
            fn load(path: &Path) -> Result<Api> {
                // SAFETY: loading the FMU library runs no initialisers with preconditions.
                let lib = unsafe { libloading::Library::new(path) }
                    .with_context(|| format!("cannot load {}", path.display()))?;
                $(
                    // SAFETY: the symbol has the FMI 2.0 signature.
                    let $name: $ty = *unsafe { lib.get::<$ty>(concat!(stringify!($name), "\0").as_bytes()) }
                        .with_context(|| format!("{} does not export {}", path.display(), stringify!($name)))?;
                )*
                Ok(Api { _lib: lib, $($name,)* })
            }
        }
    };
}

api! {
    fmi2GetTypesPlatform: unsafe extern "C" fn() -> *const c_char;
    fmi2GetVersion: unsafe extern "C" fn() -> *const c_char;
    fmi2SetDebugLogging: unsafe extern "C" fn(Comp, c_int, usize, *const *const c_char) -> c_int;
    fmi2Instantiate: unsafe extern "C" fn(*const c_char, c_int, *const c_char, *const c_char, *const Callbacks, c_int, c_int) -> Comp;
    fmi2FreeInstance: unsafe extern "C" fn(Comp);
    fmi2SetupExperiment: unsafe extern "C" fn(Comp, c_int, f64, f64, c_int, f64) -> c_int;
    fmi2EnterInitializationMode: unsafe extern "C" fn(Comp) -> c_int;
    fmi2ExitInitializationMode: unsafe extern "C" fn(Comp) -> c_int;
    fmi2Terminate: unsafe extern "C" fn(Comp) -> c_int;
    fmi2Reset: unsafe extern "C" fn(Comp) -> c_int;
    fmi2GetReal: unsafe extern "C" fn(Comp, *const u32, usize, *mut f64) -> c_int;
    fmi2GetInteger: unsafe extern "C" fn(Comp, *const u32, usize, *mut c_int) -> c_int;
    fmi2GetBoolean: unsafe extern "C" fn(Comp, *const u32, usize, *mut c_int) -> c_int;
    fmi2GetString: unsafe extern "C" fn(Comp, *const u32, usize, *mut *const c_char) -> c_int;
    fmi2SetReal: unsafe extern "C" fn(Comp, *const u32, usize, *const f64) -> c_int;
    fmi2SetInteger: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int) -> c_int;
    fmi2SetBoolean: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int) -> c_int;
    fmi2SetString: unsafe extern "C" fn(Comp, *const u32, usize, *const *const c_char) -> c_int;
    fmi2GetFMUstate: unsafe extern "C" fn(Comp, *mut *mut c_void) -> c_int;
    fmi2SetFMUstate: unsafe extern "C" fn(Comp, *mut c_void) -> c_int;
    fmi2FreeFMUstate: unsafe extern "C" fn(Comp, *mut *mut c_void) -> c_int;
    fmi2SerializedFMUstateSize: unsafe extern "C" fn(Comp, *mut c_void, *mut usize) -> c_int;
    fmi2SerializeFMUstate: unsafe extern "C" fn(Comp, *mut c_void, *mut u8, usize) -> c_int;
    fmi2DeSerializeFMUstate: unsafe extern "C" fn(Comp, *const u8, usize, *mut *mut c_void) -> c_int;
    fmi2GetDirectionalDerivative: unsafe extern "C" fn(Comp, *const u32, usize, *const u32, usize, *const f64, *mut f64) -> c_int;
    fmi2SetRealInputDerivatives: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int, *const f64) -> c_int;
    fmi2GetRealOutputDerivatives: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int, *mut f64) -> c_int;
    fmi2DoStep: unsafe extern "C" fn(Comp, f64, f64, c_int) -> c_int;
    fmi2CancelStep: unsafe extern "C" fn(Comp) -> c_int;
    fmi2GetStatus: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int;
    fmi2GetRealStatus: unsafe extern "C" fn(Comp, c_int, *mut f64) -> c_int;
    fmi2GetIntegerStatus: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int;
    fmi2GetBooleanStatus: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int;
    fmi2GetStringStatus: unsafe extern "C" fn(Comp, c_int, *mut *const c_char) -> c_int;
}

/// An unpacked FMU: its folder, model and loaded library.
struct Unpacked {
    dir: PathBuf,
    model: Model,
    api: Api,
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn unpack(file: &Path) -> Result<Unpacked> {
    let f = std::fs::File::open(file).with_context(|| format!("cannot open {}", file.display()))?;
    let mut zip =
        zip::ZipArchive::new(f).with_context(|| format!("{} is not a zip", file.display()))?;
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .context("the FMU has no modelDescription.xml")?
        .read_to_string(&mut xml)?;
    let model = Model::ALL
        .into_iter()
        .find(|m| model_description(*m) == xml)
        .with_context(|| {
            "modelDescription.xml is not what this build's variable table generates (stale FMU or drifted table)"
        })?;
    let dir = std::env::temp_dir().join(format!(
        "entrynav fmu check {} {}",
        std::process::id(),
        model.identifier()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir)?;
    zip.extract(&dir)
        .with_context(|| format!("cannot extract to {}", dir.display()))?;
    let so = dir
        .join("binaries/linux64")
        .join(format!("{}.so", model.identifier()));
    ensure!(so.exists(), "the FMU has no {}", so.display());
    for name in BUILTIN_NAMES {
        ensure!(
            dir.join(format!("resources/{name}.toml")).exists(),
            "the FMU has no resources/{name}.toml"
        );
    }
    let api = Api::load(&so)?;
    Ok(Unpacked { dir, model, api })
}

/// One instance through the host.
struct Slave<'a> {
    api: &'a Api,
    c: Comp,
    log: Box<Mutex<Vec<(i32, String)>>>,
    _callbacks: Box<Callbacks>,
}

impl<'a> Slave<'a> {
    fn new(u: &'a Unpacked, name: &str, guid: &str, resources: &str) -> Result<Slave<'a>> {
        let log: Box<Mutex<Vec<(i32, String)>>> = Box::new(Mutex::new(Vec::new()));
        let callbacks = Box::new(Callbacks {
            logger: Some(host_logger),
            allocate: None,
            free: None,
            step_finished: None,
            env: &*log as *const _ as *mut c_void,
        });
        let (n, g, r) = (
            CString::new(name)?,
            CString::new(guid)?,
            CString::new(resources)?,
        );
        // SAFETY: valid C strings and callbacks that outlive the instance.
        let c = unsafe {
            (u.api.fmi2Instantiate)(n.as_ptr(), 1, g.as_ptr(), r.as_ptr(), &*callbacks, 0, 0)
        };
        let s = Slave {
            api: &u.api,
            c,
            log,
            _callbacks: callbacks,
        };
        if c.is_null() {
            bail!("fmi2Instantiate failed: {:?}", s.messages());
        }
        Ok(s)
    }

    fn messages(&self) -> Vec<(i32, String)> {
        self.log.lock().map(|l| l.clone()).unwrap_or_default()
    }

    fn set(&self, v: &Var, val: &Value) -> i32 {
        let vr = [v.vr];
        // SAFETY: one reference and one value of the right type.
        unsafe {
            match val {
                Value::Real(x) => (self.api.fmi2SetReal)(self.c, vr.as_ptr(), 1, x),
                Value::Integer(x) => (self.api.fmi2SetInteger)(self.c, vr.as_ptr(), 1, x),
                Value::Boolean(x) => {
                    (self.api.fmi2SetBoolean)(self.c, vr.as_ptr(), 1, &(*x as c_int))
                }
                Value::String(s) => {
                    let cs = CString::new(s.as_str()).unwrap_or_default();
                    (self.api.fmi2SetString)(self.c, vr.as_ptr(), 1, &cs.as_ptr())
                }
            }
        }
    }

    /// All values of `vars` (one call per type), as f64 bit patterns / integers.
    fn get_all(&self, groups: &OutputGroups) -> Result<Vec<u64>> {
        let mut out = Vec::new();
        let mut r = vec![0.0; groups.real.len()];
        let mut i = vec![0; groups.int.len()];
        let mut b = vec![0; groups.bool.len()];
        // SAFETY: buffers sized to the reference lists.
        let st = unsafe {
            [
                (self.api.fmi2GetReal)(self.c, groups.real.as_ptr(), r.len(), r.as_mut_ptr()),
                (self.api.fmi2GetInteger)(self.c, groups.int.as_ptr(), i.len(), i.as_mut_ptr()),
                (self.api.fmi2GetBoolean)(self.c, groups.bool.as_ptr(), b.len(), b.as_mut_ptr()),
            ]
        };
        ensure!(
            st == [0, 0, 0],
            "fmi2Get* returned {st:?}: {:?}",
            self.messages()
        );
        out.extend(r.iter().map(|x| x.to_bits()));
        out.extend(i.iter().map(|x| *x as u64));
        out.extend(b.iter().map(|x| (*x != 0) as u64));
        Ok(out)
    }
}

impl Drop for Slave<'_> {
    fn drop(&mut self) {
        // SAFETY: our instance (or null).
        unsafe { (self.api.fmi2FreeInstance)(self.c) };
    }
}

struct OutputGroups {
    real: Vec<u32>,
    int: Vec<u32>,
    bool: Vec<u32>,
}

fn output_groups(vars: &[Var]) -> OutputGroups {
    let pick = |t: Type| {
        vars.iter()
            .filter(|v| v.causality == Causality::Output && v.ty == t)
            .map(|v| v.vr)
            .collect()
    };
    OutputGroups {
        real: pick(Type::Real),
        int: pick(Type::Integer),
        bool: pick(Type::Boolean),
    }
}

fn in_process_get_all(inst: &mut Instance, g: &OutputGroups) -> Result<Vec<u64>> {
    let mut out = Vec::new();
    for (t, vrs) in [
        (Type::Real, &g.real),
        (Type::Integer, &g.int),
        (Type::Boolean, &g.bool),
    ] {
        let vals = inst
            .get("fmi2Get", t, vrs)
            .map_err(|s| anyhow::anyhow!("in-process get failed: {s:?}"))?;
        out.extend(vals.into_iter().map(|v| match v {
            Value::Real(x) => x.to_bits(),
            Value::Integer(x) => x as u64,
            Value::Boolean(x) => x as u64,
            Value::String(_) => 0,
        }));
    }
    Ok(out)
}

fn file_uri(dir: &Path) -> String {
    let mut s = String::from("file://");
    for b in dir.to_string_lossy().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => {
                s.push(b as char)
            }
            _ => s.push_str(&format!("%{b:02X}")),
        }
    }
    s
}

/// The input values at communication point `t` for a check run (bank profile, beacon 2 outage,
/// and for the filter FMU the measurements of the previous step).
/// The bank-angle command of `fmu check` at time `t` [rad].
fn check_bank(t: f64) -> f64 {
    if t < 100.0 {
        0.0
    } else if t < 200.0 {
        0.35
    } else {
        -0.2
    }
}

fn check_inputs(vars: &[Var], t: f64, truth: Option<&TruthSensors>) -> Vec<(usize, Value)> {
    let bank = check_bank(t);
    let epoch = truth.and_then(|ts| ts.last_epoch());
    let slot_value = |s: Slot| -> Option<f64> {
        let (ts, e) = (truth?, epoch?);
        let c = ts
            .scenario()
            .channels
            .iter()
            .position(|c| Slot::of(c.channel) == Some(s))?;
        e.values[c]
    };
    vars.iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Input)
        .map(|(i, v)| {
            let val = match v.key {
                Key::Bank => Value::Real(bank),
                Key::BeaconAvailable(b) => Value::Boolean(!(b == 1 && (120.0..180.0).contains(&t))),
                Key::MeasEpoch => Value::Boolean(epoch.is_some()),
                Key::MeasTime => Value::Real(epoch.map(|e| e.t).unwrap_or(0.0)),
                Key::Meas(s) => Value::Real(slot_value(s).unwrap_or(0.0)),
                Key::MeasValid(s) => Value::Boolean(slot_value(s).is_some()),
                _ => v.start.clone().unwrap_or(Value::Real(0.0)),
            };
            (i, val)
        })
        .collect()
}

fn scenario_timing(name: &str, resources: &Path) -> Result<(f64, f64)> {
    let cfg = if BUILTIN_NAMES.contains(&name) {
        ScenarioConfig::builtin(name)?
    } else {
        let p = resources.join(name);
        let text =
            std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
        ScenarioConfig::from_toml_str(&text, &p.display().to_string())?
    };
    let dur = cfg.timing.duration_s;
    let name_ok = cfg.name.clone();
    let _ = name_ok;
    let sc = entrynav::scenario::Scenario::build(cfg, &|p: &str| {
        std::fs::read_to_string(resources.join(p)).map_err(|e| e.to_string())
    })?;
    let step = sc
        .channels
        .iter()
        .map(|c| c.period_s)
        .fold(f64::INFINITY, f64::min);
    Ok((dur, if step.is_finite() { step } else { 1.0 }))
}

fn check(a: &CheckArgs) -> Result<()> {
    let u = unpack(&a.file)?;
    let m = u.model;
    let vars = variables(m);
    let res = u.dir.join("resources");
    let (duration, default_step) = scenario_timing(&a.scenario, &res)?;
    let h = a.step.unwrap_or(default_step);
    let n_steps = (duration / h).round() as usize;
    let guid = guid_of(m);
    // SAFETY: plain C strings from the library.
    let (platform, version) = unsafe {
        (
            CStr::from_ptr((u.api.fmi2GetTypesPlatform)())
                .to_string_lossy()
                .into_owned(),
            CStr::from_ptr((u.api.fmi2GetVersion)())
                .to_string_lossy()
                .into_owned(),
        )
    };
    ensure!(
        platform == "default" && version == "2.0",
        "types platform {platform}, version {version}"
    );
    let params: Vec<(usize, Value)> = vars
        .iter()
        .enumerate()
        .filter_map(|(i, v)| {
            let val = match v.key {
                Key::Scenario => Value::String(a.scenario.clone()),
                Key::Filter => Value::String(a.filter.clone()),
                Key::Seed => Value::Integer(a.seed),
                Key::Dispersed => Value::Boolean(!a.nominal),
                _ => return None,
            };
            Some((i, val))
        })
        .collect();
    let groups = output_groups(&vars);
    let uri = file_uri(&res);

    // Through the host.
    let slave = Slave::new(&u, "check", &guid, &uri)?;
    // In process: the same library's safe instance, no FFI.
    let mut inst = Instance::new("check", &guid, Some(&uri), false, Box::new(|_, _, _| {}))
        .map_err(|(_, e)| anyhow::anyhow!(e))?;
    let mut feeder = if m == Model::Filter {
        Some(TruthSensors::new(
            load_scenario(&a.scenario, &res)?,
            a.seed as u64,
            !a.nominal,
        ))
    } else {
        None
    };
    for (i, v) in &params {
        ensure!(
            slave.set(&vars[*i], v) == 0,
            "set {}: {:?}",
            vars[*i].name,
            slave.messages()
        );
        ensure!(inst.set("fmi2Set", &[vars[*i].vr], vec![v.clone()]) == Status::Ok);
    }
    // SAFETY: our instance.
    unsafe {
        ensure!(
            (u.api.fmi2SetupExperiment)(slave.c, 0, 0.0, 0.0, 1, duration) == 0,
            "setup: {:?}",
            slave.messages()
        );
        ensure!(
            (u.api.fmi2EnterInitializationMode)(slave.c) == 0,
            "enter init: {:?}",
            slave.messages()
        );
        ensure!(
            (u.api.fmi2ExitInitializationMode)(slave.c) == 0,
            "exit init: {:?}",
            slave.messages()
        );
    }
    ensure!(inst.setup_experiment(0.0, Some(duration)) == Status::Ok);
    ensure!(inst.enter_initialization_mode() == Status::Ok);
    ensure!(inst.exit_initialization_mode() == Status::Ok);
    let mut compared = 0usize;
    let mut check_eq = |k: usize, host: Vec<u64>, local: Vec<u64>| -> Result<()> {
        if host != local {
            let j = host
                .iter()
                .zip(&local)
                .position(|(x, y)| x != y)
                .unwrap_or(0);
            bail!("step {k}: output #{j} differs between the host and the in-process library");
        }
        compared += host.len();
        Ok(())
    };
    check_eq(
        0,
        slave.get_all(&groups)?,
        in_process_get_all(&mut inst, &groups)?,
    )?;
    let mut warnings = 0;
    for k in 0..n_steps {
        let t = k as f64 * h;
        for (i, v) in check_inputs(&vars, t, feeder.as_ref()) {
            ensure!(
                slave.set(&vars[i], &v) == 0,
                "set {}: {:?}",
                vars[i].name,
                slave.messages()
            );
            ensure!(inst.set("fmi2Set", &[vars[i].vr], vec![v]) == Status::Ok);
        }
        // SAFETY: our instance.
        let st = unsafe { (u.api.fmi2DoStep)(slave.c, t, h, 1) };
        let st_local = inst.do_step(t, h);
        ensure!(
            st <= 1,
            "fmi2DoStep at t = {t} returned {st}: {:?}",
            slave.messages()
        );
        ensure!(
            st == st_local as i32,
            "doStep status {st} vs in-process {st_local:?}"
        );
        warnings += (st == 1) as usize;
        if let Some(ts) = feeder.as_mut() {
            // The measurements of the truth flying the bank the filter is told.
            ts.do_step(t, h, check_bank(t), &[true; MAX_BEACONS])?;
        }
        check_eq(
            k + 1,
            slave.get_all(&groups)?,
            in_process_get_all(&mut inst, &groups)?,
        )?;
    }
    // SAFETY: our instance.
    unsafe {
        ensure!((u.api.fmi2Terminate)(slave.c) == 0);
    }
    println!(
        "{}: {} ({}), {} steps of {h} s on {} / {} / seed {}: {} output values compared, all bitwise identical to the in-process library ({} warnings)",
        a.file.display(),
        m.identifier(),
        guid,
        n_steps,
        a.scenario,
        if m.has_filter() {
            a.filter.as_str()
        } else {
            "-"
        },
        a.seed,
        compared,
        warnings
    );
    if a.bench {
        bench(&u, a, &params, &uri, duration, h, n_steps)?;
    }
    Ok(())
}

fn load_scenario(name: &str, res: &Path) -> Result<Arc<entrynav::scenario::Scenario>> {
    let cfg = if BUILTIN_NAMES.contains(&name) {
        ScenarioConfig::builtin(name)?
    } else {
        let p = res.join(name);
        ScenarioConfig::from_toml_str(&std::fs::read_to_string(&p)?, &p.display().to_string())?
    };
    Ok(Arc::new(entrynav::scenario::Scenario::build(
        cfg,
        &|p: &str| std::fs::read_to_string(res.join(p)).map_err(|e| e.to_string()),
    )?))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn bench(
    u: &Unpacked,
    a: &CheckArgs,
    params: &[(usize, Value)],
    uri: &str,
    duration: f64,
    h: f64,
    n_steps: usize,
) -> Result<()> {
    ensure!(
        u.model == Model::Combined,
        "--bench needs the combined FMU (MarsEntryNav)"
    );
    let vars = variables(u.model);
    let bank_vr = vars
        .iter()
        .find(|v| v.key == Key::Bank)
        .map(|v| v.vr)
        .unwrap_or(0);
    let scenario = load_scenario(&a.scenario, &u.dir.join("resources"))?;
    let kind = entrynav::estimation::nav::FilterKind::parse(&a.filter)?;
    let guid = guid_of(u.model);
    let (mut host, mut direct, mut wrapped) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..a.reps.max(1) {
        // In process: the engine called directly.
        let mut co = entrynav::sim::cosim::EntryCoSim::new(
            Arc::clone(&scenario),
            kind,
            a.seed as u64,
            !a.nominal,
        )?;
        let clock = Instant::now();
        for k in 0..n_steps {
            let t = k as f64 * h;
            let bank = if t < 100.0 { 0.0 } else { 0.35 };
            co.do_step(t, h, bank, &[true; MAX_BEACONS])?;
        }
        direct.push(clock.elapsed().as_secs_f64());
        // In process through the safe instance wrapper (same code as behind the C API).
        let mut inst = Instance::new("bench", &guid, Some(uri), false, Box::new(|_, _, _| {}))
            .map_err(|(_, e)| anyhow::anyhow!(e))?;
        for (i, v) in params {
            inst.set("fmi2Set", &[vars[*i].vr], vec![v.clone()]);
        }
        inst.setup_experiment(0.0, Some(duration));
        inst.enter_initialization_mode();
        ensure!(inst.exit_initialization_mode() == Status::Ok);
        let clock = Instant::now();
        for k in 0..n_steps {
            let t = k as f64 * h;
            let bank = if t < 100.0 { 0.0 } else { 0.35 };
            inst.set("fmi2SetReal", &[bank_vr], vec![Value::Real(bank)]);
            ensure!(inst.do_step(t, h) <= Status::Warning);
        }
        wrapped.push(clock.elapsed().as_secs_f64());
        // Through the host: the same inputs set and the same steps.
        let s = Slave::new(u, "bench", &guid, uri)?;
        for (i, v) in params {
            s.set(&vars[*i], v);
        }
        // SAFETY: our instance; one reference and one value per set call.
        unsafe {
            (u.api.fmi2SetupExperiment)(s.c, 0, 0.0, 0.0, 1, duration);
            (u.api.fmi2EnterInitializationMode)(s.c);
            ensure!((u.api.fmi2ExitInitializationMode)(s.c) == 0);
            let clock = Instant::now();
            for k in 0..n_steps {
                let t = k as f64 * h;
                let bank = if t < 100.0 { 0.0 } else { 0.35 };
                (u.api.fmi2SetReal)(s.c, &bank_vr, 1, &bank);
                let st = (u.api.fmi2DoStep)(s.c, t, h, 1);
                ensure!(st <= 1, "doStep {st}");
            }
            host.push(clock.elapsed().as_secs_f64());
        }
    }
    let (mh, md, mw) = (median(host), median(direct), median(wrapped));
    println!(
        "bench {} / {} / {n_steps} steps of {h} s, median of {} runs: host (fmi2SetReal + fmi2DoStep via libloading) {:.3} ms ({:.2} us/step), in-process engine (EntryCoSim::do_step) {:.3} ms ({:.2} us/step), in-process instance wrapper {:.3} ms; host/in-process = {:.3}",
        a.scenario,
        a.filter,
        a.reps.max(1),
        mh * 1e3,
        mh * 1e6 / n_steps as f64,
        md * 1e3,
        md * 1e6 / n_steps as f64,
        mw * 1e3,
        mh / md
    );
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// run (in-process reference)

fn parse_value(v: &Var, text: &str) -> Result<Value> {
    let t = text.trim();
    Ok(match v.ty {
        Type::Real => Value::Real(
            t.parse()
                .with_context(|| format!("{}: bad real '{t}'", v.name))?,
        ),
        Type::Integer => Value::Integer(
            t.parse()
                .with_context(|| format!("{}: bad integer '{t}'", v.name))?,
        ),
        Type::Boolean => Value::Boolean(match t {
            "1" | "true" | "True" | "1.0" => true,
            "0" | "false" | "False" | "0.0" => false,
            _ => bail!("{}: bad boolean '{t}'", v.name),
        }),
        Type::String => Value::String(t.to_string()),
    })
}

fn fmt_value(v: &Value) -> String {
    match v {
        Value::Real(x) => format!("{x:?}"),
        Value::Integer(x) => x.to_string(),
        Value::Boolean(x) => (*x as i32).to_string(),
        Value::String(s) => s.clone(),
    }
}

fn run_reference(a: &RunArgs) -> Result<()> {
    let m = Model::ALL
        .into_iter()
        .find(|m| m.identifier() == a.model)
        .with_context(|| format!("unknown model '{}'", a.model))?;
    let vars = variables(m);
    let find = |name: &str| {
        vars.iter()
            .find(|v| v.name == name)
            .with_context(|| format!("{} has no variable '{name}'", m.identifier()))
    };
    let uri = a.resources.as_deref().map(file_uri);
    let mut inst = Instance::new(
        "reference",
        &guid_of(m),
        uri.as_deref(),
        false,
        Box::new(|_, _, msg| eprintln!("{msg}")),
    )
    .map_err(|(_, e)| anyhow::anyhow!(e))?;
    for s in &a.sets {
        let (name, value) = s
            .split_once('=')
            .with_context(|| format!("--set '{s}': expected NAME=VALUE"))?;
        let v = find(name.trim())?;
        ensure!(
            inst.set("fmi2Set", &[v.vr], vec![parse_value(v, value)?]) == Status::Ok,
            "cannot set {name}"
        );
    }
    // Input table.
    let mut columns: Vec<&Var> = Vec::new();
    let mut rows: Vec<(f64, Vec<Value>)> = Vec::new();
    if let Some(p) = &a.input {
        let text =
            std::fs::read_to_string(p).with_context(|| format!("cannot read {}", p.display()))?;
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header = lines.next().context("empty input table")?;
        let names: Vec<&str> = header
            .split(',')
            .map(|s| s.trim().trim_matches('"'))
            .collect();
        ensure!(
            names.first() == Some(&"time"),
            "the first column of the input table must be 'time'"
        );
        for n in &names[1..] {
            columns.push(find(n)?);
        }
        for line in lines {
            let cells: Vec<&str> = line.split(',').collect();
            ensure!(
                cells.len() == names.len(),
                "input row '{line}' has {} cells, expected {}",
                cells.len(),
                names.len()
            );
            let t: f64 = cells[0].trim().parse()?;
            let vals = columns
                .iter()
                .zip(&cells[1..])
                .map(|(v, c)| parse_value(v, c))
                .collect::<Result<Vec<_>>>()?;
            rows.push((t, vals));
        }
    }
    let apply = |inst: &mut Instance, t: f64| -> Result<()> {
        let row = rows
            .iter()
            .rev()
            .find(|(rt, _)| *rt <= t + 1e-9)
            .or(rows.first());
        if let Some((_, vals)) = row {
            for (v, val) in columns.iter().zip(vals) {
                ensure!(
                    inst.set("fmi2Set", &[v.vr], vec![val.clone()]) == Status::Ok,
                    "cannot set {}",
                    v.name
                );
            }
        }
        Ok(())
    };
    let outputs: Vec<&Var> = vars
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .collect();
    let mut out = String::from("time");
    for v in &outputs {
        out.push(',');
        out.push_str(&v.name);
    }
    out.push('\n');
    let mut record = |inst: &mut Instance, t: f64| -> Result<()> {
        out.push_str(&format!("{t:?}"));
        for v in &outputs {
            let val = inst
                .get("fmi2Get", v.ty, &[v.vr])
                .map_err(|s| anyhow::anyhow!("get {}: {s:?}", v.name))?;
            out.push(',');
            out.push_str(&fmt_value(&val[0]));
        }
        out.push('\n');
        Ok(())
    };
    ensure!(inst.setup_experiment(0.0, Some(a.stop)) == Status::Ok);
    ensure!(inst.enter_initialization_mode() == Status::Ok);
    apply(&mut inst, 0.0)?;
    ensure!(
        inst.exit_initialization_mode() == Status::Ok,
        "initialisation failed"
    );
    record(&mut inst, 0.0)?;
    let n = (a.stop / a.step).round() as usize;
    for k in 0..n {
        let t = k as f64 * a.step;
        apply(&mut inst, t)?;
        ensure!(
            inst.do_step(t, a.step) <= Status::Warning,
            "doStep at {t} failed"
        );
        record(&mut inst, (k + 1) as f64 * a.step)?;
    }
    std::fs::write(&a.out, out).with_context(|| format!("cannot write {}", a.out.display()))?;
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// fuzz

/// Our model of the FMI 2.0 co-simulation state machine (as the FMU implements it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum St {
    Instantiated,
    Init,
    Step,
    Terminated,
    Error,
}

fn fuzz(file: &Path, cases: usize, calls: usize, seed: u64) -> Result<()> {
    let u = unpack(file)?;
    let m = u.model;
    let vars = variables(m);
    let guid = guid_of(m);
    let uri = file_uri(&u.dir.join("resources"));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut counts = [0usize; 6];
    let mut illegal = 0usize;
    let n_vars = vars.len() as u32;
    for case in 0..cases {
        let s = Slave::new(&u, &format!("fuzz{case}"), &guid, &uri)?;
        let mut st = St::Instantiated;
        let mut time = 0.0;
        let mut states: Vec<(*mut c_void, St, f64)> = Vec::new();
        for _ in 0..calls {
            let op = rng.random_range(0..22u32);
            // Values: mostly valid, sometimes an unknown reference, NaN, or a wrong type.
            let vr = if rng.random_bool(0.1) {
                n_vars + rng.random_range(0..5u32)
            } else {
                rng.random_range(0..n_vars)
            };
            let var = vars.get(vr as usize);
            // SAFETY: our instance, valid buffers; the FMU must answer every call without crashing.
            let (status, legal): (c_int, Option<bool>) = unsafe {
                match op {
                    0 => {
                        let ok = (u.api.fmi2SetupExperiment)(
                            s.c,
                            0,
                            0.0,
                            0.0,
                            rng.random_bool(0.5) as c_int,
                            1e6,
                        );
                        (ok, Some(st == St::Instantiated))
                    }
                    1 => {
                        let r = (u.api.fmi2EnterInitializationMode)(s.c);
                        let legal = st == St::Instantiated;
                        if r == 0 {
                            st = St::Init;
                        }
                        (r, Some(legal))
                    }
                    2 => {
                        let r = (u.api.fmi2ExitInitializationMode)(s.c);
                        let legal = st == St::Init;
                        if r == 0 {
                            st = St::Step;
                        }
                        (r, if legal { None } else { Some(false) })
                    }
                    3..=5 => {
                        let h = [1.0, 0.1, 0.0, -1.0, f64::NAN][rng.random_range(0..5)];
                        let t = if rng.random_bool(0.85) {
                            time
                        } else {
                            time + 0.5
                        };
                        let r = (u.api.fmi2DoStep)(s.c, t, h, 0);
                        let legal = st == St::Step && h > 0.0 && t == time;
                        if r <= 1 {
                            time += h;
                        } else if r == 3 && legal {
                            st = St::Error;
                        }
                        (r, if legal { None } else { Some(false) })
                    }
                    6 => {
                        let r = (u.api.fmi2Terminate)(s.c);
                        let legal = st == St::Step;
                        if r == 0 {
                            st = St::Terminated;
                        }
                        (r, Some(legal))
                    }
                    7 => {
                        let r = (u.api.fmi2Reset)(s.c);
                        if r == 0 {
                            st = St::Instantiated;
                            time = 0.0;
                        }
                        (r, Some(true))
                    }
                    8 | 9 => {
                        let mut out = [0.0f64; 1];
                        let r = (u.api.fmi2GetReal)(s.c, &vr, 1, out.as_mut_ptr());
                        let legal =
                            st != St::Instantiated && var.is_some_and(|v| v.ty == Type::Real);
                        (r, if legal { None } else { Some(false) })
                    }
                    10 => {
                        let mut out = [0 as c_int; 1];
                        let r = (u.api.fmi2GetBoolean)(s.c, &vr, 1, out.as_mut_ptr());
                        let legal =
                            st != St::Instantiated && var.is_some_and(|v| v.ty == Type::Boolean);
                        (r, if legal { None } else { Some(false) })
                    }
                    11 | 12 => {
                        let x = [0.1, -0.4, f64::NAN, f64::INFINITY, 3.0][rng.random_range(0..5)];
                        let r = (u.api.fmi2SetReal)(s.c, &vr, 1, &x);
                        let legal = matches!(st, St::Instantiated | St::Init | St::Step)
                            && x.is_finite()
                            && var.is_some_and(|v| {
                                v.ty == Type::Real && v.causality == Causality::Input
                            });
                        (r, Some(legal))
                    }
                    13 => {
                        let b: c_int = rng.random_range(0..2);
                        let r = (u.api.fmi2SetBoolean)(s.c, &vr, 1, &b);
                        let legal = var.is_some_and(|v| {
                            v.ty == Type::Boolean
                                && match v.causality {
                                    Causality::Input => {
                                        matches!(st, St::Instantiated | St::Init | St::Step)
                                    }
                                    Causality::Parameter => {
                                        matches!(st, St::Instantiated | St::Init)
                                    }
                                    Causality::Output => false,
                                }
                        });
                        (r, Some(legal))
                    }
                    14 => {
                        let mut p: *mut c_void = std::ptr::null_mut();
                        let r = (u.api.fmi2GetFMUstate)(s.c, &mut p);
                        if r == 0 {
                            states.push((p, st, time));
                        }
                        (r, Some(true))
                    }
                    15 => match states.last().copied() {
                        Some((p, saved, saved_t)) => {
                            let r = (u.api.fmi2SetFMUstate)(s.c, p);
                            if r == 0 {
                                st = saved;
                                time = saved_t;
                            }
                            (r, Some(true))
                        }
                        None => (
                            (u.api.fmi2SetFMUstate)(s.c, std::ptr::null_mut()),
                            Some(false),
                        ),
                    },
                    16 => match states.pop() {
                        Some((mut p, saved, saved_t)) => {
                            let mut size = 0usize;
                            let r1 = (u.api.fmi2SerializedFMUstateSize)(s.c, p, &mut size);
                            let mut buf = vec![0u8; size];
                            let r2 = (u.api.fmi2SerializeFMUstate)(s.c, p, buf.as_mut_ptr(), size);
                            if !buf.is_empty() && rng.random_bool(0.3) {
                                let i = rng.random_range(0..buf.len());
                                buf[i] ^= 0x5a;
                            }
                            let mut q: *mut c_void = std::ptr::null_mut();
                            let r3 = (u.api.fmi2DeSerializeFMUstate)(
                                s.c,
                                buf.as_ptr(),
                                buf.len(),
                                &mut q,
                            );
                            let r4 = (u.api.fmi2FreeFMUstate)(s.c, &mut p);
                            if r3 == 0 {
                                states.push((q, saved, saved_t));
                            }
                            // Freeing twice: the second free sees NULL and is a no-op.
                            let r5 = (u.api.fmi2FreeFMUstate)(s.c, &mut p);
                            ensure!(
                                r1 == 0 && r2 == 0 && r4 == 0 && r5 == 0,
                                "state functions failed: {r1} {r2} {r4} {r5}"
                            );
                            (r3, None)
                        }
                        None => {
                            let garbage = [1u8, 2, 3];
                            let mut q: *mut c_void = std::ptr::null_mut();
                            (
                                (u.api.fmi2DeSerializeFMUstate)(s.c, garbage.as_ptr(), 3, &mut q),
                                Some(false),
                            )
                        }
                    },
                    17 => ((u.api.fmi2CancelStep)(s.c), Some(false)),
                    18 => {
                        let mut x = 0.0;
                        let d = 1.0;
                        (
                            (u.api.fmi2GetDirectionalDerivative)(s.c, &vr, 1, &vr, 1, &d, &mut x),
                            Some(false),
                        )
                    }
                    19 => {
                        let mut x = 0.0;
                        let r = (u.api.fmi2GetRealStatus)(s.c, 2, &mut x);
                        (r, Some(matches!(st, St::Step | St::Terminated)))
                    }
                    20 => {
                        // Null pointers where arrays are required.
                        let r = (u.api.fmi2GetReal)(s.c, std::ptr::null(), 3, std::ptr::null_mut());
                        (r, Some(false))
                    }
                    _ => {
                        let cat = c"logAll";
                        let p = cat.as_ptr();
                        let r = (u.api.fmi2SetDebugLogging)(s.c, 1, 1, &p);
                        (r, Some(true))
                    }
                }
            };
            counts[(status.clamp(0, 5)) as usize] += 1;
            match legal {
                Some(false) => {
                    illegal += 1;
                    ensure!(
                        status == 3,
                        "case {case}: illegal call (op {op}, state {st:?}) answered {status}, not fmi2Error"
                    );
                }
                Some(true) => ensure!(
                    status == 0,
                    "case {case}: legal call (op {op}, state {st:?}) answered {status}: {:?}",
                    s.messages().last()
                ),
                None => {}
            }
        }
        for (mut p, _, _) in states {
            // SAFETY: our instance and a state it handed out.
            unsafe { (u.api.fmi2FreeFMUstate)(s.c, &mut p) };
        }
        ensure!(
            s.messages().iter().all(|(_, m)| !m.is_empty()),
            "an empty log message"
        );
    }
    // Null and freed instances.
    // SAFETY: null is allowed everywhere.
    unsafe {
        (u.api.fmi2FreeInstance)(std::ptr::null_mut());
        ensure!((u.api.fmi2DoStep)(std::ptr::null_mut(), 0.0, 1.0, 0) == 3);
        ensure!((u.api.fmi2Terminate)(std::ptr::null_mut()) == 3);
    }
    println!(
        "fuzz {}: {cases} sequences x {calls} calls, no crash; statuses OK {} / Warning {} / Discard {} / Error {}; {illegal} illegal calls, every one answered fmi2Error",
        m.identifier(),
        counts[0],
        counts[1],
        counts[2],
        counts[3]
    );
    let _ = xml::LOG_CATEGORIES;
    Ok(())
}
