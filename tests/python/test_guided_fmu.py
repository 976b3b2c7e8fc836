"""MarsEntryNavGuided (issue 28: truth, navigation filter and guidance in one FMU) in independent FMI
tools: each delivers the vehicle exactly where `entrynav guidance deliver` does for the same run.

* fmpy's validator finds no problem in the FMI 2.0 and FMI 3.0 FMUs;
* fmpy (FMI 2.0 and 3.0), fmusim (FMI 2.0 and 3.0) and OMSimulator fly dispersed run 2 of seed 5
  with the EKF in the loop (parameters `dispersed`, `seed`, `run`) in 1 s steps: the deployment
  time, altitude and miss (distance, downrange, crossrange) at the end are those of run 2 in
  `entrynav guidance deliver --scenario msl-guided --filters ekf --seed 5 --runs 3 --json -`
  (exact doubles through fmpy and OMSimulator's C API, 16 digits through fmusim's CSV), the flown
  bank stays within the 20 deg/s limit and guidance moved it.

fmusim and OMSimulator skip with a message where they are not installed (as test_fmusim.py)."""

import json
import math

import numpy as np
import pytest

from conftest import ENTRYNAV, ENTRYNAV_DEV, run
from test_fmusim import REASON as FMUSIM_REASON
from test_fmusim import fmusim
from test_omsimulator import HAVE_OMS, oms

RATE_LIMIT = math.radians(20.0)  # msl-guided: bank_rate_limit_deg_s
SEED, RUN = 5, 2
PARAMS = {"dispersed": True, "seed": SEED, "run": RUN}
DELIVERY = {  # FMU output -> `guidance deliver` JSON field
    "deploy_time": "t_deploy_s",
    "deploy_altitude": "altitude_m",
    "miss_distance": "miss_m",
    "miss_downrange": "downrange_m",
    "miss_crossrange": "crossrange_m",
}
OUTPUTS = ["guided_status", "deployed", "truth_bank_angle", "guidance_cycles", *DELIVERY]


@pytest.fixture(scope="module")
def packed(tmp_path_factory):
    out = tmp_path_factory.mktemp("guided_fmus")
    for extra in ([], ["--fmi", "3"]):
        r = run([ENTRYNAV, "fmu", "pack", "--out", out, *extra], timeout=300)
        assert r.returncode == 0, r.stdout + r.stderr
    return out


@pytest.fixture(scope="module")
def core():
    """Every run's EKF delivery of the in-process guided loop (None: the run did not deliver)."""
    r = run([ENTRYNAV, "guidance", "deliver", "--scenario", "msl-guided", "--filters", "ekf", "--seed", SEED,
             "--runs", RUN + 1, "--json", "-"], timeout=600)
    assert r.returncode == 0, r.stderr
    rows = json.loads(r.stdout)["runs"]
    return {x["run"]: x.get("delivery") for x in rows if x["row"] == "ekf"}


def check_flight(values, want, what):
    """values: output name -> series (1 s steps from 0), the last row after the end."""
    assert values["guided_status"][-1] == 1 and values["deployed"][-1] == 1, what
    for out, field in DELIVERY.items():
        assert float(values[out][-1]) == want[field], (what, out, values[out][-1], want[field])
    bank = np.asarray(values["truth_bank_angle"], dtype=np.float64)
    assert np.all(np.abs(np.diff(bank[1:])) <= RATE_LIMIT * 1.0 * (1 + 1e-9)), what
    assert np.ptp(bank[1:]) > math.radians(10), f"{what}: guidance never moved the bank"
    assert values["guidance_cycles"][-1] > 100, what


@pytest.mark.parametrize("name", ["MarsEntryNavGuided.fmu", "MarsEntryNavGuided-fmi3.fmu"])
def test_fmpy_validates_the_guided_fmu(packed, name):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(packed / name)) == []


@pytest.mark.parametrize("name", ["MarsEntryNavGuided.fmu", "MarsEntryNavGuided-fmi3.fmu"])
def test_fmpy_delivers_where_guidance_deliver_does(packed, core, name):
    from fmpy import simulate_fmu

    want = core[RUN]
    assert want is not None, "run 2 of seed 5 delivers in process"
    res = simulate_fmu(str(packed / name), stop_time=350.0, output_interval=1.0, start_values=PARAMS,
                       output=OUTPUTS)
    check_flight({n: res[n] for n in OUTPUTS}, want, f"fmpy {name}")
    print(f"fmpy {name}: deployed at t = {float(res['deploy_time'][-1])!r} s, miss {res['miss_distance'][-1]:.1f} m, "
          "equal to guidance deliver")


@pytest.mark.skipif(FMUSIM_REASON is not None, reason=f"fmusim unavailable: {FMUSIM_REASON}")
@pytest.mark.parametrize("name", ["MarsEntryNavGuided.fmu", "MarsEntryNavGuided-fmi3.fmu"])
def test_fmusim_delivers_where_guidance_deliver_does(packed, core, name, tmp_path):
    params = {k: str(v).lower() if isinstance(v, bool) else str(v) for k, v in PARAMS.items()}
    header, rows, _ = fmusim(packed / name, params, 1, 350, tmp_path)
    values = {n: [float(row[header.index(n)]) for row in rows] for n in OUTPUTS}
    # fmusim writes 16 significant digits.
    want = {k: float("%.16g" % v) for k, v in core[RUN].items() if isinstance(v, float)}
    check_flight(values, want, f"fmusim {name}")
    print(f"fmusim {name}: {len(rows)} rows, delivery equal to guidance deliver (16 digits)")


@pytest.mark.skipif(not HAVE_OMS, reason="OMSimulator is not installed (scripts/setup.sh installs its wheel)")
def test_omsimulator_delivers_where_guidance_deliver_does(packed, core, tmp_path):
    spec = {"components": {"g": {"fmu": str(packed / "MarsEntryNavGuided.fmu"), "params": PARAMS}},
            "step": 1.0, "stop": 350.0, "observe": {"g": OUTPUTS}}
    series = np.array(oms(spec, tmp_path)["series"]["g"], dtype=np.float64)
    check_flight({n: series[:, j] for j, n in enumerate(OUTPUTS)}, core[RUN], "OMSimulator")
    print(f"OMSimulator: {len(series)} points, delivery equal to guidance deliver")


@pytest.mark.parametrize("name", ["MarsEntryNavGuided.fmu", "MarsEntryNavGuided-fmi3.fmu"])
def test_the_guided_fmu_survives_the_host_fuzzer(packed, name):
    """Random call sequences through our host (FMI 2.0 or 3.0): no crash, every status as the fuzz
    model predicts (which knows the guided FMU needs a scenario with [guidance])."""
    out = run([ENTRYNAV_DEV, "fmu", "fuzz", packed / name, "--calls", "50000", "--seed", "3"], timeout=600)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    assert "no crash" in out.stdout + out.stderr
    assert "panicked" not in out.stderr
    print(out.stdout.strip()[-400:])
