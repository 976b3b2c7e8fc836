//! `entrynav-dev fmu check`: run a `.fmu` through our host and the same model in process,
//! compare every output bit for bit, and with `--bench` time doStep both ways (`bench`).
//! The steps: what the run flies ([`Plan`]), both instances started with the same parameters,
//! then every communication step compared.

mod args;
mod bench;
pub(super) mod inputs;
mod params;

pub(super) use args::CheckArgs;

use super::guided::guided_rows;
use anyhow::{Result, bail, ensure};
use entrynav::scenario::Scenario;
use entrynav::sim::engine::TruthSensors;
use entrynav::sim::guided::GuidedStep;
use entrynav_fmi_host::{
    OutputGroups, Slave, Unpacked, file_uri, in_process_get_all, output_groups, unpack,
};
use entrynav_fmu::ModelSpec;
use entrynav_fmu::instance::{Instance, Status};
use entrynav_fmu::vars::{Key, Model, Value, Var};
use inputs::{check_available, check_bank, check_inputs, scenario_timing};
use params::{check_scenario, filter_of, scenario_param};
use std::ffi::CStr;
use std::sync::Arc;

/// What a check run flies, and what it sets and compares.
struct Plan {
    spec: Arc<ModelSpec>,
    vars: Vec<Var>,
    scenario: Arc<Scenario>,
    duration: f64,
    /// The communication step.
    h: f64,
    n_steps: usize,
    /// The guidance FMU's inputs per communication point (empty for the other models).
    guided: Vec<GuidedStep>,
    guid: String,
    /// The parameters set before initialisation: (index in `vars`, value).
    params: Vec<(usize, Value)>,
    groups: OutputGroups,
    /// The resources folder as a URI.
    uri: String,
    /// The seed and whether the truth is dispersed (the filter FMU's measurement feeder).
    seed: u64,
    dispersed: bool,
}

/// The plan of `a` on the FMU `u`; the library must report the default types platform and FMI
/// 2.0.
fn plan(u: &Unpacked, a: &CheckArgs) -> Result<Plan> {
    let m = u.model;
    let spec = Arc::clone(&u.spec);
    let vars = spec.vars().to_vec();
    let res = u.dir.join("resources");
    let scenario_name = scenario_param(a, m);
    let scenario = check_scenario(u, &scenario_name, &res)?;
    let (duration, default_step) = match m {
        // The guidance and guided FMUs' default experiment: one step per guidance period.
        Model::Guidance | Model::Guided => {
            let (_, stop, step) = spec.default_experiment();
            (stop, step)
        }
        _ => scenario_timing(&scenario),
    };
    let h = a.step.unwrap_or(default_step);
    super::bounds::step(h, duration)?;
    let n_steps = (duration / h).round() as usize;
    let guided = match m {
        Model::Guidance => guided_rows(&scenario, a.seed as u64, h, n_steps)?,
        _ => Vec::new(),
    };
    let guid = spec.guid().to_string();
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
                Key::Scenario => Value::String(scenario_name.clone()),
                Key::Filter => Value::String(filter_of(a, &spec)),
                Key::Seed => Value::Integer(a.seed),
                Key::Dispersed => Value::Boolean(!a.nominal),
                _ => return None,
            };
            Some((i, val))
        })
        .collect();
    let groups = output_groups(&vars);
    let uri = file_uri(&res);
    Ok(Plan {
        spec,
        vars,
        scenario,
        duration,
        h,
        n_steps,
        guided,
        guid,
        params,
        groups,
        uri,
        seed: a.seed as u64,
        dispersed: !a.nominal,
    })
}

/// The model through the host and in process, both with the plan's parameters and initialised.
fn start(u: &Unpacked, p: &Plan) -> Result<(Slave, Instance)> {
    // Through the host.
    let slave = Slave::new(&u.api, "check", &p.guid, &p.uri)?;
    // In process: the same library's safe instance, no FFI.
    let mut inst = Instance::new(
        Arc::clone(&p.spec),
        "check",
        &p.guid,
        Some(&p.uri),
        false,
        Box::new(|_, _, _| {}),
    )
    .map_err(|(_, e)| anyhow::anyhow!(e))?;
    for (i, v) in &p.params {
        ensure!(
            slave.set(&p.vars[*i], v) == 0,
            "set {}: {:?}",
            p.vars[*i].name,
            slave.messages()
        );
        ensure!(inst.set(v.ty(), &[p.vars[*i].vr], vec![v.clone()]) == Status::Ok);
    }
    // SAFETY: our instance.
    unsafe {
        ensure!(
            (u.api.fmi2SetupExperiment)(slave.c, 0, 0.0, 0.0, 1, p.duration) == 0,
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
    ensure!(inst.setup_experiment(0.0, Some(p.duration)) == Status::Ok);
    ensure!(inst.enter_initialization_mode() == Status::Ok);
    ensure!(inst.exit_initialization_mode() == Status::Ok);
    Ok((slave, inst))
}

/// Every output of the host and of the in-process instance after step `k`, compared bit for
/// bit; returns how many values were compared.
fn compare(k: usize, slave: &Slave, inst: &mut Instance, groups: &OutputGroups) -> Result<usize> {
    let (host, local) = (slave.get_all(groups)?, in_process_get_all(inst, groups)?);
    if host != local {
        let j = host
            .iter()
            .zip(&local)
            .position(|(x, y)| x != y)
            .unwrap_or(0);
        bail!("step {k}: output #{j} differs between the host and the in-process library");
    }
    Ok(host.len())
}

/// Every communication step of the plan on both instances, the same inputs set on both (the
/// filter FMU's measurements from a truth fed with the check's bank and beacons); returns the
/// values compared and the warnings the host's steps answered.
fn run_steps(u: &Unpacked, p: &Plan, slave: &Slave, inst: &mut Instance) -> Result<(usize, usize)> {
    let h = p.h;
    let mut feeder = match u.model {
        Model::Filter => Some(TruthSensors::new(
            Arc::clone(&p.scenario),
            p.seed,
            p.dispersed,
        )),
        _ => None,
    };
    let mut compared = compare(0, slave, inst, &p.groups)?;
    let mut warnings = 0;
    for k in 0..p.n_steps {
        let t = k as f64 * h;
        for (i, v) in check_inputs(
            p.spec.model(),
            &p.vars,
            t,
            h,
            feeder.as_ref(),
            p.guided.get(k),
        ) {
            ensure!(
                slave.set(&p.vars[i], &v) == 0,
                "set {}: {:?}",
                p.vars[i].name,
                slave.messages()
            );
            ensure!(inst.set(v.ty(), &[p.vars[i].vr], vec![v]) == Status::Ok);
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
            // The measurements the combined FMU's truth makes on this step (its bank and
            // beacon availability); the filter is told this bank with them, one step late.
            ts.do_step(t, h, check_bank(t), &check_available(t))?;
        }
        compared += compare(k + 1, slave, inst, &p.groups)?;
    }
    Ok((compared, warnings))
}

pub(super) fn check(a: &CheckArgs) -> Result<()> {
    super::bounds::input(&a.file, "FILE")?;
    super::bounds::count("reps", a.reps, super::bounds::MAX_REPS)?;
    let u = unpack(&a.file)?;
    let p = plan(&u, a)?;
    let (slave, mut inst) = start(&u, &p)?;
    let (compared, warnings) = run_steps(&u, &p, &slave, &mut inst)?;
    // SAFETY: our instance.
    unsafe {
        ensure!((u.api.fmi2Terminate)(slave.c) == 0);
    }
    println!(
        "{}: {} ({}), {} steps of {} s on {} / {} / seed {}: {} output values compared, all bitwise identical to the in-process library ({} warnings)",
        a.file.display(),
        p.spec.identifier(),
        p.guid,
        p.n_steps,
        p.h,
        p.scenario.config.name,
        if u.model.has_filter() {
            filter_of(a, &p.spec)
        } else {
            "-".to_string()
        },
        a.seed,
        compared,
        warnings
    );
    if a.bench {
        bench::bench(&u, a, &p.params, &p.uri, p.duration, p.h, p.n_steps)?;
    }
    Ok(())
}
