"""Our FMUs in OMSimulator 3 (OpenModelica's FMI/SSP co-simulation engine, the wheel in
../shared/tools; skipped with a message where it is not installed): OMSimulator rejects a NaN
output (it drops the step's whole result row) and stops on fmi2Warning from a step.

* each FMU alone, 1 s steps over the default 300 s: no result row lost, and every observed output
  after every step bitwise equal to the in-process library (`entrynav-dev fmu run`);
* the truth FMU with a 2 s step (longer than its 1 s sensors) runs to the end, bitwise equal;
* the split pair connected in OMSimulator (truth measurements into the filter) beside the combined
  FMU: the filter's estimate is the combined FMU's one step late, bitwise;
* the SSP packages of `entrynav fmu pack --ssp` (valid against the SSP 1.0 schemas OMSimulator
  ships; the guided one is run in test_guidance.py): the split system, flown with a bank profile and a beacon outage through its system
  inputs, is the combined system one step late, bitwise."""

import csv
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import ENTRYNAV, ENTRYNAV_DEV, run

HERE = Path(__file__).resolve().parent

try:
    import OMSimulator  # noqa: F401

    HAVE_OMS = True
except ImportError:
    HAVE_OMS = False

pytestmark = pytest.mark.skipif(
    not HAVE_OMS,
    reason="OMSimulator is not installed: scripts/setup.sh installs ../shared/tools/omsimulator-*.whl when present",
)

PARAMS = {"seed": 4, "dispersed": True}
EST = ["est_r", "est_lon", "est_v", "est_fpa", "est_sigma_1", "nav_time", "nis", "n_meas", "nav_status_code"]
TRUTH = ["truth_r", "truth_v", "truth_density", "meas_epoch", "meas_time", "meas_range_1", "meas_range_1_valid"]


def oms(spec, tmp_path):
    spec = dict(spec, result=str(tmp_path / "oms_result.csv"))
    out = subprocess.run([sys.executable, HERE / "oms_run.py", json.dumps(spec)], capture_output=True, text=True,
                         timeout=600)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    assert "error" not in out.stderr.lower(), out.stderr[-3000:]
    line = next(x for x in out.stdout.splitlines() if x.startswith('{"times"'))
    result = json.loads(line)
    with open(spec["result"]) as f:
        rows = list(csv.reader(f))
    result["result_times"] = sorted({float(r[0]) for r in rows[1:]})
    result["stdout"] = out.stdout
    return result


def reference(model, step, stop, params, tmp_path):
    ref_csv = tmp_path / f"{model}_ref.csv"
    sets = [a for k, v in params.items() for a in ("--set", f"{k}={str(v).lower() if isinstance(v, bool) else v}")]
    r = run([ENTRYNAV_DEV, "fmu", "run", "--model", model, "--stop", stop, "--step", step, *sets, "--out", ref_csv])
    assert r.returncode == 0, r.stderr
    return np.genfromtxt(ref_csv, delimiter=",", names=True, deletechars="", dtype=np.float64)


def assert_bitwise(series, names, ref, what):
    got = np.array(series, dtype=np.float64)
    assert got.shape == (len(ref), len(names)), (what, got.shape, len(ref))
    for j, n in enumerate(names):
        col = "nav_status" if n == "nav_status_code" else n
        assert np.array_equal(got[:, j], ref[col]), f"{what}: {n} differs from the in-process library"
        assert np.all(np.isfinite(got[:, j])), f"{what}: {n} not finite"


@pytest.mark.parametrize(
    "model,observe,params",
    [
        ("MarsEntryNav", EST + TRUTH[:3], dict(PARAMS, filter="dcifaif")),
        ("MarsEntryNavFilter", EST, dict(PARAMS, filter="dcifaif")),
        ("MarsEntryTruth", TRUTH, PARAMS),
    ],
)
def test_each_fmu_alone_loses_no_row_and_matches_the_library(fmus, model, observe, params, tmp_path):
    res = oms({"components": {"c": {"fmu": str(fmus[model]), "params": params}}, "step": 1.0, "stop": 300.0,
               "observe": {"c": observe}}, tmp_path)
    assert res["result_times"] == [float(k) for k in range(301)], f"{model}: result rows lost"
    assert_bitwise(res["series"]["c"], observe, reference(model, 1, 300, params, tmp_path), model)
    print(model, "301 rows, bitwise equal to the library;", len(observe), "outputs")


def test_the_truth_fmu_runs_with_a_2_s_step(fmus, tmp_path):
    res = oms({"components": {"c": {"fmu": str(fmus["MarsEntryTruth"]), "params": PARAMS}}, "step": 2.0,
               "stop": 300.0, "observe": {"c": TRUTH}}, tmp_path)
    assert res["result_times"][-1] == 300.0, res["result_times"][-5:]
    assert_bitwise(res["series"]["c"], TRUTH, reference("MarsEntryTruth", 2, 300, PARAMS, tmp_path), "truth, 2 s")
    assert "spans 2 measurement epochs" in res["stdout"], res["stdout"][-2000:]


def test_the_split_pair_is_the_combined_fmu_one_step_late(fmus, tmp_path):
    from fmpy import read_model_description

    md = read_model_description(str(fmus["MarsEntryTruth"]))
    meas = [v.name for v in md.modelVariables if v.causality == "output" and v.name.startswith("meas_")]
    params = dict(PARAMS, filter="dcifaif")
    res = oms({
        "components": {
            # (A component named like one of its variables, "filter", crashes OMSimulator 3.)
            "nav": {"fmu": str(fmus["MarsEntryNav"]), "params": params},
            "tru": {"fmu": str(fmus["MarsEntryTruth"]), "params": PARAMS},
            "flt": {"fmu": str(fmus["MarsEntryNavFilter"]), "params": params},
        },
        "connections": [[f"tru.{m}", f"flt.{m}"] for m in meas],
        "step": 1.0,
        "stop": 300.0,
        "observe": {"nav": EST, "flt": EST},
    }, tmp_path)
    comb = np.array(res["series"]["nav"], dtype=np.float64)
    filt = np.array(res["series"]["flt"], dtype=np.float64)
    assert filt[-1, EST.index("n_meas")] > 0, "the filter never received a measurement"
    assert np.array_equal(filt[1:], comb[:-1]), "the split filter is not the combined FMU one step late"
    print(f"split pair: {len(meas)} connections, {filt[1:].size} values equal one step late")


@pytest.fixture(scope="module")
def ssps(tmp_path_factory):
    out = tmp_path_factory.mktemp("ssp")
    r = run([ENTRYNAV, "fmu", "pack", "--out", out, "--ssp"], timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    return {"split": out / "MarsEntrySplit.ssp", "combined": out / "MarsEntryNav.ssp",
            "guided": out / "MarsEntryGuided.ssp"}


def test_ssp_packages_are_valid_ssp_1_0(ssps):
    import zipfile

    from lxml import etree

    schema_dir = Path(OMSimulator.__file__).parent / "schema" / "ssp"
    ssd_schema = etree.XMLSchema(etree.parse(str(schema_dir / "SystemStructureDescription.xsd")))
    ssv_schema = etree.XMLSchema(etree.parse(str(schema_dir / "SystemStructureParameterValues.xsd")))
    for name, path in ssps.items():
        with zipfile.ZipFile(path) as z:
            names = z.namelist()
            ssd = etree.fromstring(z.read("SystemStructure.ssd"))
            assert ssd_schema.validate(ssd), (name, ssd_schema.error_log)
            ssv_files = [n for n in names if n.endswith(".ssv")]
            assert len(ssv_files) == 1, names
            ssv = etree.fromstring(z.read(ssv_files[0]))
            assert ssv_schema.validate(ssv), (name, ssv_schema.error_log)
            for comp in ssd.iter("{http://ssp-standard.org/SSP1/SystemStructureDescription}Component"):
                assert comp.get("source") in names, (name, comp.get("source"))
        print(name, names)


BANK = [[0.0, 0.0], [100.0, 0.35], [200.0, -0.2]]
OUTAGE = [[0.0, True], [120.0, False], [180.0, True]]


def test_the_ssp_split_system_is_the_combined_system_one_step_late(ssps, tmp_path):
    inputs = {"bank_angle": BANK, "beacon_available_2": OUTAGE}
    split = oms({"ssp": str(ssps["split"]), "system": "MarsEntrySplit", "inputs": inputs, "step": 1.0,
                 "stop": 300.0, "observe": {"navfilter": EST, "truth": ["truth_bank_angle", "truth_r"]}}, tmp_path)
    comb = oms({"ssp": str(ssps["combined"]), "system": "MarsEntryNav", "inputs": inputs, "step": 1.0,
                "stop": 300.0, "observe": {"nav": EST + ["truth_r"]}}, tmp_path)
    assert split["result_times"] == [float(k) for k in range(301)]
    f = np.array(split["series"]["navfilter"], dtype=np.float64)
    t = np.array(split["series"]["truth"], dtype=np.float64)
    c = np.array(comb["series"]["nav"], dtype=np.float64)
    # The truth flew the bank profile (truth_bank_angle after the step from t is BANK at t).
    assert t[101, 0] == 0.35 and t[201, 0] == -0.2 and t[100, 0] == 0.0
    assert np.array_equal(t[:, 1], c[:, -1]), "the split truth is not the combined truth"
    assert f[-1, EST.index("n_meas")] > 0
    assert np.array_equal(f[1:], c[:-1, :-1]), "the SSP split filter is not the combined system one step late"
    print(f"SSP split vs combined: {f[1:].size} values equal one step late across the bank switches and the outage")
