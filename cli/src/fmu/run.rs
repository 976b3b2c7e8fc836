//! `entrynav fmu run`: the in-process reference run of a model (no `.fmu` involved), printing
//! or writing its outputs.

#![allow(non_snake_case)]

use super::*;
use mars_entry_nav::host::*;

pub(super) fn parse_value(v: &Var, text: &str) -> Result<Value> {
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

pub(super) fn fmt_value(v: &Value) -> String {
    match v {
        Value::Real(x) => format!("{x:?}"),
        Value::Integer(x) => x.to_string(),
        Value::Boolean(x) => (*x as i32).to_string(),
        Value::String(s) => s.clone(),
    }
}

pub(super) fn run_reference(a: &RunArgs) -> Result<()> {
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
