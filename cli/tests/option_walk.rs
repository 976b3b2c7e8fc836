//! Every option of every `entrynav` subcommand, walked from clap's own command tree with extreme
//! and malformed values (issue 53): no hang, no crash, and every refusal names the option.
//!
//! Each command gets a small valid command line (below); each of its options in turn gets every
//! value of [`walker::extreme_values`] (negative, zero, 10^13, ±1e300, 1e-9, NaN, infinity, empty,
//! a 10 240-character name, a 300-byte file name, a FIFO, a folder, `/dev/zero`). A command
//! added without a base line here fails [`every_command_has_a_base_line`].

#[path = "option_walk/walker.rs"]
mod walker;

use std::path::Path;
use std::process::Command;

fn entrynav() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_entrynav"))
}

/// The valid, quick command line of each command, by option id (`[]` for a flag).
fn base_lines(dir: &Path) -> walker::BaseLines {
    let p = |f: &str| dir.join(f).display().to_string();
    let s = |v: &str| vec![v.to_string()];
    let lib = entrynav()
        .parent()
        .unwrap()
        .join("libentrynav_fmu.so")
        .display()
        .to_string();
    let scenario = |name: &str| ("scenario", s(name));
    let check = vec![("check_runs", s("10")), ("check_filter", s("ekf"))];
    let search = vec![("starts", s("1")), ("iterations", s("5"))];
    let mut b = walker::BaseLines::new();
    let mut add = |path: &str, args: Vec<(&'static str, Vec<String>)>| {
        b.insert(path.to_string(), args);
    };
    add("scenarios", vec![]);
    add("scenario show", vec![("scenario", s("ground-beacons-3"))]);
    add("scenario schema", vec![]);
    add(
        "atmosphere inspect",
        vec![("file", vec![p("gram.txt")]), scenario("msl-airdata")],
    );
    add(
        "atmosphere generate",
        vec![("out", vec![p("generated.txt")])],
    );
    add(
        "simulate",
        vec![scenario("ground-beacons-3"), ("out", vec![p("sim.csv")])],
    );
    add(
        "trade",
        vec![
            scenario("ground-beacons-3"),
            ("runs", s("2")),
            ("filters", s("ekf")),
        ],
    );
    add(
        "trade compare",
        vec![("a", vec![p("a.json")]), ("b", vec![p("b.json")])],
    );
    add("trade merge", vec![("shards", vec![p("shard.json")])]);
    add(
        "tune",
        vec![
            scenario("ground-beacons-3"),
            ("filter", s("ekf")),
            ("runs", s("2")),
            ("validation_runs", s("2")),
            ("max_evaluations", s("6")),
            ("out", vec![p("tuned.toml")]),
        ],
    );
    add(
        "observe",
        vec![scenario("ground-beacons-3"), ("runs", s("2"))],
    );
    add(
        "lincov",
        vec![scenario("ground-beacons-3"), ("filter", s("ekf"))],
    );
    add(
        "train-density",
        vec![
            ("out", vec![p("net.toml")]),
            ("trajectories", s("2")),
            ("epochs", s("1")),
        ],
    );
    add(
        "fmu pack",
        vec![("out", vec![p("fmus")]), ("lib", vec![lib])],
    );
    let mut orbiters = vec![scenario("orbiters-3")];
    orbiters.extend(search.clone());
    orbiters.extend(check.clone());
    add("optimize orbiters", orbiters);
    let mut ground = vec![scenario("ground-beacons-3"), ("beacons", s("3"))];
    ground.extend(search);
    ground.extend(check.clone());
    add("optimize ground", ground);
    let mut select = vec![
        scenario("ground-beacons-3"),
        ("k", s("3")),
        ("grid_deg", s("5")),
    ];
    select.extend(check);
    add("optimize select", select);
    add(
        "guidance deliver",
        vec![
            scenario("msl-guided"),
            ("runs", s("1")),
            ("filters", s("ekf")),
        ],
    );
    add("guidance reference", vec![scenario("msl-guided")]);
    b
}

/// The files the base lines read: a density table, two trade summaries and a shard.
fn make_inputs(dir: &Path) {
    let run = |args: &[&str]| {
        let out = Command::new(entrynav())
            .args(args)
            .current_dir(dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "entrynav {args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    run(&["atmosphere", "generate", "--out", "gram.txt"]);
    let trade = ["trade", "--scenario", "ground-beacons-3", "--runs", "2"];
    run(&[
        &trade[..],
        &["--filters", "ekf", "--json", "a.json", "--quiet"],
    ]
    .concat());
    run(&[
        &trade[..],
        &[
            "--filters",
            "ekf",
            "--seed",
            "2",
            "--json",
            "b.json",
            "--quiet",
        ],
    ]
    .concat());
    run(&[
        &trade[..],
        &[
            "--filters",
            "ekf",
            "--shard",
            "0/1",
            "--json",
            "shard.json",
            "--quiet",
        ],
    ]
    .concat());
}

#[test]
fn a_region_at_negative_coordinates_is_read_after_a_space_and_with_commas() {
    let dir = walker::scratch("region");
    for (i, region) in [
        &["--region", "-34", "-18", "-84", "-74"][..],
        &["--region=-34,-18,-84,-74"][..],
    ]
    .iter()
    .enumerate()
    {
        let json = dir.join(format!("r{i}.json"));
        let mut args: Vec<String> = [
            "optimize",
            "select",
            "--scenario",
            "ground-beacons-3",
            "--k",
            "3",
            "--grid-deg",
            "2",
            "--no-check",
            "--quiet",
            "--json",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        args.push(json.display().to_string());
        args.extend(region.iter().map(|s| s.to_string()));
        let out = walker::run(entrynav(), &args, &dir, i);
        assert_eq!(out.code, Some(0), "{region:?}: {}", out.stderr);
        let doc: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        assert_eq!(
            doc["constraints"]["region_deg"],
            serde_json::json!([-34.0, -18.0, -84.0, -74.0]),
            "{region:?}"
        );
    }
}

#[test]
fn every_command_has_a_base_line() {
    // Panics naming a command without one, or a base line with an option its command lacks.
    let commands = walker::commands(&entrynav_cli::command(), &base_lines(Path::new("/tmp")));
    assert!(commands.len() > 15, "{} commands", commands.len());
}

#[test]
fn every_option_of_every_command_refuses_extreme_values_by_name_and_in_time() {
    let dir = walker::scratch("cli");
    let lib = entrynav().parent().unwrap().join("libentrynav_fmu.so");
    assert!(
        lib.is_file(),
        "{} missing: `fmu pack`'s base line needs it; build the workspace first \
         (cargo build --release --workspace, as scripts/test.sh does)",
        lib.display()
    );
    make_inputs(&dir);
    let commands = walker::commands(&entrynav_cli::command(), &base_lines(&dir));
    let probes = walker::checked_probes(entrynav(), &commands, &dir);
    assert!(probes.len() > 1500, "only {} probes", probes.len());
    walker::assert_all_pass(entrynav(), &probes, &dir);
}

/// Issue 52: `--filter` and `--filters` are both accepted wherever filters are named.
#[test]
fn filter_and_filters_are_both_accepted_everywhere() {
    let cases: [&[&str]; 5] = [
        &["trade", "--scenario", "x"],
        &["tune", "--scenario", "x", "--out", "t.toml"],
        &["lincov", "--scenario", "x"],
        &["guidance", "deliver", "--scenario", "x"],
        &["train-density", "--evaluate", "2"],
    ];
    for case in cases {
        for flag in ["--filter", "--filters"] {
            let mut args = vec!["entrynav"];
            args.extend_from_slice(case);
            args.extend_from_slice(&[flag, "ekf"]);
            let parsed = entrynav_cli::command().try_get_matches_from(&args);
            assert!(parsed.is_ok(), "{args:?}: {}", parsed.unwrap_err());
        }
    }
}
