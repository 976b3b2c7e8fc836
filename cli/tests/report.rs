//! End-to-end tests of `entrynav trade --report FILE.html`: one self-contained page with every
//! section, written before a study's first run is refused, on Ctrl-C, and for grids.

mod common;
use common::entrynav;

fn tmpdir(name: &str) -> std::path::PathBuf {
    common::scratch_dir("report", name)
}

/// No script, style sheet, font or image from anywhere: every `src=`/`href=` is local.
fn assert_self_contained(html: &str) {
    for bad in ["<script", "<link", "<img", "<iframe", "@import", "url("] {
        assert!(!html.contains(bad), "page contains {bad}");
    }
    for attr in ["src=", "href="] {
        for (i, _) in html.match_indices(attr) {
            let value = &html[i + attr.len()..(i + attr.len() + 10).min(html.len())];
            assert!(
                !value.contains("http:") && !value.contains("https:") && !value.contains("//"),
                "network reference {attr}{value}"
            );
        }
    }
}

#[test]
fn trade_report_is_one_self_contained_page_with_every_section() {
    let dir = tmpdir("trade");
    let html_path = dir.join("r.html");
    let json = dir.join("s.json");
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--filters",
        "ekf,dcifaif",
        "--runs",
        "5",
        "--quiet",
        "--set",
        "monte_carlo.runs=7",
        "--json",
        json.to_str().unwrap(),
        "--report",
        html_path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("wrote report"), "{out}");
    let html = std::fs::read_to_string(&html_path).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    for id in [
        "summary",
        "rmse",
        "errors",
        "nees-nis",
        "weights",
        "dispersion",
        "provenance",
    ] {
        assert!(
            html.contains(&format!("<section id=\"{id}\">")),
            "no {id} section"
        );
    }
    assert_self_contained(&html);
    assert!(html.matches("<svg").count() > 20, "inline SVG figures");
    for text in [
        "consistent",
        "PCRLB",
        "ekf",
        "dcifaif",
        "surface-1",
        "surface-2",
        "orbiter-1",
        "orbiter-2",
        "downrange error (m)",
        "χ² 95 %",
    ] {
        assert!(html.contains(text), "page lacks {text}");
    }
    // Each filter's NIS against its own band: DCIFAIF's NIS sums its four local filters'
    // innovations (dof 16), the EKF's has dof 7.
    assert!(
        html.contains("(dof 7.0, ekf)") && html.contains("(dof 16.0, dcifaif)"),
        "NIS bands are not per filter"
    );
    // The 900-px NEES/NIS figures take a row each (labels drawn at full size): NEES, NIS, and
    // each filter's NIS per channel.
    let nees_section = html.split("<section id=\"nees-nis\">").nth(1).unwrap();
    let nees_section = nees_section.split("</section>").next().unwrap();
    assert_eq!(nees_section.matches("<div class=\"fig wide\">").count(), 4);
    for f in ["ekf", "dcifaif"] {
        assert!(
            nees_section.contains(&format!("{f}: NIS per channel over runs")),
            "no per-channel NIS figure of {f}"
        );
    }
    // A decision at the top: the recommendation names the most accurate consistent filter.
    let rec = html
        .split("<p class=\"recommendation\">")
        .nth(1)
        .and_then(|s| s.split("</p>").next())
        .expect("no recommendation line");
    assert!(
        rec.contains("ekf: consistent, lowest position RMSE among the consistent filters")
            && rec.contains("dcifaif consistent"),
        "{rec}"
    );
    assert!(
        html.find("recommendation").unwrap() < html.find("<table").unwrap(),
        "the recommendation is not at the top"
    );
    // Fractions inside ±3σ with one decimal (99.5 % must not read 100 %).
    assert!(
        html.contains("99.") && html.contains(" %</td>"),
        "no one-decimal ±3σ fraction"
    );
    // The provenance block is the summary's.
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let fingerprint = v["provenance"]["scenario_fingerprint"].as_str().unwrap();
    assert!(
        html.contains(fingerprint),
        "fingerprint {fingerprint} missing"
    );
    assert!(html.contains("monte_carlo.runs=7"), "overrides missing");
    assert!(
        html.contains("&quot;command_line&quot;"),
        "command line missing"
    );
}

#[test]
fn a_gated_study_reports_its_gate_and_exclusions() {
    let dir = tmpdir("gating");
    let html_path = dir.join("r.html");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion-faults",
        "--filters",
        "ekf",
        "--runs",
        "4",
        "--quiet",
        "--report",
        html_path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(&html_path).unwrap();
    assert!(html.contains("<section id=\"gating\">"), "no gate section");
    // orbiter-2's 500 m bias from 150 s is excluded in every run.
    assert!(html.contains("ekf / orbiter-2"), "no exclusion row");
    assert!(
        html.contains("4 of 4"),
        "orbiter-2 not excluded in every run"
    );
    // Without a gate there is no such section.
    let plain = dir.join("p.html");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion-faults",
        "--set",
        "filter.gating.enabled=false",
        "--filters",
        "ekf",
        "--runs",
        "2",
        "--quiet",
        "--report",
        plain.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        !std::fs::read_to_string(&plain)
            .unwrap()
            .contains("id=\"gating\"")
    );
}

#[test]
fn an_unwritable_report_path_is_refused_before_the_first_run() {
    let dir = tmpdir("refuse");
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let bad = file.join("r.html");
    let clock = std::time::Instant::now();
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--runs",
        "100000",
        "--report",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--report"), "{err}");
    assert!(clock.elapsed().as_secs() < 10, "refused only after running");
    let (code, _, err) = entrynav(&["trade", "--scenario", "four-beacon-fusion", "--report", "-"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn sigint_writes_the_report_of_the_partial_study() {
    let dir = tmpdir("sigint");
    let html_path = dir.join("partial.html");
    let mut child = common::spawn_with_progress(
        &[
            "trade",
            "--scenario",
            "orbiters-3",
            "--filters",
            "ekf",
            "--threads",
            "1",
            "--runs",
            "1000000",
            "--report",
            html_path.to_str().unwrap(),
        ],
        std::process::Stdio::null(),
    );
    child.wait_for_runs(0);
    child.interrupt();
    let end = child.finish(60);
    assert_eq!(end.status.code(), Some(130), "{}", end.err);
    let done = end.last_progress.unwrap();
    let html = std::fs::read_to_string(&html_path).expect("a partial report");
    assert!(
        html.contains(&format!("INTERRUPTED: {done} of 1000000 runs completed")),
        "the page does not say {done} runs"
    );
    assert!(html.contains("<section id=\"provenance\">"));
}

#[test]
fn grid_report_shows_cells_as_categories() {
    let dir = tmpdir("grid");
    let grid = dir.join("g.toml");
    std::fs::write(
        &grid,
        "name = \"g\"\nruns = 3\nseed = 2\nfilters = [\"ekf\", \"dcifaif\"]\nscenarios = [\"four-beacon-fusion\"]\n\
         [variations]\nbeacons = [2, 4]\n",
    )
    .unwrap();
    let html_path = dir.join("g.html");
    let (code, _, err) = entrynav(&[
        "trade",
        "--grid",
        grid.to_str().unwrap(),
        "--out-dir",
        dir.join("out").to_str().unwrap(),
        "--report",
        html_path.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(&html_path).unwrap();
    assert_self_contained(&html);
    for text in [
        "<section id=\"summary\">",
        "<section id=\"metrics\">",
        "<section id=\"consistency\">",
        "<section id=\"provenance\">",
        "2 beacons",
        "4 beacons",
        "final position error RMSE (m)",
        "grid cell (see the table)",
    ] {
        assert!(html.contains(text), "grid page lacks {text}");
    }
    assert!(html.matches("<svg").count() >= 4);
}

#[test]
fn a_diverged_filter_is_marked_diverged_and_never_recommended() {
    let dir = tmpdir("diverged");
    let html_path = dir.join("r.html");
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--filters",
        "ci,ekf",
        "--runs",
        "6",
        "--quiet",
        "--report",
        html_path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // The CLI prints the same line after its tables.
    let line = out
        .lines()
        .find(|l| l.starts_with("recommendation: "))
        .expect("no recommendation line");
    assert!(
        line.contains("recommendation: ekf: consistent")
            && line.contains("ci diverged in 6/6 runs"),
        "{line}"
    );
    let html = std::fs::read_to_string(&html_path).unwrap();
    // Every verdict cell of CI says it diverged (not "optimistic").
    assert_eq!(
        html.matches("diverged in 6/6 runs</td>").count(),
        3,
        "CI's three verdict cells"
    );
}

/// Issue 52: a filter with a lower RMSE whose σ does not describe its errors is not what the
/// recommendation picks, and the line says why (the tutorial's msl-pressure case).
#[test]
fn a_lower_rmse_from_an_inconsistent_filter_is_named_as_such() {
    let (code, out, err) = common::entrynav(&[
        "trade",
        "--scenario",
        "msl-pressure",
        "--set",
        "dispersions.density_bias=0.05",
        "--filters",
        "ekf,mmae",
        "--runs",
        "50",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let rec = out
        .lines()
        .find(|l| l.starts_with("recommendation:"))
        .unwrap_or_else(|| panic!("no recommendation line in\n{out}"));
    assert!(
        rec.contains("ekf: consistent, lowest position RMSE among the consistent filters"),
        "{rec}"
    );
    assert!(
        rec.contains("mmae optimistic (errors exceed σ)")
            && rec.contains("(lower, but its σ does not describe its errors)"),
        "{rec}"
    );
}

/// The stroke colours of the first SVG after the anchor `id` but black (axes, text).
fn stroke_colours(html: &str, id: &str) -> std::collections::BTreeSet<String> {
    let at = html.find(&format!("id=\"{id}\"")).expect("no such section");
    let start = at + html[at..].find("<svg").expect("no figure");
    let end = start + html[start..].find("</svg>").unwrap();
    html[start..end]
        .match_indices("stroke=\"#")
        .map(|(i, _)| html[start + i + 8..start + i + 15].to_string())
        .filter(|c| c != "#000000")
        .collect()
}

#[test]
fn a_method_both_report_has_contents_the_lincov_table_and_lincov_in_its_filters_colours() {
    let dir = tmpdir("both");
    let html_path = dir.join("r.html");
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--filters",
        "ekf,ci",
        "--runs",
        "6",
        "--quiet",
        "--method",
        "both",
        "--report",
        html_path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(&html_path).unwrap();
    // A table of contents linking every section (and each filter's error grid).
    let toc = &html[html.find("<nav class=\"toc\">").expect("no contents")..];
    let toc = &toc[..toc.find("</nav>").unwrap()];
    for id in [
        "summary",
        "rmse",
        "lincov",
        "errors",
        "errors-ekf",
        "errors-ci",
        "provenance",
    ] {
        assert!(
            toc.contains(&format!("href=\"#{id}\"")),
            "contents lack {id}"
        );
        assert!(html.contains(&format!("id=\"{id}\"")), "no anchor {id}");
    }
    // The LinCov / Monte Carlo table the terminal prints, per filter, with CI's disagreement
    // blamed on its expected divergence, as in the terminal.
    let lincov = &html[html.find("id=\"lincov\"").unwrap()..html.find("id=\"errors\"").unwrap()];
    assert!(lincov.contains("rmse_time_avg.pos_m") && lincov.contains("anees_per_dof"));
    assert_eq!(lincov.matches("<table").count(), 2, "one table per filter");
    let warning = "6 of 6 Monte Carlo runs failed or diverged, which a first-order prediction \
                   about the nominal cannot show; expected: seed 000 §4.1";
    assert!(lincov.contains(warning), "{lincov}");
    assert!(out.contains(warning), "{out}");
    assert!(
        !out.contains("first-order (linear) prediction holds"),
        "{out}"
    );
    // RMSE charts: LinCov dashed in its filter's colour, so two filters and the PCRLB give three
    // colours, not five.
    let colours = stroke_colours(&html, "rmse");
    assert_eq!(
        colours.len(),
        3,
        "ekf, ci (each with LinCov), PCRLB: {colours:?}"
    );
}

#[test]
fn failed_runs_are_counted_and_listed_only_on_request_with_the_papers_explanation() {
    let args = [
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--filters",
        "ci",
        "--runs",
        "4",
        "--quiet",
    ];
    let (code, out, err) = entrynav(&args);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("    run 0 at t = "), "{out}");
    let line = out
        .lines()
        .find(|l| l.contains("4 of 4 runs (100.0%) failed or diverged"))
        .expect("no line for the diverged runs");
    assert!(
        line.contains("expected: seed 000 §4.1 ([P0], the DCIFAIF paper)")
            && line.contains("list them with --list-runs")
            && !line.contains("WARNING"),
        "{line}"
    );
    assert_eq!(
        out.matches("expected: seed 000 §4.1").count(),
        2,
        "the line and the recommendation: {out}"
    );
    let mut listed = args.to_vec();
    listed.push("--list-runs");
    let (code, out, err) = entrynav(&listed);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.matches("\n    run ").count(), 4, "{out}");
    assert!(!out.contains("list them with --list-runs"), "{out}");
}

#[test]
fn an_inconsistent_filter_is_diagnosed_by_epochs_in_the_tables_and_the_report() {
    // msl-pressure-orbiter's EKF is consistent on average but above its NEES band around peak
    // deceleration and below it late in the flight: the tables and the report say where.
    let dir = tmpdir("diagnosis");
    let html_path = dir.join("r.html");
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "msl-pressure-orbiter",
        "--filters",
        "ekf",
        "--runs",
        "30",
        "--quiet",
        "--report",
        html_path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let line = out
        .lines()
        .find(|l| l.starts_with("  diagnosis: "))
        .unwrap_or_else(|| panic!("no diagnosis in {out}"));
    assert!(
        line.contains("% of epochs inside the NEES band (at least 50 % wanted)")
            && line.contains("longest above the band: ")
            && line.contains("longest below: "),
        "{line}"
    );
    let html = std::fs::read_to_string(&html_path).unwrap();
    assert!(html.contains("ekf: ") && html.contains("longest above the band: "));
    // A consistent filter gets none: the demo's EKF.
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--filters",
        "ekf",
        "--runs",
        "20",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("diagnosis:"), "{out}");
}
