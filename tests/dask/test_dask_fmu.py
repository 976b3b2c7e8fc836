"""FMU mode of scripts/dask_trade.py: fmpy runs of MarsEntryNav.fmu as Dask tasks on a 2-worker
LocalCluster give exactly the result of the same runs simulated one after another in this process.

The FMU comes from ENTRYNAV_FMU (default target/fmu/MarsEntryNav.fmu; scripts/test.sh packs it with
`entrynav fmu pack --out target/fmu` before running this file).
"""

import importlib.util
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "dask_trade.py"
FMU = Path(os.environ.get("ENTRYNAV_FMU", ROOT / "target" / "fmu" / "MarsEntryNav.fmu"))

spec = importlib.util.spec_from_file_location("dask_trade", SCRIPT)
dask_trade = importlib.util.module_from_spec(spec)
spec.loader.exec_module(dask_trade)

# (scenario, filters, runs): orbiters-3 has Cartesian filter states, dispersed truths and a filter
# start drawn from P0 = (1 km)^2 I per axis; four-beacon-fusion has spherical states and one truth
# (no dispersions), the runs differ in measurement noise only.
CASES = [("orbiters-3", ["ekf", "ukf"], 13), ("four-beacon-fusion", ["ekf", "dcifaif"], 7)]
SEED = 17


@pytest.fixture(scope="module")
def fmu():
    assert FMU.is_file(), f"{FMU} missing: run `target/release/entrynav fmu pack --out target/fmu` or set ENTRYNAV_FMU"
    return FMU


def run_script(*args, timeout=300):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True, timeout=timeout)


@pytest.mark.parametrize("scenario,filters,runs", CASES, ids=[c[0] for c in CASES])
def test_fmu_runs_on_localcluster_equal_sequential(fmu, tmp_path, scenario, filters, runs):
    out, rows_csv = tmp_path / "dask.json", tmp_path / "dask.csv"
    # Batches of 5 runs: uneven batches, several tasks per worker, finishing in any order.
    res = run_script("--fmu", fmu, "--scenario", scenario, "--filters", ",".join(filters), "--runs", runs,
                     "--seed", SEED, "--workers", 2, "--batch-size", 5, "--json", out, "--csv", rows_csv)
    assert res.returncode == 0, res.stderr
    merged = json.loads(out.read_text())

    # The same runs here, one batch, no cluster.
    summary, rows = dask_trade.fmu_study(fmu, scenario, filters, runs, seed=SEED)
    assert merged == json.loads(json.dumps(summary)), "Dask result differs from the sequential one"
    local_csv = tmp_path / "local.csv"
    dask_trade.write_rows_csv(rows, local_csv)
    assert rows_csv.read_text() == local_csv.read_text(), "per-run rows differ"

    # Independent of the script's batching and FMU reuse: the last run of the last filter in a fresh
    # fmpy.simulate_fmu of the packed .fmu has the same final estimation errors.
    from fmpy import simulate_fmu

    last = rows[-1]
    assert (last["filter"], last["run"]) == (filters[-1], runs - 1)
    direct = simulate_fmu(str(fmu), start_values={"scenario": scenario, "filter": filters[-1],
                                                  "seed": dask_trade.fmu_seed(SEED, runs - 1), "dispersed": True})
    for i, name in enumerate(last["states"]):
        assert float(direct[f"err_{i + 1}"][-1]) == last[f"final_{name}"], name

    assert [f["filter"] for f in merged["filters"]] == filters
    for f in merged["filters"]:
        assert f["runs"] == runs and f["failed"] == 0
        start, final, avg = f["pos_initial_rms_m"], f["rmse_final"]["pos_m"], f["rmse_time_avg"]["pos_m"]
        assert all(math.isfinite(v) for v in (start, final, avg)), f
        # The filters converge from a km-level start to tens of metres.
        assert final < 0.01 * start and avg < 0.05 * start, (f["filter"], start, avg, final)
        assert f["within_3sigma_all"] > 0.9, f

    by_filter = {f: [r for r in rows if r["filter"] == f] for f in filters}
    truths = [(r["truth_r0_m"], r["truth_v0_mps"]) for r in by_filter[filters[0]]]
    for f in filters[1:]:  # every filter sees the same K truths
        assert [(r["truth_r0_m"], r["truth_v0_mps"]) for r in by_filter[f]] == truths
    finals = [r["final_pos_m"] for r in by_filter[filters[0]]]
    assert len(set(finals)) == runs, "runs with different seeds gave the same final error"
    if scenario == "orbiters-3":
        assert merged["filters"][0]["coordinates"] == "cartesian"
        assert len(set(truths)) == runs, "different seeds gave the same truth"
        # Filter start drawn from P0 = (1 km)^2 per axis: initial position error RMS sqrt(3) km.
        start = merged["filters"][0]["pos_initial_rms_m"]
        assert 0.5 * math.sqrt(3) * 1e3 < start < 2 * math.sqrt(3) * 1e3, start
        assert merged["filters"][0]["rmse_final"]["pos_m"] < 100.0
    else:
        assert merged["filters"][0]["coordinates"] == "spherical"
        assert len(set(truths)) == 1, "four-beacon-fusion has no dispersions: one truth"


def test_fmu_mode_reports_a_failed_run(fmu, tmp_path):
    res = run_script("--fmu", fmu, "--scenario", "no-such-scenario", "--runs", 2, "--workers", 1,
                     "--json", tmp_path / "x.json")
    assert res.returncode != 0
    assert "no-such-scenario" in res.stderr and "run 0" in res.stderr, res.stderr
    assert not (tmp_path / "x.json").exists()


def test_fmu_seed_is_entrynav_run_seed_truncated():
    # run_seed(seed, run) of core/src/sim/mod.rs, evaluated by the Rust function.
    for seed, run, rust in [(0, 0, 7905728728188956330), (17, 0, 9122641953627174104),
                            (17, 12, 8258036486996729729), (1, 199, 3207441914119346606)]:
        assert dask_trade.fmu_seed(seed, run) == rust >> 33
    seeds = [dask_trade.fmu_seed(SEED, k) for k in range(1000)]
    assert len(set(seeds)) == 1000 and all(0 <= s < 2**31 for s in seeds)
