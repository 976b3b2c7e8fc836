"""Shared set-up: the packed FMUs (built by `entrynav fmu pack` if missing) and the tools."""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FMU_DIR = Path(os.environ.get("ENTRYNAV_FMU_DIR", ROOT / "target" / "fmu"))
ENTRYNAV = Path(os.environ.get("ENTRYNAV_BIN", ROOT / "target" / "release" / "entrynav"))
# The developer tools (fmu check, fuzz, run, cross-check): built with the workspace, not shipped.
ENTRYNAV_DEV = Path(os.environ.get("ENTRYNAV_DEV_BIN", ROOT / "target" / "release" / "entrynav-dev"))
VENV_BIN = ROOT / ".venv" / "bin"
MODELS = ["MarsEntryNav", "MarsEntryNavFilter", "MarsEntryTruth"]


@pytest.fixture(scope="session")
def fmus():
    """Paths of the three .fmu files."""
    paths = {m: FMU_DIR / f"{m}.fmu" for m in MODELS}
    if not all(p.exists() for p in paths.values()):
        assert ENTRYNAV.exists(), f"{ENTRYNAV} missing: run cargo build --release --workspace first"
        subprocess.run([str(ENTRYNAV), "fmu", "pack", "--out", str(FMU_DIR)], check=True, timeout=300)
    return paths


def run(cmd, timeout=300, **kw):
    """Run a command in a subprocess (a crash fails the test; a hang times out)."""
    return subprocess.run(
        [str(c) for c in cmd], capture_output=True, text=True, timeout=timeout, **kw
    )
