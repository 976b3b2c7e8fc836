//! `entrynav fmu check`: run a `.fmu` through our host and the same model in process, compare
//! every output bit for bit, and with `--bench` time doStep both ways.

#![allow(non_snake_case)]

use super::*;
use entrynav::sim::guided::GuidedStep;
use entrynav_fmi_host::*;

/// The input values at communication point `t` for a check run (bank profile, beacon 2 outage,
/// and for the filter FMU the measurements of the previous step).
/// The bank-angle command of `fmu check` at time `t` \[rad\].
pub(super) fn check_bank(t: f64) -> f64 {
    if t < 100.0 {
        0.0
    } else if t < 200.0 {
        0.35
    } else {
        -0.2
    }
}

/// Beacon availability of the check runs: beacon 2 (slot 1) out from 120 s to 180 s.
pub(super) fn check_available(t: f64) -> [bool; MAX_BEACONS] {
    std::array::from_fn(|b| !(b == 1 && (120.0..180.0).contains(&t)))
}

/// The bank input of a check run's row at `t` with communication step `h`: the command of the
/// step from `t`, except for the filter FMU, which is told the bank its measurements were flown
/// with — the previous step's, like the measurements (one step late; fmu/README "Split pair").
pub(super) fn bank_input(model: Model, t: f64, h: f64) -> f64 {
    match model {
        Model::Filter => check_bank((t - h).max(0.0)),
        _ => check_bank(t),
    }
}

/// The inputs of a check run's row at `t` (communication step `h`); the filter FMU's
/// measurements are the last epoch of `truth`.
pub(super) fn check_inputs(
    model: Model,
    vars: &[Var],
    t: f64,
    h: f64,
    truth: Option<&TruthSensors>,
    guided: Option<&GuidedStep>,
) -> Vec<(usize, Value)> {
    let bank = bank_input(model, t, h);
    let available = check_available(t);
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
            if let Some(val) = guided.and_then(|g| super::guided::guided_input(v.key, g)) {
                return (i, val);
            }
            let val = match v.key {
                Key::Bank => Value::Real(bank),
                Key::BeaconAvailable(b) => {
                    Value::Boolean(available.get(b).copied().unwrap_or(true))
                }
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

/// The scenario's duration and its fastest sensor period (the default communication step).
pub(super) fn scenario_timing(sc: &entrynav::scenario::Scenario) -> (f64, f64) {
    let step = sc
        .channels
        .iter()
        .map(|c| c.period_s)
        .fold(f64::INFINITY, f64::min);
    (
        sc.config.timing.duration_s,
        if step.is_finite() { step } else { 1.0 },
    )
}

/// The scenario a check runs: `--scenario`, else the guided scenario for the guidance and guided
/// FMUs and four-beacon-fusion for the others.
fn scenario_param(a: &CheckArgs, m: Model) -> String {
    a.scenario.clone().unwrap_or_else(|| {
        match m {
            Model::Guidance | Model::Guided => mars_entry_nav::vars::GUIDED_SCENARIO_FILE,
            _ => mars_entry_nav::vars::DEFAULT_SCENARIO,
        }
        .to_string()
    })
}

/// The filter a check runs: `--filter`, else the FMU's default.
fn filter_of(a: &CheckArgs, spec: &mars_entry_nav::ModelSpec) -> String {
    a.filter.clone().unwrap_or_else(|| {
        super::fuzz::model::start_params(spec)
            .map(|(_, f)| f)
            .unwrap_or(mars_entry_nav::vars::DEFAULT_FILTER)
            .to_string()
    })
}

/// The scenario a check runs: the embedded one of a specific FMU, else `name` from `resources`.
pub(super) fn check_scenario(
    u: &Unpacked,
    name: &str,
    resources: &Path,
) -> Result<Arc<entrynav::scenario::Scenario>> {
    match u.spec.specific() {
        Some(s) => Ok(Arc::clone(&s.scenario)),
        None => load_scenario(name, resources),
    }
}

pub(super) fn check(a: &CheckArgs) -> Result<()> {
    let u = unpack(&a.file)?;
    let m = u.model;
    let spec = Arc::clone(&u.spec);
    let vars = spec.vars().to_vec();
    let res = u.dir.join("resources");
    let scenario_name = scenario_param(a, m);
    let scenario = check_scenario(&u, &scenario_name, &res)?;
    let (duration, default_step) = match m {
        // The guidance and guided FMUs' default experiment: one step per guidance period.
        Model::Guidance | Model::Guided => {
            let (_, stop, step) = spec.default_experiment();
            (stop, step)
        }
        _ => scenario_timing(&scenario),
    };
    let h = a.step.unwrap_or(default_step);
    let n_steps = (duration / h).round() as usize;
    let guided = match m {
        Model::Guidance => super::guided::guided_rows(&scenario, a.seed as u64, h, n_steps)?,
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

    // Through the host.
    let slave = Slave::new(&u, "check", &guid, &uri)?;
    // In process: the same library's safe instance, no FFI.
    let mut inst = Instance::new(
        Arc::clone(&spec),
        "check",
        &guid,
        Some(&uri),
        false,
        Box::new(|_, _, _| {}),
    )
    .map_err(|(_, e)| anyhow::anyhow!(e))?;
    let mut feeder = if m == Model::Filter {
        Some(TruthSensors::new(
            Arc::clone(&scenario),
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
        ensure!(inst.set(v.ty(), &[vars[*i].vr], vec![v.clone()]) == Status::Ok);
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
        for (i, v) in check_inputs(spec.model(), &vars, t, h, feeder.as_ref(), guided.get(k)) {
            ensure!(
                slave.set(&vars[i], &v) == 0,
                "set {}: {:?}",
                vars[i].name,
                slave.messages()
            );
            ensure!(inst.set(v.ty(), &[vars[i].vr], vec![v]) == Status::Ok);
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
        spec.identifier(),
        guid,
        n_steps,
        scenario.config.name,
        if m.has_filter() {
            filter_of(a, &spec)
        } else {
            "-".to_string()
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

/// The scenario an FMU instance with `scenario = name` loads from the resources folder `res`.
pub(super) fn load_scenario(name: &str, res: &Path) -> Result<Arc<entrynav::scenario::Scenario>> {
    Ok(Arc::new(entrynav_loader::load(
        name,
        &[],
        entrynav_loader::Base::Folder(res),
    )?))
}

pub(super) fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

pub(super) fn bench(
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
    let vars = u.spec.vars();
    let bank_vr = vars
        .iter()
        .find(|v| v.key == Key::Bank)
        .map(|v| v.vr)
        .unwrap_or(0);
    let scenario = check_scenario(u, &scenario_param(a, u.model), &u.dir.join("resources"))?;
    let kind = entrynav::estimation::nav::FilterKind::parse(&filter_of(a, &u.spec))?;
    let guid = u.spec.guid().to_string();
    let (mut host, mut direct, mut wrapped) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..a.reps.max(1) {
        // In process: the engine called directly.
        let mut co = entrynav::sim::engine::EntryCoSim::new(
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
        let mut inst = Instance::new(
            Arc::clone(&u.spec),
            "bench",
            &guid,
            Some(uri),
            false,
            Box::new(|_, _, _| {}),
        )
        .map_err(|(_, e)| anyhow::anyhow!(e))?;
        for (i, v) in params {
            inst.set(v.ty(), &[vars[*i].vr], vec![v.clone()]);
        }
        inst.setup_experiment(0.0, Some(duration));
        inst.enter_initialization_mode();
        ensure!(inst.exit_initialization_mode() == Status::Ok);
        let clock = Instant::now();
        for k in 0..n_steps {
            let t = k as f64 * h;
            let bank = if t < 100.0 { 0.0 } else { 0.35 };
            inst.set(Type::Real, &[bank_vr], vec![Value::Real(bank)]);
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
        scenario.config.name,
        filter_of(a, &u.spec),
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
