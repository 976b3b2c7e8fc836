//! The tables every `entrynav optimize` problem prints: sites and elements, the search line, the
//! LinCov polish and the check of the optimum against the input design.

use entrynav_optimizer::{LinCovFigures, OrbitElements, SearchOptions, SearchResult, Site};
use entrynav_studies::design::check::{ANEES_BAND, DesignCheck};
use entrynav_studies::design::lincov_stage::LinCovStage;

/// Sites with their smallest elevation along the entry, if known.
pub fn print_sites(sites: &[Site], elevation: Option<&[f64]>) {
    println!(
        "  {:<6} {:>11} {:>11} {:>22}",
        "site", "lat [deg]", "lon [deg]", "min elevation [deg]"
    );
    for (k, s) in sites.iter().enumerate() {
        let [lat, lon] = s.degrees();
        let e = elevation
            .and_then(|e| e.get(k))
            .map_or(String::new(), |e| format!("{:.4}", e.to_degrees()));
        println!("  {:<6} {lat:>11.4} {lon:>11.4} {e:>22}", k + 1);
    }
}

/// Orbit elements in degrees.
pub fn print_elements(el: &[OrbitElements]) {
    println!(
        "  {:<10} {:>10} {:>10} {:>10}",
        "orbiter", "RAAN [deg]", "i [deg]", "f [deg]"
    );
    for (k, e) in el.iter().enumerate() {
        let [raan, inc, f] = e.degrees();
        println!("  {:<10} {raan:>10.3} {inc:>10.3} {f:>10.3}", k + 1);
    }
}

/// The `search` summary line of `optimize orbiters` and `optimize ground`.
pub fn print_search(s: &SearchResult, search_s: f64, wall_s: f64, opts: &SearchOptions) {
    println!(
        "search      {} evaluations ({} swarm), {:.3} s search, {:.3} s wall; seed {}, {} starts x {} \
         particles x {} iterations + Nelder-Mead",
        s.evaluations,
        s.swarm_evaluations,
        search_s,
        wall_s,
        opts.seed,
        opts.starts,
        opts.particles,
        opts.iterations
    );
}

/// A design's predicted position RMSE.
pub fn lincov_figures(x: &LinCovFigures) -> String {
    format!(
        "{:.2} m time-averaged, {:.2} m final, NEES/dof {:.2}",
        x.avg_m, x.final_m, x.nees_ratio
    )
}

/// The LinCov polish of an optimum.
pub fn print_lincov(l: &LinCovStage) {
    let f = l.filter.name();
    println!();
    println!(
        "lincov      {} = {:.6e}: {}",
        l.figure.name(),
        l.value,
        l.figure.units(l.filter)
    );
    if let Some(i) = &l.input {
        println!(
            "  predicted {f} position RMSE, input:         {}",
            lincov_figures(i)
        );
    }
    println!(
        "  predicted {f} position RMSE, bound optimum: {}",
        lincov_figures(&l.start)
    );
    println!(
        "  predicted {f} position RMSE, polished:      {}",
        lincov_figures(&l.end)
    );
    println!(
        "  polish: {} LinCov evaluations in {:.1} s (Nelder-Mead from the bound's optimum, {} \
         iterations per round, simplex {} of the box)",
        l.evaluations, l.elapsed_s, l.opts.polish_iterations, l.opts.polish_step
    );
}

/// The check (or that it was skipped), and on standard error the warning naming every worse
/// figure.
pub fn print_check(check: Option<&DesignCheck>) {
    let Some(c) = check else {
        println!("check       skipped (--no-check): the optimum is not compared with the input");
        return;
    };
    println!();
    println!(
        "check       {} runs of {} (seed {}) on the input design and on the optimum, with the \
         PCRLB of each",
        c.runs, c.filter, c.seed
    );
    println!(
        "  {:<28} {:>12} {:>12} {:>11} {:>24}",
        "figure", "input", "optimum", "change", "95 % interval of change"
    );
    let f = |v: Option<f64>| v.map_or("-".into(), |v| format!("{v:.4}"));
    let d = c.differences();
    let (a, b) = (&c.input, &c.optimum);
    let rows = [
        ("pos RMSE time-avg [m]", a.rmse_avg(), b.rmse_avg(), d[0].1),
        ("pos RMSE final [m]", a.rmse_final(), b.rmse_final(), d[1].1),
        ("ANEES/dof", a.anees_dof(), b.anees_dof(), d[2].1),
        ("pos PCRLB time-avg [m]", a.pcrlb_avg, b.pcrlb_avg, None),
        ("pos PCRLB final [m]", a.pcrlb_final, b.pcrlb_final, None),
    ];
    for (name, x, y, d) in rows {
        let (change, ci) = d.map_or((String::new(), String::new()), |d| {
            (
                d.rel.map_or("-".into(), |r| format!("{:+.1} %", 100.0 * r)),
                format!(
                    "[{:+.3}, {:+.3}]{}",
                    d.ci_low,
                    d.ci_high,
                    if d.significant { " *" } else { "" }
                ),
            )
        });
        println!(
            "  {name:<28} {:>12} {:>12} {change:>11} {ci:>24}",
            f(x),
            f(y)
        );
    }
    println!("  (* the interval excludes 0; ANEES/dof band {ANEES_BAND:?})");
    match c.warning() {
        None => println!(
            "  verdict: the optimum is not worse than the input on any figure (beyond the Monte \
             Carlo noise)"
        ),
        Some(w) => eprintln!("warning: {w}"),
    }
}
