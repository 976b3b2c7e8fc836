//! `cargo bench -p entrynav-optimizer --bench select_exact [-- OPTIONS]`: the branch and bound of
//! `entrynav optimize select --exact` on `ground-beacons-3`, as a report (node counts, bound,
//! optimum, wall time), not a timed test.
//!
//! Options: `--k 3,4,5` `--grid-deg 0.5` `--criterion logdet|min-eig` `--eig-epochs S`
//! (min-eig over epochs S seconds apart) `--time-limit 60` (s) `--batch 8` `--no-dives`
//! `--no-screening` `--threads N` `--json FILE`. Candidates are the visible grid sites plus, when
//! k equals their number, the scenario's hand-placed sites (as `optimize select` does). Without
//! `--bench` (i.e. under `cargo test --benches`) it runs nothing.

use entrynav::beacons::BeaconConfig;
use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::select::{BranchBoundOptions, site_information};
use entrynav_optimizer::{
    GroundObjective, GroundProblem, SelectionCriterion, SelectionProblem, Site,
};
use std::time::{Duration, Instant};

fn no_files(p: &str) -> Result<String, entrynav::files::FileError> {
    Err(entrynav::files::FileError::new(p, "no files here"))
}

fn arg(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if !args.iter().any(|a| a == "--bench") {
        return;
    }
    let ks: Vec<usize> = arg(&args, "--k")
        .unwrap_or_else(|| "3,4,5".into())
        .split(',')
        .map(|s| s.parse().expect("--k takes a comma-separated list"))
        .collect();
    let grid: f64 = arg(&args, "--grid-deg").map_or(0.5, |s| s.parse().expect("--grid-deg"));
    let criterion = match arg(&args, "--criterion").as_deref() {
        None | Some("logdet") => SelectionCriterion::LogDet,
        Some("min-eig") => SelectionCriterion::MinEig,
        Some(other) => panic!("--criterion {other}: expected logdet or min-eig"),
    };
    let limit: f64 = arg(&args, "--time-limit").map_or(60.0, |s| s.parse().expect("--time-limit"));
    let batch: usize = arg(&args, "--batch").map_or(8, |s| s.parse().expect("--batch"));
    let threads: Option<usize> = arg(&args, "--threads").map(|s| s.parse().expect("--threads"));
    let dives = !args.iter().any(|a| a == "--no-dives");
    let screening = !args.iter().any(|a| a == "--no-screening");
    let epochs: Option<f64> = arg(&args, "--eig-epochs").map(|s| s.parse().expect("--eig-epochs"));
    let cfg = ScenarioConfig::builtin("ground-beacons-3").expect("built-in scenario");
    let ground = GroundProblem::new(&cfg, &no_files, 3, GroundObjective::LogDet, 1.0, 0.0)
        .expect("ground problem");
    let grid_sites = ground.visible_grid(grid).expect("grid");
    // The scenario's hand-placed surface sites (lat/lon form), certified like `optimize select`.
    let hand: Vec<Site> = cfg
        .beacons
        .iter()
        .filter_map(|b| match b {
            BeaconConfig::Surface(s) => Some(Site::from_degrees(s.lat_deg?, s.lon_deg?)),
            BeaconConfig::Orbiter(_) => None,
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .expect("thread pool");
    println!(
        "ground-beacons-3, {} criterion, grid {grid} deg ({} visible sites), batch {batch}, dives {dives}, screening {screening}, {} threads, limit {limit} s",
        criterion.name(),
        grid_sites.len(),
        pool.current_num_threads()
    );
    println!(
        "{:>2} {:>4} {:>11} {:>11} {:>11} {:>11} {:>9} {:>10} {:>7} {:>7} {:>7} {:>9} {:>8}",
        "k",
        "m",
        "root bound",
        "heuristic",
        "optimum",
        "bound",
        "gap",
        "status",
        "nodes",
        "solves",
        "cheap",
        "screened",
        "time s"
    );
    let mut rows = Vec::new();
    for &k in &ks {
        let mut sites = grid_sites.clone();
        if k == hand.len() {
            sites.extend(hand.iter().copied());
        }
        let blocks = site_information(&ground, &sites, epochs).expect("blocks");
        let problem = SelectionProblem::new(blocks, k, criterion).expect("problem");
        let started = Instant::now();
        let heuristic = problem.solve().expect("heuristic");
        let opts = BranchBoundOptions {
            time_limit: Some(Duration::from_secs_f64(limit)),
            batch,
            dives,
            screening,
            ..BranchBoundOptions::default()
        };
        let r = pool
            .install(|| problem.branch_and_bound(&opts, Some(&heuristic.improved), &|_| {}))
            .expect("branch and bound");
        let wall = started.elapsed().as_secs_f64();
        println!(
            "{k:>2} {:>4} {:>11.6} {:>11.6} {:>11.6} {:>11.6} {:>9.2e} {:>10} {:>7} {:>7} {:>7} {:>9} {wall:>8.2}",
            sites.len(),
            r.root_bound,
            heuristic.improved.value,
            r.best.value,
            r.bound,
            r.gap,
            r.status.name(),
            r.nodes,
            r.solver_calls,
            r.pruned_cheap,
            r.screened,
        );
        let chosen: Vec<String> = r
            .best
            .indices
            .iter()
            .map(|&i| {
                let [lat, lon] = sites[i].degrees();
                format!("({lat:.2}, {lon:.2})")
            })
            .collect();
        println!("   sites {}", chosen.join(" "));
        rows.push(format!(
            "{{\"k\": {k}, \"candidates\": {}, \"root_bound\": {}, \"heuristic\": {}, \"optimum\": {}, \"bound\": {}, \"gap\": {}, \"status\": \"{}\", \"nodes\": {}, \"solver_calls\": {}, \"pruned_cheap\": {}, \"pruned_relaxation\": {}, \"solver_trouble\": {}, \"max_depth\": {}, \"wall_s\": {wall}, \"sites\": \"{}\"}}",
            sites.len(), r.root_bound, heuristic.improved.value, r.best.value, r.bound, r.gap,
            r.status.name(), r.nodes, r.solver_calls, r.pruned_cheap, r.pruned_relaxation,
            r.solver_trouble, r.max_depth, chosen.join(" ")
        ));
    }
    if let Some(path) = arg(&args, "--json") {
        let text = format!(
            "{{\"scenario\": \"ground-beacons-3\", \"criterion\": \"{}\", \"eig_epochs_s\": {}, \"grid_deg\": {grid}, \"time_limit_s\": {limit}, \"batch\": {batch}, \"dives\": {dives}, \"screening\": {screening}, \"threads\": {}, \"runs\": [\n  {}\n]}}\n",
            criterion.name(),
            epochs.map_or("null".to_string(), |e| e.to_string()),
            pool.current_num_threads(),
            rows.join(",\n  ")
        );
        std::fs::write(&path, text).expect("write --json file");
        println!("wrote {path}");
    }
}
