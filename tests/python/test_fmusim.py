"""Our FMI 2.0 FMUs in the Reference-FMUs' `fmusim` v0.0.39 (the FMI reference importer, in
../shared/tools or $ENTRYNAV_TOOLS; skipped with a message where it is missing or cannot run):
each FMU simulated with fmusim's own co-simulation master equals the in-process library at every
communication point, to the 16 significant digits fmusim writes; the truth FMU also with a 2 s
communication step (longer than its sensors' 1 s)."""

import csv
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import ENTRYNAV_DEV, ROOT, run

FMUSIM = Path(os.environ.get("ENTRYNAV_TOOLS", ROOT.parent / "shared" / "tools")) / "fmusim"


def _usable():
    if not FMUSIM.exists():
        return f"{FMUSIM} not found"
    r = subprocess.run([str(FMUSIM), "--version"], capture_output=True, text=True)
    if r.returncode != 0:
        return f"{FMUSIM} does not run ({r.stderr.strip()[:200]}); scripts/setup.sh installs its libraries"
    return None


REASON = _usable()
pytestmark = pytest.mark.skipif(REASON is not None, reason=f"fmusim unavailable: {REASON}")

PARAMS = {"seed": "4", "dispersed": "true"}


def fmusim(fmu, params, step, stop, tmp_path):
    out = tmp_path / f"{fmu.stem}_fmusim.csv"
    args = [FMUSIM, "--interface-type", "cs", "--output-interval", step, "--stop-time", stop]
    for k, v in params.items():
        args += ["--start-value", k, v]
    r = run([*args, "--log-level", "warning", "--output-file", out, fmu])
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    with open(out) as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:], r.stdout + r.stderr


def reference(model, params, step, stop, tmp_path):
    ref_csv = tmp_path / f"{model}_ref.csv"
    sets = [a for k, v in params.items() for a in ("--set", f"{k}={v}")]
    r = run([ENTRYNAV_DEV, "fmu", "run", "--model", model, "--stop", stop, "--step", step, *sets, "--out", ref_csv])
    assert r.returncode == 0, r.stderr
    return np.genfromtxt(ref_csv, delimiter=",", names=True, deletechars="", dtype=np.float64)


def compare(header, rows, ref, what):
    assert len(rows) == len(ref), (what, len(rows), len(ref))
    compared = 0
    for j, name in enumerate(header):
        if name == "time" or name not in ref.dtype.names:
            continue
        for k, row in enumerate(rows):
            got = float(row[j])
            assert np.isfinite(got), f"{what}: {name} = {row[j]} at row {k}"
            want = float("%.16g" % ref[name][k])
            assert got == want, f"{what}: {name} at t = {row[0]}: fmusim {row[j]}, library {ref[name][k]!r}"
            compared += 1
    return compared


@pytest.mark.parametrize(
    "model,params",
    [
        ("MarsEntryNav", dict(PARAMS, filter="dcifaif")),
        ("MarsEntryNavFilter", dict(PARAMS, filter="dcifaif")),
        ("MarsEntryTruth", PARAMS),
    ],
)
def test_fmusim_equals_the_library(fmus, model, params, tmp_path):
    header, rows, _ = fmusim(fmus[model], params, 1, 300, tmp_path)
    n = compare(header, rows, reference(model, params, 1, 300, tmp_path), model)
    print(f"{model}: {len(rows)} rows, {n} values equal to 16 digits")


def test_fmusim_runs_the_truth_with_a_2_s_step(fmus, tmp_path):
    header, rows, log = fmusim(fmus["MarsEntryTruth"], PARAMS, 2, 300, tmp_path)
    assert float(rows[-1][0]) == 300.0
    n = compare(header, rows, reference("MarsEntryTruth", PARAMS, 2, 300, tmp_path), "truth, 2 s")
    print(f"truth at 2 s: {len(rows)} rows, {n} values equal")
