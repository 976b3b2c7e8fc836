"""The Python package (`import entrynav`, python/, built by scripts/build_python.sh):

- for every built-in, `entrynav.trade(...)` equals the CLI's `--json` summary bit for bit outside
  `provenance` and `timing` (same scenario, filters, runs, seed);
- the result does not depend on the thread count, nor on another trade running at the same time
  in another Python thread;
- a bad field raises ValueError naming it, a missing file FileNotFoundError;
- Ctrl-C during a trade raises KeyboardInterrupt within 1 s with the finished runs attached;
- the wheel installs into a fresh virtual environment and a one-liner like docs/cli.md's (Python) runs.
"""

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from conftest import ENTRYNAV, ROOT, run

entrynav = pytest.importorskip("entrynav", reason="the package is not installed: run scripts/build_python.sh")

BUILTINS = list(entrynav.builtin_scenarios())


def _cli_summary(name, filters, runs, seed, extra=()):
    r = run([ENTRYNAV, "trade", "--scenario", name, "--filters", filters, "--runs", runs, "--seed", seed,
             "--quiet", *extra, "--json", "-"], timeout=600)
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    for key in ("provenance", "timing"):
        doc.pop(key)
    return doc


def test_every_builtin_is_listed_with_a_description():
    cli = run([ENTRYNAV, "scenarios"]).stdout.split("\n")
    assert len(BUILTINS) == len([l for l in cli if l.strip()]) >= 9
    for name, line in entrynav.builtin_scenarios().items():
        assert any(l.startswith(name + " ") and line in l for l in cli), name


@pytest.mark.parametrize("name", BUILTINS)
def test_a_python_trade_equals_the_cli_json_bit_for_bit(name):
    res = entrynav.trade(entrynav.Scenario.builtin(name), ["ekf"], runs=4, seed=3)
    assert res.complete
    cli = _cli_summary(name, "ekf", 4, 3)
    # A scenario with [guidance]: both add the delivery Monte Carlo, the same study as
    # entrynav.deliver's (test_deliver_equals_the_cli...).
    delivery = cli.get("delivery")
    assert (delivery is not None) == ("guidance" in res.scenario.to_dict())
    if delivery is not None:
        assert entrynav.deliver(name, ["ekf"], runs=4, seed=3)["delivery"] == delivery
    assert res.summary == cli


def test_a_changed_scenario_equals_the_cli_with_set():
    sc = entrynav.Scenario.builtin("ground-beacons-3").set("beacons.0.lat_deg", -24.0)
    assert sc.to_dict()["beacons"][0]["lat_deg"] == -24.0
    assert entrynav.Scenario.builtin("ground-beacons-3").to_dict()["beacons"][0]["lat_deg"] != -24.0
    res = entrynav.trade(sc, ["ekf"], runs=6, seed=2)
    cli = _cli_summary("ground-beacons-3", "ekf", 6, 2, ["--set", "beacons.0.lat_deg=-24.0"])
    assert res.summary == cli


def test_series_frames_match_the_summary():
    res = entrynav.trade("four-beacon-fusion", ["ekf", "dcifaif"], runs=5, seed=1)
    rmse = res.rmse("dcifaif")
    assert list(rmse.columns[-5:]) == ["pos_m", "vel_mps", "downrange_m", "crossrange_m", "up_m"]
    final = next(f for f in res.summary["filters"] if f["name"] == "dcifaif")["rmse_final"]["pos_m"]
    assert rmse["pos_m"].iloc[-1] == pytest.approx(final, rel=1e-12)
    assert len(res.final_errors()) == 10
    nees = res.nees("ekf")
    assert {"nees", "nees_lower", "nees_upper", "nis"} <= set(nees.columns)
    assert res.pcrlb() is not None and (res.pcrlb()["pos_m"] > 0).all()
    with pytest.raises(ValueError, match="not in this trade"):
        res.rmse("ukf")


def test_series_are_numpy_views_of_the_native_result_without_a_copy():
    import numpy as np

    res = entrynav.trade("four-beacon-fusion", ["ekf", "dcifaif"], runs=5, seed=1)
    details = res._details["filters"]["dcifaif"]["series"]
    for key in ["times_s", "pos_rmse_m", "nees_mean", "rmse", "local_rmse_m"]:
        a = res.series("dcifaif", key)
        # A view of the bytes the native side handed over: no Python lists, no second buffer
        # (a 2-D series is a reshaped view of the 1-D view).
        root = a
        while isinstance(root, np.ndarray):
            assert not root.flags.owndata, key
            root = root.base
        assert isinstance(root, bytes) and not a.flags.writeable, key
        want = np.array(details[key], dtype=float)
        assert a.shape == want.shape, key
        assert np.array_equal(a, want, equal_nan=True), key
    assert res.series("dcifaif", "rmse").shape == (len(details["times_s"]), len(res.summary["states"]))
    with pytest.raises(ValueError, match="does not exist"):
        res.series("ekf", "no_such_series")
    with pytest.raises(ValueError, match="not in this trade"):
        res.series("ukf", "times_s")


def test_thread_count_and_concurrent_trades_do_not_change_results():
    sc = entrynav.Scenario.builtin("orbiters-3")
    one = entrynav.trade(sc, ["ekf"], runs=16, seed=5, threads=1).summary
    two = entrynav.trade(sc, ["ekf"], runs=16, seed=5, threads=2).summary
    assert one == two
    other = entrynav.trade("four-beacon-fusion", ["ekf"], runs=8, seed=7).summary
    got = {}

    def go(key, *args, **kw):
        got[key] = entrynav.trade(*args, **kw).summary

    threads = [
        threading.Thread(target=go, args=("a", sc, ["ekf"]), kwargs=dict(runs=16, seed=5)),
        threading.Thread(target=go, args=("b", "four-beacon-fusion", ["ekf"]), kwargs=dict(runs=8, seed=7)),
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert got["a"] == one and got["b"] == other


def test_bad_input_raises_python_exceptions_naming_the_field():
    sc = entrynav.Scenario.builtin("ground-beacons-3")
    with pytest.raises(ValueError, match=r"beacons\[0\].lat_deg = 123.0 .*\[-90, 90\]"):
        sc.set("beacons.0.lat_deg", 123.0)
    with pytest.raises(ValueError, match="nonexistent"):
        sc.set("truth.nonexistent", 1)
    with pytest.raises(FileNotFoundError):
        entrynav.Scenario.from_file("/no/such/scenario.toml")
    with pytest.raises(ValueError, match="not a built-in"):
        entrynav.Scenario.builtin("mars-2099")
    # A near miss gets the nearest name, from the package and from the loader alike.
    with pytest.raises(ValueError, match="did you mean 'msl-airdata'"):
        entrynav.Scenario.builtin("msl-airdta")
    with pytest.raises(FileNotFoundError, match="did you mean 'msl-airdata'"):
        entrynav.trade("msl-airdta", ["ekf"], runs=2)
    with pytest.raises(ValueError, match="runs = 0 is out of range"):
        entrynav.trade(sc, ["ekf"], runs=0)
    with pytest.raises(ValueError, match="wiener"):
        entrynav.trade(sc, ["wiener"], runs=2)


def test_an_implausible_entry_value_is_refused_with_its_likely_unit_unless_allowed():
    sc = entrynav.Scenario.builtin("four-beacon-fusion")
    # A speed in km/s: ValueError naming the field, the plausible range and the likely unit, and
    # how to insist; the same message the CLI gives for --set.
    with pytest.raises(ValueError) as refused:
        sc.set("truth.initial.speed_mps", 5.515)
    message = str(refused.value)
    assert "truth.initial.speed_mps = 5.515 is outside what a Mars entry plausibly has" in message
    assert "plausible 3000–8000 m/s (km/s? 5.515 km/s = 5515 m/s)" in message
    assert 'Scenario.set("allow_implausible", True)' in message
    r = run([ENTRYNAV, "trade", "--scenario", "four-beacon-fusion", "--runs", "2",
             "--set", "truth.initial.speed_mps=5.515"], timeout=60)
    assert r.returncode == 2 and "km/s? 5.515 km/s = 5515 m/s" in r.stderr, r.stderr
    with pytest.raises(ValueError, match=r"radians\? -0.21 rad"):
        sc.set("filter.initial.fpa_deg", -0.21)
    # Insisted on: the value is kept and a study runs on it.
    meant = sc.set("allow_implausible", True).set("truth.initial.speed_mps", 5.515)
    assert meant.to_dict()["truth"]["initial"]["speed_mps"] == 5.515
    assert entrynav.trade(meant, ["ekf"], runs=1).summary["runs"] == 1


def test_progress_callback_sees_every_run_and_can_stop_the_trade():
    seen = []
    entrynav.trade("orbiters-3", ["ekf"], runs=40, seed=1, progress=lambda d, n: seen.append((d, n)))
    assert seen[-1] == (40, 40) and all(n == 40 for _, n in seen)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)


CTRL_C = r"""
import json, os, signal, sys, threading, time
import entrynav
threading.Timer(1.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
t0 = time.time()
try:
    entrynav.trade("four-beacon-fusion", ["ekf", "dcifaif"], runs=100000, seed=1)
    print(json.dumps({"raised": False}))
except KeyboardInterrupt as e:
    p = e.partial
    print(json.dumps({"raised": True, "after_signal_s": time.time() - t0 - 1.5, "complete": p.complete,
                      "done": p.summary["runs_completed"], "runs": p.summary["runs"],
                      "pos": p.summary["filters"][0]["rmse_final"]["pos_m"]}))
"""


def test_ctrl_c_raises_keyboard_interrupt_within_a_second_and_keeps_the_finished_runs():
    out = subprocess.run([sys.executable, "-c", CTRL_C], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    r = json.loads(out.stdout.strip().splitlines()[-1])
    assert r["raised"], "the trade ran to the end"
    assert r["after_signal_s"] < 1.0, r
    assert r["complete"] is False and 0 < r["done"] < r["runs"] == 100000, r
    assert r["pos"] is not None and r["pos"] > 0


def test_the_wheel_installs_into_a_fresh_venv_and_the_one_liner_runs(tmp_path):
    wheels = sorted((ROOT / "target" / "wheels").glob("entrynav-*.whl"))
    assert wheels, "no wheel: run scripts/build_python.sh"
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=120)
    py = venv / "bin" / "python"
    r = subprocess.run([str(py), "-m", "pip", "install", "--quiet", "--no-deps", str(wheels[-1])],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    one = "import entrynav; r = entrynav.trade(entrynav.Scenario.builtin('orbiters-3'), ['ekf'], runs=4); print(r.summary['runs_completed'])"
    r = subprocess.run([str(py), "-c", one], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "4"


@pytest.mark.parametrize("name,dispersed", [("msl-airdata", True), ("orbiters-3", False)])
def test_simulate_equals_the_cli_csv(name, dispersed, tmp_path):
    import numpy as np
    import pandas as pd

    df = entrynav.simulate(name, seed=9, dispersed=dispersed)
    out = tmp_path / "sim.csv"
    r = run([ENTRYNAV, "simulate", "--scenario", name, "--seed", 9, *(["--dispersed"] if dispersed else []),
             "--out", out])
    assert r.returncode == 0, r.stderr
    cli = pd.read_csv(out, dtype=float)
    assert list(df.columns) == list(cli.columns)
    assert np.array_equal(df.to_numpy(), cli.to_numpy(), equal_nan=True)
    assert df.attrs["stop"] in ("duration", "stop_speed", "ground")
    assert df.attrs["peaks"]["dynamic_pressure_pa"]["value"] >= df["dynamic_pressure_pa"].max()


def _strip_times(v):
    """A JSON value without its wall-clock fields (elapsed/wall/timing)."""
    if isinstance(v, dict):
        return {k: _strip_times(x) for k, x in v.items()
                if not any(w in k for w in ("elapsed", "wall", "timing", "_ms", "seconds"))}
    if isinstance(v, list):
        return [_strip_times(x) for x in v]
    return v


def test_optimize_ground_equals_the_cli_and_checks_its_answer(tmp_path):
    d = entrynav.optimize_ground("ground-beacons-3", beacons=3)
    js = tmp_path / "g.json"
    r = run([ENTRYNAV, "optimize", "ground", "--scenario", "ground-beacons-3", "--beacons", 3, "--json", js])
    assert r.returncode == 0, r.stderr
    assert _strip_times(d.summary) == _strip_times(json.loads(js.read_text()))
    assert "check" in d.summary
    assert len(d.scenario.to_dict()["beacons"]) == 3
    # The written scenario is a Scenario: trade it directly.
    assert entrynav.trade(d.scenario, ["ekf"], runs=4).complete


def test_observe_and_tune_and_a_refused_design_raise_or_return_like_the_cli(tmp_path):
    o = entrynav.observe("ground-beacons-3", step=5.0)
    assert len(o["delta"]) == 49 and min(o["delta_min"].values() if isinstance(o["delta_min"], dict) else [o["delta_min"]]) > 0
    tuned = entrynav.tune("ground-beacons-3", ["ekf"], runs=8, validation_runs=12, max_evaluations=20, force=True)
    out = tmp_path / "tuned.toml"
    r = run([ENTRYNAV, "tune", "--scenario", "ground-beacons-3", "--filter", "ekf", "--runs", 8, "--validation-runs", 12,
             "--max-evaluations", 20, "--force", "--quiet", "--out", out])
    assert r.returncode == 0, r.stderr
    assert tuned == entrynav.Scenario(out.read_text(), tuned.folder)
    assert entrynav.trade(tuned, ["ekf"], runs=4).complete
    # From a Q 10^8 too large and a budget of 6 evaluations the tuning is better on every primary
    # figure, so written, but still conservative: RuntimeError naming why, with the tuned scenario
    # on `result`, as the CLI writes the file and exits 1.
    big_q = ["filter.q_diag=[1.0e6, 1.0e-6, 1.0e-6, 1.0e4, 1.0e-6, 1.0e-6]"]
    with pytest.raises(RuntimeError, match=r"still inconsistent on the fresh runs: ANEES/dof 0\.\d+ outside \[0\.7, 1\.5\]") as e:
        entrynav.tune(entrynav.Scenario.builtin("ground-beacons-3").with_sets(big_q), ["ekf"], runs=4,
                      validation_runs=8, max_evaluations=6)
    assert e.value.result.to_dict()["filter"]["tuned"]["ekf"]["q_diag"][0] < 1.0e6
    r = run([ENTRYNAV, "tune", "--scenario", "ground-beacons-3", "--set", big_q[0], "--filter", "ekf", "--runs", 4,
             "--validation-runs", 8, "--max-evaluations", 6, "--quiet", "--out", tmp_path / "big.toml"])
    assert r.returncode == 1 and "written, but not consistent yet" in r.stderr, r.stderr
    assert "# WARNING: ekf is still inconsistent on the fresh runs" in (tmp_path / "big.toml").read_text()
    assert entrynav.Scenario((tmp_path / "big.toml").read_text(), tuned.folder) == e.value.result
    # With sites only 2 deg apart the certified logdet selection is worse than the hand-placed sites
    # on this scenario: the CLI's check refuses it (exit 1), which the package raises.
    with pytest.raises(RuntimeError, match="worse than the input design") as refused:
        entrynav.optimize_select("ground-beacons-3", k=3, grid_deg=1.0, exact=True, min_separation_deg=2.0)
    assert "check" in refused.value.result.summary
    with pytest.raises(ValueError, match=r"beacons = -3 is out of range: must be from 1 to 100"):
        entrynav.optimize_ground("ground-beacons-3", beacons=-3)
    with pytest.raises(TypeError, match="unexpected keyword argument 'min_seperation_deg'"):
        entrynav.optimize_ground("ground-beacons-3", min_seperation_deg=2.0)


def test_fmu_pack_from_python(tmp_path):
    lib = ROOT / "target" / "release" / "libentrynav_fmu.so"
    paths = entrynav.fmu_pack(tmp_path, fmi=3, library=lib)
    assert [p.name for p in paths] == ["MarsEntryGuidance-fmi3.fmu", "MarsEntryNav-fmi3.fmu", "MarsEntryNavFilter-fmi3.fmu",
                                       "MarsEntryNavGuided-fmi3.fmu", "MarsEntryTruth-fmi3.fmu"]
    spec = entrynav.fmu_pack(tmp_path, scenario="msl-airdata", library=lib)
    assert [p.name for p in spec] == ["MarsEntryNav_msl_airdata.fmu"]
    # FMI 3.0 declares the arrays only when asked (OMSimulator 3.0 cannot load them), never in FMI 2.0.
    import zipfile

    def declares_arrays(fmu):
        with zipfile.ZipFile(fmu) as z:
            return "n_state_slots" in z.read("modelDescription.xml").decode()

    assert not declares_arrays(tmp_path / "MarsEntryNav-fmi3.fmu")
    arrays = entrynav.fmu_pack(tmp_path / "arrays", fmi=3, arrays=True, library=lib)
    assert declares_arrays(tmp_path / "arrays" / "MarsEntryNav-fmi3.fmu") and len(arrays) == 5
    with pytest.raises(ValueError, match=r"arrays = true needs fmi = 3 \(fmi = 2\)"):
        entrynav.fmu_pack(tmp_path / "fmi2", arrays=True, library=lib)


def test_the_html_report_from_python(tmp_path):
    res = entrynav.trade("four-beacon-fusion", ["ekf", "dcifaif"], runs=6, seed=1)
    page = res.report(tmp_path / "r.html").read_text()
    assert page.startswith("<!DOCTYPE html>") and '<p class="recommendation">' in page
    for section in ("summary", "rmse", "errors", "nees-nis"):
        assert f'<section id="{section}">' in page
    with pytest.raises(ValueError):
        res.report(tmp_path)  # a folder, not a file


def test_deliver_equals_the_cli_and_refuses_a_scenario_without_guidance(tmp_path):
    d = entrynav.deliver("four-beacon-fusion-guided", ["ekf"], runs=3, seed=2)
    js = tmp_path / "d.json"
    r = run([ENTRYNAV, "guidance", "deliver", "--scenario", "four-beacon-fusion-guided", "--filters", "ekf",
             "--runs", 3, "--seed", 2, "--json", js])
    assert r.returncode == 0, r.stderr
    assert d == json.loads(js.read_text())
    rows = {row["name"]: row for row in d["delivery"]["rows"]}
    assert set(rows) == {"perfect-nav", "unguided", "ekf"}
    assert rows["ekf"]["deployed"] == 3 and rows["ekf"]["rms_miss_m"] < 2 * rows["perfect-nav"]["rms_miss_m"]
    with pytest.raises(ValueError, match=r"\[guidance\]"):
        entrynav.deliver("four-beacon-fusion", runs=2)


def test_a_package_shard_of_a_guided_study_merges_with_a_cli_shard_into_the_delivery_table(tmp_path):
    """`trade_shard` of a scenario with `[guidance]` carries its runs' deliveries as the CLI's
    shard file does: a package shard and a CLI shard merge into the single-process delivery."""
    common = ["--scenario", "msl-guided", "--filters", "ekf", "--runs", "300", "--seed", "5"]
    s0 = tmp_path / "s0.json"
    s0.write_text(entrynav.trade_shard("msl-guided", ["ekf"], 300, 5, 0, 2))
    assert len(json.loads(s0.read_text())["delivery"]["runs"]) == 256
    s1 = tmp_path / "s1.json"
    r = run([ENTRYNAV, "trade", *common, "--shard", "1/2", "--quiet", "--json", s1], timeout=600)
    assert r.returncode == 0, r.stderr
    merged = tmp_path / "merged.json"
    r = run([ENTRYNAV, "trade", "merge", s0, s1, "--json", merged], timeout=600)
    assert r.returncode == 0, r.stderr
    whole = _cli_summary("msl-guided", "ekf", 300, 5)
    assert json.loads(merged.read_text())["delivery"] == whole["delivery"]


# The same out-of-range option, refused by the study layer before any work, with one message in
# both front ends: (Python call, the CLI's arguments, the message).
REFUSALS = [
    (lambda: entrynav.trade("orbiters-3", ["ekf"], runs=2, threads=10**6),
     ["trade", "--scenario", "orbiters-3", "--runs", "2", "--threads", "1000000"],
     "threads = 1000000 is out of range: must be from 1 to 1024"),
    (lambda: entrynav.trade("orbiters-3", ["ekf"], runs=2, threads=-1),
     ["trade", "--scenario", "orbiters-3", "--runs", "2", "--threads", "-1"],
     "threads = -1 is out of range: must be from 1 to 1024"),
    (lambda: entrynav.trade("orbiters-3", ["ekf"], runs=0),
     ["trade", "--scenario", "orbiters-3", "--runs", "0"],
     "runs = 0 is out of range: must be from 1 to 10000000"),
    (lambda: entrynav.trade_shard("orbiters-3", ["ekf"], 10**13, 1, 0, 2),
     ["trade", "--scenario", "orbiters-3", "--runs", "10000000000000", "--shard", "0/2", "--json", "/tmp/never.json"],
     "runs = 10000000000000 is out of range: must be from 1 to 10000000"),
    (lambda: entrynav.tune("orbiters-3", ["ekf"], runs=200000),
     ["tune", "--scenario", "orbiters-3", "--runs", "200000", "--out", "/tmp/never.toml"],
     "runs = 200000 is out of range: must be from 1 to 100000"),
    (lambda: entrynav.deliver("msl-guided", runs=0),
     ["guidance", "deliver", "--scenario", "msl-guided", "--runs", "0"],
     "runs = 0 is out of range: must be from 1 to 10000000"),
    (lambda: entrynav.optimize_ground("ground-beacons-3", beacons=10**13),
     ["optimize", "ground", "--scenario", "ground-beacons-3", "--beacons", "10000000000000"],
     "beacons = 10000000000000 is out of range: must be from 1 to 100"),
    (lambda: entrynav.optimize_select("ground-beacons-3", k=10**13),
     ["optimize", "select", "--scenario", "ground-beacons-3", "--k", "10000000000000"],
     "k = 10000000000000 is out of range: must be from 1 to 100"),
    (lambda: entrynav.optimize_orbiters("orbiters-3", particles=1),
     ["optimize", "orbiters", "--scenario", "orbiters-3", "--particles", "1"],
     "particles = 1 is out of range: must be from 2 to 10000"),
    # Issue 53's reproducers.
    (lambda: entrynav.trade("orbiters-3", ["0"], runs=2),
     ["trade", "--scenario", "orbiters-3", "--runs", "2", "--filters", "0"],
     "filters = '0' is unknown: must be one of ekf, ukf, ci, dcifaif, mmae, mmae-moe, ukf-cm, ukf-ac, uskf-nn"),
    (lambda: entrynav.trade("orbiters-3", ["ekf"], runs=2, seed=-1),
     ["trade", "--scenario", "orbiters-3", "--runs", "2", "--seed", "-1"],
     "seed = -1 is out of range: must be from 0 to 18446744073709551615"),
    (lambda: entrynav.optimize_select("ground-beacons-3", k=3, exact=True, time_limit=1e300),
     ["optimize", "select", "--scenario", "ground-beacons-3", "--k", "3", "--exact", "--time-limit", "1e300"],
     "time_limit = 1e300 is out of range: must be a number from 0 to 1000000"),
    (lambda: entrynav.optimize_select("ground-beacons-3", k=3, grid_deg=1e-9),
     ["optimize", "select", "--scenario", "ground-beacons-3", "--k", "3", "--grid-deg", "1e-9"],
     "grid_deg = 1e-9 is out of range: must be a number from 0.05 to 30"),
    (lambda: entrynav.optimize_select("ground-beacons-3", k=3, region=[-34, -18, -84]),
     ["optimize", "select", "--scenario", "ground-beacons-3", "--k", "3", "--region", "-34", "-18", "-84"],
     "region = -34 -18 -84 is out of range: must be four numbers LAT_MIN LAT_MAX LON_MIN LON_MAX [deg], "
     "e.g. -34 -18 -84 -74"),
    (lambda: entrynav.optimize_ground("ground-beacons-3", step=1e300),
     ["optimize", "ground", "--scenario", "ground-beacons-3", "--step", "1e300"],
     "step = 1e300 is out of range: must be a number from 0.01 to 120"),
    (lambda: entrynav.optimize_ground("ground-beacons-3", iterations=10**13),
     ["optimize", "ground", "--scenario", "ground-beacons-3", "--iterations", "10000000000000"],
     "iterations = 10000000000000 is out of range: must be from 0 to 1000000"),
    (lambda: entrynav.optimize_orbiters("orbiters-3", altitude_km=0),
     ["optimize", "orbiters", "--scenario", "orbiters-3", "--altitude-km", "0"],
     "altitude_km = 0 is out of range: must be a number from 80 to 100000"),
]


@pytest.mark.parametrize("python,cli,message", REFUSALS, ids=[" ".join(c[:2]) + " " + c[-1] for _, c, _ in REFUSALS])
def test_an_out_of_range_option_is_refused_with_one_message_by_both_front_ends(python, cli, message):
    start = time.monotonic()
    with pytest.raises(ValueError) as refused:
        python()
    assert str(refused.value) == message
    r = run([ENTRYNAV, *cli], timeout=60)
    assert r.returncode == 2 and message in r.stderr, r.stderr
    # Refused before any work: well under the time of the work itself.
    assert time.monotonic() - start < 30


def test_the_package_links_neither_the_command_line_nor_an_fmi_host():
    manifest = (ROOT / "python" / "Cargo.toml").read_text()
    assert "entrynav-cli" not in manifest and "fmi-host" not in manifest
    tree = run(["cargo", "tree", "-p", "entrynav-python", "-e", "normal", "--prefix", "none"], timeout=600)
    assert tree.returncode == 0, tree.stderr
    names = {line.split()[0] for line in tree.stdout.splitlines() if line.strip()}
    assert "entrynav-studies" in names
    assert not names & {"entrynav-cli", "entrynav-fmi-host", "libloading"}, names
