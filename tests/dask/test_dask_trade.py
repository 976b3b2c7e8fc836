"""A study run as Dask shard tasks on a 2-worker LocalCluster merges to the single-process result, with
the shards run in the workers' processes by the Python package (the default) or by the CLI."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ENTRYNAV = os.environ.get("ENTRYNAV", str(ROOT / "target" / "release" / "entrynav"))


def summary(path):
    report = json.loads(Path(path).read_text())
    report.pop("timing")  # wall-clock timing: the one non-reproducible block
    provenance = report.pop("provenance")
    # The command lines differ (trade vs trade merge); what the study was must not.
    report["study"] = {k: provenance[k] for k in ("overrides", "atmosphere", "scenario_fingerprint")}
    return report


@pytest.mark.parametrize("engine", ["package", "cli"])
def test_dask_localcluster_matches_single_process(tmp_path, engine):
    common = ["--scenario", "orbiters-3", "--filters", "ekf,ukf", "--runs", "520", "--seed", "17",
              "--set", "filter.update_iterations=2"]
    single = tmp_path / "single.json"
    subprocess.run([ENTRYNAV, "trade", *common, "--json", str(single), "--quiet"], check=True, timeout=600)
    merged = tmp_path / "dask.json"
    res = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "dask_trade.py"), *common, "--shards", "3", "--workers", "2",
         "--engine", engine, "--entrynav", ENTRYNAV, "--json", str(merged)],
        capture_output=True, text=True, timeout=900)
    assert res.returncode == 0, res.stderr
    assert summary(single) == summary(merged)


def test_failed_shard_is_reported(tmp_path):
    res = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "dask_trade.py"), "--scenario", "no-such-scenario", "--runs", "10",
         "--shards", "2", "--workers", "1", "--entrynav", ENTRYNAV, "--json", str(tmp_path / "x.json")],
        capture_output=True, text=True, timeout=600)
    assert res.returncode != 0
    assert "no-such-scenario" in res.stderr
