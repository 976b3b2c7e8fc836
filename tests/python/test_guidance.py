"""MarsEntryGuidance (issue 28) in independent FMI tools, and the guided SSP in OMSimulator.

* fmpy's validator finds no problem in the FMI 2.0 and FMI 3.0 guidance FMUs;
* the FMI Cross-Check files of the guidance FMU (`entrynav-dev fmu cross-check`: its inputs are what the
  in-process guided loop, EKF in the loop, gave its guidance at each 1 s communication point) pass
  fmpy's repository validator, and fmpy (FMI 2.0 and FMI 3.0) and fmusim reproduce the reference
  exactly; the reference itself flies within the 20 deg/s rate limit, reverses the bank and
  deploys on the estimate;
* `MarsEntryGuided.ssp` (truth -> navfilter -> guidance -> truth) in OMSimulator: the guidance FMU
  deploys on its estimate by the range trigger (range to go near zero) with the truth inside the
  deployment box and within a few seconds of the 450 m/s nominal speed, the truth flies the
  guidance's bank one step late, and the bank rate stays within the limit.

fmusim and OMSimulator skip with a message where they are not installed (as test_fmusim.py and
test_omsimulator.py)."""

import csv
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import ENTRYNAV, ENTRYNAV_DEV, ROOT, run

HERE = Path(__file__).resolve().parent
FMUSIM = Path(os.environ.get("ENTRYNAV_TOOLS", ROOT.parent / "shared" / "tools")) / "fmusim"
RATE_LIMIT = math.radians(20.0)  # msl-guided.toml: the [guidance] default bank_rate_limit_deg_s
TRIGGER_MPS = 450.0  # msl-guided.toml: the range trigger's nominal speed (trigger = { range = { nominal_speed_mps = 450.0, … } })

try:
    import OMSimulator  # noqa: F401

    HAVE_OMS = True
except ImportError:
    HAVE_OMS = False


@pytest.fixture(scope="module")
def packed(tmp_path_factory):
    """The generic FMUs (FMI 2.0 with the SSPs, and FMI 3.0) packed from this build."""
    out = tmp_path_factory.mktemp("guidance_fmus")
    for extra in (["--ssp"], ["--fmi", "3"]):
        r = run([ENTRYNAV, "fmu", "pack", "--out", out, *extra], timeout=300)
        assert r.returncode == 0, r.stdout + r.stderr
    return out


@pytest.fixture(scope="module")
def cross_check(packed, tmp_path_factory):
    out = tmp_path_factory.mktemp("guidance_xc")
    r = run([ENTRYNAV_DEV, "fmu", "cross-check", "--out", out, packed / "MarsEntryGuidance.fmu"], timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    (model_dir,) = list(out.glob("fmus/2.0/cs/linux64/entrynav/*/MarsEntryGuidance"))
    return out, model_dir


@pytest.mark.parametrize("name", ["MarsEntryGuidance.fmu", "MarsEntryGuidance-fmi3.fmu"])
def test_fmpy_validates_the_guidance_fmu(packed, name):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(packed / name)) == []


def test_the_cross_check_reference_flies_within_the_limits_and_deploys(cross_check):
    from fmpy.cross_check.validate_vendor_repo import read_csv, validate_repo

    out, model_dir = cross_check
    n_fmus, _, problems = validate_repo(str(out))
    assert n_fmus == 1 and problems == [], problems
    ref = read_csv(str(model_dir / "MarsEntryGuidance_ref.csv"))
    bank, t = ref["bank_command"], ref["time"]
    assert np.all(np.abs(np.diff(bank)) <= RATE_LIMIT * np.diff(t) * (1 + 1e-9))
    assert np.sum(np.diff(np.sign(bank[bank != 0])) != 0) >= 2, "no bank reversal"
    deployed = ref["deployed"].astype(bool)
    k = int(np.argmax(deployed))
    assert deployed[k] and np.all(deployed[k:]), "the estimate never reached the trigger, or it unlatched"
    assert ref["deploy_trigger"][k] <= 0.0 < ref["deploy_trigger"][k - 1]
    # Guidance steered the estimate to within a few km of the target (Apollo, EKF in the loop).
    assert ref["range_to_go"][k] < 10e3, ref["range_to_go"][k]
    # No cycle after deployment.
    assert np.all(ref["guidance_cycles"][k:] == ref["guidance_cycles"][k])
    print(f"deployed on the estimate at t = {t[k]} s, range to go {ref['range_to_go'][k]:.1f} m, "
          f"{int(ref['guidance_cycles'][k])} cycles")


@pytest.mark.parametrize("fmi", [2, 3])
def test_fmpy_reproduces_the_cross_check_reference_exactly(packed, cross_check, fmi):
    from fmpy import simulate_fmu
    from fmpy.cross_check.validate_vendor_repo import read_csv
    from fmpy.util import read_ref_opt_file

    _, model_dir = cross_check
    fmu = model_dir / "MarsEntryGuidance.fmu" if fmi == 2 else packed / "MarsEntryGuidance-fmi3.fmu"
    opt = read_ref_opt_file(str(model_dir / "MarsEntryGuidance_ref.opt"))
    ref = read_csv(str(model_dir / "MarsEntryGuidance_ref.csv"))
    inputs = read_csv(str(model_dir / "MarsEntryGuidance_in.csv"))
    res = simulate_fmu(str(fmu), start_time=opt["StartTime"], stop_time=opt["StopTime"],
                       output_interval=opt["StepSize"], input=inputs, output=list(ref.dtype.names[1:]))
    assert len(res) == len(ref)
    for col in ref.dtype.names[1:]:
        assert np.array_equal(np.asarray(res[col], dtype=np.float64), ref[col]), f"FMI {fmi}: {col} differs"
    print(f"fmpy FMI {fmi}.0: {len(ref)} rows x {len(ref.dtype.names) - 1} outputs equal the reference")


def _fmusim_reason():
    if not FMUSIM.exists():
        return f"{FMUSIM} not found"
    r = subprocess.run([str(FMUSIM), "--version"], capture_output=True, text=True)
    if r.returncode != 0:
        return f"{FMUSIM} does not run ({r.stderr.strip()[:200]}); scripts/setup.sh installs its libraries"
    return None


@pytest.mark.skipif(_fmusim_reason() is not None, reason=f"fmusim unavailable: {_fmusim_reason()}")
def test_fmusim_reproduces_the_cross_check_reference(cross_check, tmp_path):
    _, model_dir = cross_check
    out = tmp_path / "fmusim.csv"
    r = run([FMUSIM, "--interface-type", "cs", "--output-interval", 1, "--stop-time", 350,
             "--input-file", model_dir / "MarsEntryGuidance_in.csv", "--log-level", "warning",
             "--output-file", out, model_dir / "MarsEntryGuidance.fmu"])
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    with open(out) as f:
        rows = list(csv.reader(f))
    with open(model_dir / "MarsEntryGuidance_ref.csv") as f:
        ref = list(csv.reader(f))
    header, ref_header = rows[0], ref[0]
    assert len(rows) == len(ref) == 352
    compared = 0
    for j, name in enumerate(header):
        if name == "time":
            continue
        i = ref_header.index(name)
        for got, want in zip(rows[1:], ref[1:]):
            # fmusim writes 16 significant digits.
            assert float(got[j]) == float("%.16g" % float(want[i])), (name, got[0], got[j], want[i])
            compared += 1
    assert compared == 351 * 12
    print(f"fmusim: {compared} values equal the reference to 16 digits")


@pytest.mark.skipif(not HAVE_OMS, reason="OMSimulator is not installed: scripts/setup.sh installs ../shared/tools/omsimulator-*.whl when present")
def test_the_guided_ssp_closes_the_loop_in_omsimulator(packed, tmp_path):
    import zipfile

    ssp = packed / "MarsEntryGuided.ssp"
    with zipfile.ZipFile(ssp) as z:
        ssv = z.read("resources/MarsEntryGuided.ssv").decode()
    for p in ('"truth.scenario"><ssv:String value="msl-guided.toml"', '"navfilter.filter"><ssv:String value="ekf"'):
        assert p in ssv, ssv
    step, stop = 0.25, 350.0
    spec = {
        "ssp": str(ssp), "system": "MarsEntryGuided", "step": step, "stop": stop,
        "result": str(tmp_path / "oms_guided.csv"),
        # The .ssv's String values, set through the API (OMSimulator 3.0.0.post114 does not apply them).
        "params": {"truth.scenario": "msl-guided.toml", "navfilter.scenario": "msl-guided.toml",
                   "navfilter.filter": "ekf"},
        "observe": {"truth": ["truth_v", "truth_altitude", "truth_bank_angle", "truth_stop_code"],
                    "guidance": ["bank_command", "deployed", "range_to_go", "guidance_cycles"],
                    "navfilter": ["nav_status_code"]},
    }
    out = subprocess.run([sys.executable, HERE / "oms_run.py", json.dumps(spec)], capture_output=True,
                         text=True, timeout=600)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    assert "error" not in out.stderr.lower(), out.stderr[-3000:]
    result = json.loads(next(x for x in out.stdout.splitlines() if x.startswith('{"times"')))
    t = np.array(result["times"])
    truth = np.array(result["series"]["truth"], dtype=np.float64)
    g = np.array(result["series"]["guidance"], dtype=np.float64)
    nav = np.array(result["series"]["navfilter"], dtype=np.float64)
    assert len(t) == round(stop / step) + 1
    v, alt, flown, stop_code = truth.T
    bank, deployed = g[:, 0], g[:, 1].astype(bool)
    # The truth reaches the range trigger's nominal speed above the ground (then flies on to the ground).
    k = int(np.argmax(v <= TRIGGER_MPS))
    assert v[k] <= TRIGGER_MPS < v[k - 1] and alt[k] > 0.0, (t[k], v[k], alt[k])
    # The guidance FMU deploys on its estimate (range trigger: where its range to go reaches zero,
    # inside the window) and latches; the truth is then inside the default deployment box
    # (380-540 m/s, at or above 5 km) and near the nominal speed, within a few seconds of it.
    j = int(np.argmax(deployed))
    assert deployed[j] and np.all(deployed[j:]), "the guidance FMU never deployed"
    assert 380.0 <= v[j] <= 540.0 and alt[j] >= 5000.0, (t[j], v[j], alt[j])
    assert abs(t[j] - t[k]) <= 5.0, (t[j], t[k])
    assert g[j, 2] < 2e3, g[j, 2]
    # The filter never failed; the truth flew the guidance's bank, one step late.
    assert np.all(nav[:, 0] != 2)
    assert np.array_equal(flown[1:], bank[:-1])
    # The bank rate limit holds on every step, and guidance reversed the bank.
    assert np.all(np.abs(np.diff(bank)) <= RATE_LIMIT * step * (1 + 1e-9))
    assert np.sum(np.diff(np.sign(bank[bank != 0])) != 0) >= 2
    print(f"OMSimulator guided SSP: truth at {TRIGGER_MPS} m/s at t = {t[k]} s, altitude {alt[k]:.0f} m; "
          f"guidance deployed at t = {t[j]} s (truth {v[j]:.1f} m/s at {alt[j]:.0f} m) with range to go {g[j, 2]:.1f} m; "
          f"largest bank rate {math.degrees(np.abs(np.diff(bank)).max() / step):.3f} deg/s")
