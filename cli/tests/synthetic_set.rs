//! `entrynav atmosphere generate` writes the synthetic test set of docs/density.md as a Mars-GRAM
//! Monte Carlo set that `atmosphere inspect` and `trade --atmosphere-file` read back.

mod common;
use common::entrynav;

#[test]
fn generated_set_is_read_back_as_18_covering_profiles_and_flown_by_the_trade() {
    let dir = std::env::temp_dir().join(format!("entrynav-synth-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("set.txt");
    let path = file.to_str().unwrap();
    let (code, out, err) = entrynav(&["atmosphere", "generate", "--out", path]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("18 profiles"), "{out}");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("#      Var_X      DENSTOT       Radius"));
    // The same seed writes the same file; another seed another one.
    let again = dir.join("again.txt");
    entrynav(&["atmosphere", "generate", "--out", again.to_str().unwrap()]);
    assert_eq!(std::fs::read_to_string(&again).unwrap(), text);
    let other = dir.join("other.txt");
    entrynav(&[
        "atmosphere",
        "generate",
        "--out",
        other.to_str().unwrap(),
        "--seed",
        "2",
    ]);
    assert_ne!(std::fs::read_to_string(&other).unwrap(), text);

    let (code, out, err) = entrynav(&["atmosphere", "inspect", path, "--scenario", "msl-airdata"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("profiles  18"), "{out}");
    assert!(out.contains("radius column Radius"), "{out}");
    assert!(!err.contains("warning"), "{err}");

    // Two runs fly profiles 0 and 1 (run k flies profile k mod 18).
    let (code, json, err) = entrynav(&[
        "trade",
        "--scenario",
        "msl-airdata",
        "--filters",
        "uskf-nn",
        "--runs",
        "2",
        "--quiet",
        "--atmosphere-file",
        path,
        "--json",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(json.contains("run k flies profile k mod 18"), "{json}");
    let (code, _, err) = entrynav(&[
        "atmosphere",
        "generate",
        "--out",
        path,
        "--factors-above",
        "0",
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("factors_above = 0 is out of range: must be a number from 0.01 to 100"),
        "{err}"
    );

    // The extended set: the 18 standard profiles, unchanged, then 12 high-latitude ones.
    let ext = dir.join("extended.txt");
    let (code, out, err) = entrynav(&[
        "atmosphere",
        "generate",
        "--preset",
        "extended",
        "--out",
        ext.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("30 profiles"), "{out}");
    assert_eq!(out.matches("(high latitude)").count(), 12, "{out}");
    let ext_text = std::fs::read_to_string(&ext).unwrap();
    let rows = |t: &str| -> Vec<String> {
        t.lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect()
    };
    let (std_rows, ext_rows) = (rows(&text), rows(&ext_text));
    assert_eq!(ext_rows.len(), 30 * 151);
    assert_eq!(&ext_rows[..std_rows.len()], &std_rows[..]);
    let (code, out, err) = entrynav(&["atmosphere", "inspect", ext.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("profiles  30"), "{out}");
    let (code, _, err) = entrynav(&[
        "atmosphere",
        "generate",
        "--preset",
        "high-latitude",
        "--factors-above",
        "1",
        "--out",
        ext.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("--preset"), "{err}");
}
