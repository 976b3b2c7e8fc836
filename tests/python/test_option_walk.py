"""Every keyword of the Python API, walked with extreme and malformed values (issue 53): no hang,
no crash of the interpreter, and every refusal a ValueError or TypeError (FileNotFoundError for a
file that is not there) whose message names the keyword.

The keywords come from the functions' signatures and, for the study functions that take
`**options`, from the native module's `keywords(function)`: the field names of the study layer's
options struct, so an option added there is walked without a change here. Each keyword gets every
value of VALUES on top of a small valid call (BASE); the calls of one keyword run in one child
interpreter, which is killed (and the rest of its values run in a new one) when a call has not
returned after 10 s.
"""

import inspect
import json
import os
import re
import selectors
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from conftest import ROOT

entrynav = pytest.importorskip("entrynav", reason="the package is not installed: run scripts/build_python.sh")

TIMEOUT_S = 10.0
LIB = ROOT / "target" / "release" / "libentrynav_fmu.so"

# A small valid call of each function (keyword -> value; `None` entries are left out).
BASE = {
    "trade": dict(scenario="ground-beacons-3", filters=["ekf"], runs=2),
    "trade_shard": dict(scenario="ground-beacons-3", filters=["ekf"], runs=2, seed=1, index=0, count=1),
    "simulate": dict(scenario="ground-beacons-3"),
    "tune": dict(scenario="ground-beacons-3", filters=["ekf"], runs=2, validation_runs=2, max_evaluations=6),
    "observe": dict(scenario="ground-beacons-3", runs=2),
    "deliver": dict(scenario="msl-guided", filters=["ekf"], runs=1),
    "optimize_ground": dict(scenario="ground-beacons-3", beacons=3, starts=1, check_runs=10),
    "optimize_select": dict(scenario="ground-beacons-3", k=3, grid_deg=5, check_runs=10),
    "optimize_orbiters": dict(scenario="orbiters-3", starts=1, iterations=5, check_runs=10),
    "fmu_pack": dict(out="{dir}/fmus", library=str(LIB)),
    "Scenario.builtin": dict(name="ground-beacons-3"),
    "Scenario.from_file": dict(path="{dir}/s.toml"),
    "Scenario.set": dict(path="truth.density_bias", value=0.05),
    "TradeResult.to_json": dict(path="{dir}/r.json"),
    "TradeResult.report": dict(path="{dir}/r.html"),
}

# How a child calls each function with `kw` (a dict).
CALLS = {
    "Scenario.builtin": "entrynav.Scenario.builtin(**kw)",
    "Scenario.from_file": "entrynav.Scenario.from_file(**kw)",
    "Scenario.set": "entrynav.Scenario.builtin('ground-beacons-3').set(**kw)",
    "TradeResult.to_json": "RESULT.to_json(**kw)",
    "TradeResult.report": "RESULT.report(**kw)",
}


def values(folder):
    return [-1, 0, 10**13, 1e300, 1e-9, -1e300, float("nan"), float("inf"), "", "x" * 10240,
            f"{folder}/{'n' * 300}", f"{folder}/pipe", f"{folder}/folder", "/dev/zero", [], {}]


def keywords(name):
    """The keywords of `name`: its signature's, and the native options for `**options`."""
    if "." in name:
        cls, meth = name.split(".")
        fn = getattr(getattr(entrynav, cls), meth)
    else:
        fn = getattr(entrynav, name)
    params = inspect.signature(fn).parameters
    names = [p for p, v in params.items() if v.kind not in (v.VAR_KEYWORD, v.VAR_POSITIONAL) and p != "self"]
    if any(v.kind == v.VAR_KEYWORD for v in params.values()):
        names += [k for k in entrynav._entrynav.keywords(name) if k not in names]
    return names


CHILD = r"""
import json, sys, math
import entrynav
RESULT = None
if {needs_result}:
    RESULT = entrynav.trade("ground-beacons-3", ["ekf"], runs=2)
base = json.loads(sys.argv[1])
for line in sys.stdin:
    key, value = json.loads(line)
    if isinstance(value, dict) and "float" in value:
        value = float(value["float"])
    kw = dict(base)
    if key != "__base__":
        kw[key] = value
    kw = {{k: v for k, v in kw.items() if v is not None}}
    try:
        {call}
        out = {{"ok": True}}
    except BaseException as e:
        out = {{"type": type(e).__name__, "message": str(e)[:2000]}}
    print(json.dumps(out), flush=True)
"""


def encode(v):
    if isinstance(v, float) and not math_finite(v):
        return {"float": repr(v)}
    return v


def math_finite(v):
    return v == v and v not in (float("inf"), float("-inf"))


def run_keyword(name, key, vals, folder):
    """Run every value of `vals` for keyword `key` of `name`; one result per value."""
    base = {k: (v.format(dir=folder) if isinstance(v, str) else v) for k, v in BASE[name].items()}
    call = CALLS.get(name, f"entrynav.{name}(**kw)")
    code = CHILD.format(call=call, needs_result=name.startswith("TradeResult"))
    results = []
    pending = list(vals)
    while pending:
        child = subprocess.Popen([sys.executable, "-c", code, json.dumps(base)], stdin=subprocess.PIPE,
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=folder)
        sel = selectors.DefaultSelector()
        sel.register(child.stdout, selectors.EVENT_READ)
        # The first call also waits for the import (and the trade of RESULT).
        while pending:
            v = pending[0]
            child.stdin.write(json.dumps([key, encode(v)]) + "\n")
            child.stdin.flush()
            ready = sel.select(TIMEOUT_S + (20 if not results else 0))
            line = child.stdout.readline() if ready else ""
            if not line:
                child.kill()
                err = child.stderr.read()[-300:] if not ready else ""
                code_ = child.wait()
                results.append((v, {"hang": True} if not ready else {"crash": code_, "stderr": err}))
                pending.pop(0)
                break
            results.append((v, json.loads(line)))
            pending.pop(0)
        else:
            child.stdin.close()
            child.wait(timeout=30)
    return results


def names_word(text, word):
    return re.search(rf"(?<![\w-]){re.escape(word)}(?![\w-])", text) is not None


# What else names an argument: `Scenario.set`'s value is named by the field it is set on.
ALSO_NAMED = {("Scenario.set", "value"): BASE["Scenario.set"]["path"]}


def verdict(key, value, out, name=""):
    if out.get("hang"):
        return f"hang (no answer after {TIMEOUT_S:.0f} s)"
    if "crash" in out:
        return f"the interpreter died (exit {out['crash']}): {out['stderr']}"
    if out.get("ok"):
        return None
    kind, message = out["type"], out["message"]
    if kind == "RuntimeError" and "worse" in message:
        return None  # a design's verdict on a value it accepted
    if kind not in ("ValueError", "TypeError", "FileNotFoundError"):
        return f"{kind} (not ValueError or TypeError): {message[:200]}"
    also = ALSO_NAMED.get((name, key))
    if not names_word(message, key) and not (also and also in message):
        return f"{kind} without naming {key}: {message[:200]}"
    return None


FUNCTIONS = list(BASE)


def test_the_walk_covers_every_public_study_function():
    public = {n for n, f in vars(entrynav).items() if inspect.isfunction(f) and not n.startswith("_")}
    # Listings and accessors with no option of their own.
    public -= {"builtin_scenarios", "version"}
    assert public <= set(FUNCTIONS), public - set(FUNCTIONS)
    # Every keyword of the study functions, native options included.
    assert "min_elevation_deg" in keywords("optimize_ground")
    assert "region" in keywords("optimize_select")


def test_every_keyword_of_the_python_api_refuses_extreme_values_by_name_and_in_time():
    folder = Path(tempfile.mkdtemp(prefix="entrynav-walk-py-"))
    (folder / "folder").mkdir()
    os.mkfifo(folder / "pipe")
    (folder / "s.toml").write_text(entrynav.Scenario.builtin("ground-beacons-3").to_toml())
    # Each base call alone runs cleanly, so a probe's outcome is its value's.
    for name in FUNCTIONS:
        [(_, out)] = run_keyword(name, "__base__", [None], str(folder))
        assert out.get("ok"), f"the base call of {name} fails: {out}"
    jobs = [(name, key) for name in FUNCTIONS for key in keywords(name)]
    assert len(jobs) > 80, jobs
    start = time.monotonic()
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        outcomes = list(pool.map(lambda j: (j, run_keyword(j[0], j[1], values(folder), str(folder))), jobs))
    failures = []
    for (name, key), results in outcomes:
        for value, out in results:
            why = verdict(key, value, out, name)
            if why:
                failures.append(f"{name}({key}={str(value)[:40]!s}): {why}")
    probes = sum(len(r) for _, r in outcomes)
    accepted = sum(1 for _, r in outcomes for _, out in r if out.get("ok"))
    print(f"{probes} calls of {len(jobs)} keywords in {time.monotonic() - start:.1f} s, {accepted} accepted")
    assert not failures, f"{len(failures)} of {probes} calls failed:\n" + "\n".join(failures)
