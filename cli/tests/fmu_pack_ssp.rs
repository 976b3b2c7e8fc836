//! `entrynav fmu pack --ssp --fmi 3` and `--arrays` without `--fmi 3` are refused, and `entrynav fmu pack --help` says why (issue 52):
//! the SSP packages are SSP 1.0, whose connector types describe FMI 1.0/2.0 variables only; FMI 3.0
//! components need SSP 2.0, which OMSimulator 3 does not read
//! (`entrynav_studies::fmu_pack::SSP_FMI3_REFUSAL` cites the clauses).

mod common;
use common::entrynav;

/// `text` with its whitespace runs folded to one space (clap wraps the help).
fn folded(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[test]
fn the_help_says_why_ssp_packages_hold_fmi_2_fmus() {
    let (code, out, err) = entrynav(&["fmu", "pack", "--help"]);
    assert_eq!(code, 0, "{err}");
    let help = folded(&out);
    for part in [
        "FMI 2.0 only (refused with `--fmi 3`)",
        "the packages are SSP 1.0, whose connector types (Real, Integer, Boolean, String, Enumeration, Binary) describe FMI 1.0/2.0 variables only",
        "FMI 3.0 components (Float64, Int64, UInt64, arrays, structural parameters) need SSP 2.0, which OMSimulator 3 does not read",
    ] {
        assert!(help.contains(part), "'{part}' missing from:\n{out}");
    }
}

#[test]
fn ssp_with_fmi_3_is_refused_with_the_reason() {
    let dir = common::scratch_dir("fmu_pack_ssp", "refused");
    let out = dir.join("fmus");
    let (code, stdout, err) = entrynav(&[
        "fmu",
        "pack",
        "--ssp",
        "--fmi",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_ne!(code, 0, "{stdout}");
    let err = folded(&err);
    assert!(
        err.contains("ssp packages are SSP 1.0, whose components are FMI 1.0/2.0 FMUs"),
        "{err}"
    );
    assert!(
        err.contains("FMI 3.0 components need SSP 2.0, which OMSimulator 3 does not read"),
        "{err}"
    );
    // Refused before anything is written.
    assert!(!out.join("MarsEntrySplit.ssp").exists());
    assert!(!out.join("MarsEntryNav-fmi3.fmu").exists());
}

/// `--arrays` (FMI 3.0's est_x, est_sigma, est_covariance, which OMSimulator 3.0 cannot load) is
/// refused without `--fmi 3`, naming the option and both values, before anything is written.
#[test]
fn arrays_without_fmi_3_are_refused() {
    let dir = common::scratch_dir("fmu_pack_ssp", "arrays");
    let out = dir.join("fmus");
    let (code, stdout, err) =
        entrynav(&["fmu", "pack", "--arrays", "--out", out.to_str().unwrap()]);
    assert_ne!(code, 0, "{stdout}");
    assert!(
        folded(&err)
            .contains("arrays = true needs fmi = 3 (fmi = 2): FMI 2.0 has no array variables"),
        "{err}"
    );
    assert!(!out.join("MarsEntryNav.fmu").exists());
    let (code, help, _) = entrynav(&["fmu", "pack", "--help"]);
    assert_eq!(code, 0);
    assert!(
        folded(&help).contains(
            "Off by default because OMSimulator 3.0 cannot load an FMU with a structural parameter"
        ),
        "{help}"
    );
}
