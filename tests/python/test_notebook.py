"""docs/examples/study.ipynb runs end to end in a Jupyter kernel (nbclient): every cell, including the
asserts that check what its text claims; and it is committed without outputs."""

import json
from pathlib import Path

import pytest

from conftest import ROOT

nbclient = pytest.importorskip("nbclient", reason="nbclient is not installed (scripts/setup.sh installs it)")
nbformat = pytest.importorskip("nbformat")
pytest.importorskip("entrynav", reason="the package is not installed: run scripts/build_python.sh")

NOTEBOOK = ROOT / "docs" / "examples" / "study.ipynb"


def test_the_notebook_is_committed_without_outputs():
    nb = json.loads(NOTEBOOK.read_text())
    for cell in nb["cells"]:
        if cell["cell_type"] == "code":
            assert cell.get("outputs") == [] and cell.get("execution_count") is None


def test_the_study_notebook_runs(tmp_path):
    nb = nbformat.read(str(NOTEBOOK), as_version=4)
    nbclient.NotebookClient(nb, timeout=900, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    text = "\n".join(o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []))
    assert "EKF RMSE / PCRLB" in text and "refused: beacons[0].lat_deg = 123.0" in text
    assert (tmp_path / "study_rmse.png").stat().st_size > 10_000
    print(text)
