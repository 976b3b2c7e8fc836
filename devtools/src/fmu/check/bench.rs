//! `entrynav-dev fmu check --bench`: doStep of the combined FMU timed three ways, the engine
//! called directly, the in-process instance, and the host (fmi2SetReal + fmi2DoStep through
//! libloading), each the median of `--reps` runs.

use super::args::CheckArgs;
use super::params::{check_scenario, filter_of, scenario_param};
use anyhow::{Result, ensure};
use entrynav::estimation::nav::FilterKind;
use entrynav::sim::engine::EntryCoSim;
use entrynav_fmi_host::{Slave, Unpacked};
use entrynav_fmu::instance::{Instance, Status};
use entrynav_fmu::vars::{Key, MAX_BEACONS, Model, Type, Value};
use std::sync::Arc;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The bank of the benchmark runs at `t`.
fn bench_bank(t: f64) -> f64 {
    if t < 100.0 { 0.0 } else { 0.35 }
}

/// Seconds to run `n_steps` steps of `h` through the in-process instance, after setting
/// `params` and initialising.
fn time_instance(
    u: &Unpacked,
    params: &[(usize, Value)],
    uri: &str,
    duration: f64,
    h: f64,
    n_steps: usize,
) -> Result<f64> {
    let vars = u.spec.vars();
    let bank_vr = vars
        .iter()
        .find(|v| v.key == Key::Bank)
        .map(|v| v.vr)
        .unwrap_or(0);
    // In process through the safe instance wrapper (same code as behind the C API).
    let mut inst = Instance::new(
        Arc::clone(&u.spec),
        "bench",
        u.spec.guid(),
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
        inst.set(Type::Real, &[bank_vr], vec![Value::Real(bench_bank(t))]);
        ensure!(inst.do_step(t, h) <= Status::Warning);
    }
    Ok(clock.elapsed().as_secs_f64())
}

/// Seconds to run `n_steps` steps of `h` through the host, after setting `params` and
/// initialising.
fn time_host(
    u: &Unpacked,
    params: &[(usize, Value)],
    uri: &str,
    duration: f64,
    h: f64,
    n_steps: usize,
) -> Result<f64> {
    let vars = u.spec.vars();
    let bank_vr = vars
        .iter()
        .find(|v| v.key == Key::Bank)
        .map(|v| v.vr)
        .unwrap_or(0);
    let s = Slave::new(&u.api, "bench", u.spec.guid(), uri)?;
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
            (u.api.fmi2SetReal)(s.c, &bank_vr, 1, &bench_bank(t));
            let st = (u.api.fmi2DoStep)(s.c, t, h, 1);
            ensure!(st <= 1, "doStep {st}");
        }
        Ok(clock.elapsed().as_secs_f64())
    }
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
    let scenario = check_scenario(u, &scenario_param(a, u.model), &u.dir.join("resources"))?;
    let kind = FilterKind::parse(&filter_of(a, &u.spec))?;
    let (mut host, mut direct, mut wrapped) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..a.reps.max(1) {
        // In process: the engine called directly.
        let mut co = EntryCoSim::new(Arc::clone(&scenario), kind, a.seed as u64, !a.nominal)?;
        let clock = Instant::now();
        for k in 0..n_steps {
            let t = k as f64 * h;
            co.do_step(t, h, bench_bank(t), &[true; MAX_BEACONS])?;
        }
        direct.push(clock.elapsed().as_secs_f64());
        wrapped.push(time_instance(u, params, uri, duration, h, n_steps)?);
        // Through the host: the same inputs set and the same steps.
        host.push(time_host(u, params, uri, duration, h, n_steps)?);
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
