"""The hardening issue against the packed FMUs and external tools: the 7-call sequence for every
filter, GUID binding, stripped libraries, scenario files that cannot leak, the scenario-specific
FMU, and the FMI Cross-Check files checked by fmpy.

Cases that load an FMU library run in a subprocess (cases.py) with a timeout; none may write to
stderr (a Rust panic message would)."""

import json
import os
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from conftest import ENTRYNAV, ENTRYNAV_DEV, MODELS, VENV_BIN, run

HERE = Path(__file__).resolve().parent
MIB = 1024 * 1024


def run_case(case, **kw):
    out = run([sys.executable, HERE / "cases.py", case], timeout=600, **kw)
    assert out.returncode == 0, f"case {case} failed (exit {out.returncode}):\n{out.stdout[-3000:]}\n{out.stderr[-6000:]}"
    assert out.stderr == "", f"case {case} wrote to stderr:\n{out.stderr[-3000:]}"
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("case", ["regression", "guid_binding", "scenario_files"])
def test_hardening_case(fmus, case):
    result = run_case(case)
    print(case, json.dumps(result, indent=1))
    if case == "regression":
        assert len(result) == 18 and all(r["status"] == 3 for r in result.values())


@pytest.mark.parametrize("model", MODELS)
def test_library_is_stripped_and_under_8_mib(fmus, model, tmp_path):
    with zipfile.ZipFile(fmus[model]) as z:
        z.extract(f"binaries/linux64/{model}.so", tmp_path)
    so = tmp_path / "binaries" / "linux64" / f"{model}.so"
    size = so.stat().st_size
    print(f"{model}.so: {size / MIB:.2f} MiB, {fmus[model].stat().st_size / MIB:.2f} MiB packed")
    assert size < 8 * MIB, size
    sections = run(["readelf", "-S", "-W", so]).stdout
    assert ".symtab" not in sections and ".debug_info" not in sections, sections


@pytest.fixture(scope="module")
def specific(tmp_path_factory):
    """MarsEntryNav_msl_airdata.fmu: the combined model specific to msl-airdata, default UKF."""
    out = tmp_path_factory.mktemp("specific")
    r = run([ENTRYNAV, "fmu", "pack", "--out", out, "--scenario", "msl-airdata", "--filter", "ukf"])
    assert r.returncode == 0, r.stdout + r.stderr
    return out / "MarsEntryNav_msl_airdata.fmu"


def test_scenario_specific_fmu(specific, tmp_path):
    from fmpy import read_model_description, simulate_fmu

    for cmd in ([VENV_BIN / "fmpy", "validate", specific], [VENV_BIN / "fmutool", "-input", specific, "-check"]):
        r = run(cmd)
        assert r.returncode == 0 and ("No problems found" in r.stdout or "No semantic error" in r.stdout + r.stderr), r.stdout + r.stderr
    md = read_model_description(str(specific))
    vs = {v.name: v for v in md.modelVariables}
    assert "scenario" not in vs and vs["filter"].start == "ukf"
    for name, unit in [("est.r", "m"), ("est.lon", "rad"), ("est.v", "m/s"), ("est.cd_s_over_m", "m2/kg"),
                       ("est.lift_to_drag", "1"), ("est_sigma.r", "m"), ("err.fpa", "rad"), ("truth_x.heading", "rad")]:
        assert vs[name].unit == unit, (name, vs[name].unit)
    assert not any(n.startswith("est_x_") for n in vs)
    assert (md.defaultExperiment.stopTime, md.defaultExperiment.stepSize) == ("350.0", "0.25")
    with zipfile.ZipFile(specific) as z:
        assert "resources/MarsEntryNav_msl_airdata.toml" in z.namelist()
    # No parameter needed: fmpy's default experiment equals the in-process reference, bit for bit.
    res = simulate_fmu(str(specific), output_interval=0.25)
    ref_csv = tmp_path / "ref.csv"
    r = run([ENTRYNAV_DEV, "fmu", "run", "--fmu", specific, "--stop", "350", "--step", "0.25", "--out", ref_csv])
    assert r.returncode == 0, r.stderr
    ref = np.genfromtxt(ref_csv, delimiter=",", names=True, deletechars="", dtype=np.float64)
    for name in ["est.r", "est.lon", "est_sigma.v", "err.r", "truth_altitude", "nav_status"]:
        assert np.array_equal(np.asarray(res[name], dtype=np.float64), ref[name], equal_nan=True), name
    r = run([ENTRYNAV_DEV, "fmu", "check", specific], timeout=600)
    assert r.returncode == 0 and "bitwise identical" in r.stdout, r.stdout + r.stderr
    print(r.stdout)
    print(run_case("specific_binding", env=dict(os.environ, ENTRYNAV_SPECIFIC_FMU=str(specific))))


def test_cross_check_files_pass_fmpy(fmus, specific, tmp_path):
    from fmpy import simulate_fmu
    from fmpy.cross_check import validate_result
    from fmpy.cross_check.validate_vendor_repo import read_csv, validate_repo
    from fmpy.util import read_ref_opt_file

    out = tmp_path / "xc"
    r = run([ENTRYNAV_DEV, "fmu", "cross-check", "--out", out, *fmus.values(), specific], timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    n_fmus, _, problems = validate_repo(str(out))
    assert n_fmus == 4 and problems == [], problems
    for model_dir in sorted(out.glob("fmus/2.0/cs/linux64/entrynav/*/*")):
        name = model_dir.name
        opt = read_ref_opt_file(str(model_dir / f"{name}_ref.opt"))
        ref = read_csv(str(model_dir / f"{name}_ref.csv"))
        inputs = read_csv(str(model_dir / f"{name}_in.csv"))
        assert len(ref.dtype.names) <= 11 and (model_dir / f"{name}_ref.csv").stat().st_size < 1e6
        res = simulate_fmu(str(model_dir / f"{name}.fmu"), start_time=opt["StartTime"], stop_time=opt["StopTime"],
                           output_interval=opt["StepSize"], input=inputs, output=list(ref.dtype.names[1:]))
        assert validate_result(result=res, reference=ref, t_start=opt["StartTime"], t_stop=opt["StopTime"]) is None
        for col in ref.dtype.names[1:]:
            assert np.array_equal(np.asarray(res[col], dtype=np.float64), ref[col]), f"{name}: {col} differs from the reference"
        print(name, len(ref), "rows", ref.dtype.names[1:])
    # The filter fed from its cross-check input (the truth's measurements and bank, one step late)
    # reproduces the combined FMU one step late, bit for bit.
    vendor = next(out.glob("fmus/2.0/cs/linux64/entrynav/*"))
    comb = read_csv(str(vendor / "MarsEntryNav" / "MarsEntryNav_ref.csv"))
    filt = read_csv(str(vendor / "MarsEntryNavFilter" / "MarsEntryNavFilter_ref.csv"))
    shared = [c for c in filt.dtype.names[1:] if c in comb.dtype.names]
    assert {"est_r", "est_v", "est_fpa", "nav_time", "n_meas"} <= set(shared), shared
    for col in shared:
        assert np.array_equal(filt[col][1:], comb[col][:-1]), f"filter {col} is not the combined FMU's one step late"
    # Across the bank switches at 100 s and 200 s the filter runs on (no jump in its estimate).
    assert filt["n_meas"][-1] > 0 and np.all(np.isfinite(filt["est_r"]))
