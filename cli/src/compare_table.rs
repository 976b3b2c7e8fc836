//! The table of `entrynav trade compare`.

use entrynav_studies::compare::types::{Comparison, Row, Source};

fn num(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) {
        format!("{x:.4e}")
    } else {
        format!("{x:.4}")
    }
}

fn header(tag: &str, s: &Source) {
    let partial = if s.complete { "" } else { "  (partial)" };
    println!(
        "{tag}: {}  scenario {}  fingerprint {}  seed {}{partial}",
        s.path,
        s.scenario,
        s.scenario_fingerprint.as_deref().unwrap_or("-"),
        s.seed
    );
}

/// Print the comparison on standard output.
pub fn print(c: &Comparison) {
    header("A", &c.a);
    header("B", &c.b);
    for n in &c.notes {
        println!("note: {n}");
    }
    if !c.scenario_differences.is_empty() {
        println!("scenario differences (A -> B):");
        for d in &c.scenario_differences {
            println!("  {d}");
        }
    }
    for f in &c.filters {
        println!();
        println!(
            "filter {}  (runs used: A {}, B {}; B - A with its {:.0} % interval; * = interval excludes 0)",
            f.name,
            f.runs[0],
            f.runs[1],
            100.0 * c.confidence
        );
        println!(
            "  {:<18} {:<20} {:>12} {:>12} {:>12} {:>9} {:>27}  sig",
            "metric", "state", "A", "B", "B - A", "rel", "interval"
        );
        if f.diverged.iter().any(|&d| d > 0) {
            println!(
                "  note: diverged runs (A {}, B {}) give heavy-tailed errors: these intervals are too narrow",
                f.diverged[0], f.diverged[1]
            );
        }
        for r in &f.rows {
            print_row(r);
        }
    }
    if !c.only_in_a.is_empty() {
        println!("\nonly in A (not compared): {}", c.only_in_a.join(", "));
    }
    if !c.only_in_b.is_empty() {
        println!("\nonly in B (not compared): {}", c.only_in_b.join(", "));
    }
    if c.filters.is_empty() {
        println!("\nno filter is in both summaries");
    }
}

fn print_row(r: &Row) {
    let d = &r.difference;
    let rel = d
        .rel
        .map(|x| format!("{:+.1}%", 100.0 * x))
        .unwrap_or_else(|| "-".into());
    let interval = format!("[{}, {}]", num(d.ci_low), num(d.ci_high));
    println!(
        "  {:<18} {:<20} {:>12} {:>12} {:>12} {:>9} {:>27}  {}",
        r.metric,
        r.state,
        num(r.a.value),
        num(r.b.value),
        num(d.diff),
        rel,
        interval,
        if d.significant { "*" } else { "" }
    );
    if let Some(b) = &r.band {
        let inside = |x: bool| if x { "inside" } else { "OUTSIDE" };
        println!(
            "  {:<18} dof {}: A/dof {:.3} {} its 95% band [{:.3}, {:.3}], B/dof {:.3} {} [{:.3}, {:.3}]",
            "",
            b.dof,
            r.a.value / b.dof as f64,
            inside(b.a_inside),
            b.a[0] / b.dof as f64,
            b.a[1] / b.dof as f64,
            r.b.value / b.dof as f64,
            inside(b.b_inside),
            b.b[0] / b.dof as f64,
            b.b[1] / b.dof as f64,
        );
    }
}
