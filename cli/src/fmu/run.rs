//! `entrynav fmu run`: the in-process reference run of a model (no FFI), writing its outputs as
//! CSV. The cross-check artifacts are made with the same runner.

#![allow(non_snake_case)]

use super::*;
use mars_entry_nav::ModelSpec;
use mars_entry_nav::host::*;

pub(super) fn parse_value(v: &Var, text: &str) -> Result<Value> {
    let t = text.trim().trim_matches('"');
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

/// An input table: the variables of its columns and its rows (time, values).
#[derive(Default)]
pub(super) struct Table {
    pub(super) columns: Vec<Var>,
    pub(super) rows: Vec<(f64, Vec<Value>)>,
}

impl Table {
    /// Parse a CSV with a `time` column and one column per variable of `vars` (names may be
    /// quoted, as the FMI cross-check rules write them).
    pub(super) fn parse(text: &str, vars: &[Var]) -> Result<Table> {
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
        let mut columns = Vec::new();
        for n in &names[1..] {
            let v = vars
                .iter()
                .find(|v| v.name == *n)
                .with_context(|| format!("no variable '{n}'"))?;
            columns.push(v.clone());
        }
        let mut rows = Vec::new();
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
        Ok(Table { columns, rows })
    }

    /// The row that applies at `t`: the last at or before it (the first before any).
    fn at(&self, t: f64) -> Option<&Vec<Value>> {
        self.rows
            .iter()
            .rev()
            .find(|(rt, _)| *rt <= t + 1e-9)
            .or(self.rows.first())
            .map(|(_, v)| v)
    }
}

/// Run `spec` in process from 0 to `stop` in steps of `step` with the parameter and start values
/// `sets` and the input `table`; returns the time and the values of `record` at every
/// communication point, the start included.
pub(super) fn run_in_process(
    spec: &Arc<ModelSpec>,
    resources: Option<&Path>,
    sets: &[(Var, Value)],
    table: &Table,
    stop: f64,
    step: f64,
    record: &[Var],
) -> Result<Vec<(f64, Vec<Value>)>> {
    let uri = resources.map(file_uri);
    let mut inst = Instance::new(
        Arc::clone(spec),
        "reference",
        spec.guid(),
        uri.as_deref(),
        false,
        Box::new(|_, _, msg| eprintln!("{msg}")),
    )
    .map_err(|(_, e)| anyhow::anyhow!(e))?;
    for (v, val) in sets {
        ensure!(
            inst.set("fmi2Set", &[v.vr], vec![val.clone()]) == Status::Ok,
            "cannot set {}",
            v.name
        );
    }
    let apply = |inst: &mut Instance, t: f64| -> Result<()> {
        if let Some(vals) = table.at(t) {
            for (v, val) in table.columns.iter().zip(vals) {
                ensure!(
                    inst.set("fmi2Set", &[v.vr], vec![val.clone()]) == Status::Ok,
                    "cannot set {}",
                    v.name
                );
            }
        }
        Ok(())
    };
    let read = |inst: &mut Instance, t: f64| -> Result<(f64, Vec<Value>)> {
        let mut vals = Vec::with_capacity(record.len());
        for v in record {
            let got = inst
                .get("fmi2Get", v.ty, &[v.vr])
                .map_err(|s| anyhow::anyhow!("get {}: {s:?}", v.name))?;
            vals.extend(got);
        }
        Ok((t, vals))
    };
    ensure!(inst.setup_experiment(0.0, Some(stop)) == Status::Ok);
    ensure!(inst.enter_initialization_mode() == Status::Ok);
    apply(&mut inst, 0.0)?;
    ensure!(
        inst.exit_initialization_mode() == Status::Ok,
        "initialisation failed"
    );
    let mut rows = vec![read(&mut inst, 0.0)?];
    let n = (stop / step).round() as usize;
    for k in 0..n {
        let t = k as f64 * step;
        apply(&mut inst, t)?;
        ensure!(
            inst.do_step(t, step) <= Status::Warning,
            "doStep at {t} failed"
        );
        rows.push(read(&mut inst, (k + 1) as f64 * step)?);
    }
    Ok(rows)
}

/// The CSV text of `rows` with the `names` of their values (quoted when `quote`).
pub(super) fn csv(names: &[&str], rows: &[(f64, Vec<Value>)], quote: bool) -> String {
    let q = |s: &str| {
        if quote {
            format!("\"{s}\"")
        } else {
            s.to_string()
        }
    };
    let mut out = q("time");
    for n in names {
        out.push(',');
        out.push_str(&q(n));
    }
    out.push('\n');
    for (t, vals) in rows {
        out.push_str(&format!("{t:?}"));
        for v in vals {
            out.push(',');
            out.push_str(&fmt_value(v));
        }
        out.push('\n');
    }
    out
}

pub(super) fn run_reference(a: &RunArgs) -> Result<()> {
    let unpacked = a.fmu.as_deref().map(unpack).transpose()?;
    let (spec, resources) = match &unpacked {
        Some(u) => (Arc::clone(&u.spec), Some(u.dir.join("resources"))),
        None => {
            let m = Model::from_identifier(&a.model)
                .with_context(|| format!("unknown model '{}'", a.model))?;
            (
                Arc::new(mars_entry_nav::ModelSpec::generic(m)),
                a.resources.clone(),
            )
        }
    };
    let vars = spec.vars();
    let find = |name: &str| {
        vars.iter()
            .find(|v| v.name == name)
            .with_context(|| format!("{} has no variable '{name}'", spec.identifier()))
    };
    let mut sets = Vec::new();
    for s in &a.sets {
        let (name, value) = s
            .split_once('=')
            .with_context(|| format!("--set '{s}': expected NAME=VALUE"))?;
        let v = find(name.trim())?;
        sets.push((v.clone(), parse_value(v, value)?));
    }
    let table = match &a.input {
        Some(p) => Table::parse(
            &std::fs::read_to_string(p).with_context(|| format!("cannot read {}", p.display()))?,
            vars,
        )?,
        None => Table::default(),
    };
    let outputs: Vec<Var> = vars
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .cloned()
        .collect();
    let rows = run_in_process(
        &spec,
        resources.as_deref(),
        &sets,
        &table,
        a.stop,
        a.step,
        &outputs,
    )?;
    let names: Vec<&str> = outputs.iter().map(|v| v.name.as_str()).collect();
    std::fs::write(&a.out, csv(&names, &rows, false))
        .with_context(|| format!("cannot write {}", a.out.display()))?;
    Ok(())
}
