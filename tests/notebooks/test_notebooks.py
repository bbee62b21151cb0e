"""Execute every notebook in ``notebooks/`` headless, in fast mode.

Each notebook runs top to bottom in a fresh kernel from this interpreter's environment
(``ipykernel``), with ``RIGIDSIM_FAST=1`` (small frames, fewer steps) and a per-cell
timeout. A cell that raises fails the test with the cell's traceback. Notebooks are committed
without outputs; the test checks that too. Each executed notebook is kept in the session's
``executed_notebooks`` folder, where the documentation site's test (``test_site.py``) takes it
instead of running the notebook a second time.
"""

from __future__ import annotations

import os
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOK_DIR = Path(__file__).resolve().parents[2] / "notebooks"
NOTEBOOKS = sorted(NOTEBOOK_DIR.glob("*.ipynb"))
CELL_TIMEOUT_S = 300


EXPECTED_NOTEBOOKS = {
    "01_rigid_body_integration.ipynb",
    "02_contacts_and_solver.ipynb",
    "03_rasterizer.ipynb",
    "04_navmesh.ipynb",
    "07_viewer_contacts.ipynb",
    "08_camera_models.ipynb",
    "managed_rigid_object_tutorial.ipynb",
}


def test_every_teaching_notebook_is_collected() -> None:
    # the parametrized tests below run once per file the glob finds: if it found none (or
    # lost one), they would pass vacuously, so the expected set is spelled out here
    assert EXPECTED_NOTEBOOKS <= {path.name for path in NOTEBOOKS}


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_is_committed_without_outputs(path: Path) -> None:
    notebook = nbformat.read(path, as_version=4)
    for cell in notebook.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, path.name


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_executes_in_fast_mode(
    path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, executed_notebooks: Path
) -> None:
    monkeypatch.setenv("RIGIDSIM_FAST", "1")
    # Jupyter's own backend: figures become PNG outputs, which the docs site shows
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    # the kernel must import this checkout's packages even when run from another folder
    root = str(NOTEBOOK_DIR.parent)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([root, os.environ.get("PYTHONPATH", "")]))
    notebook = nbformat.read(path, as_version=4)
    client = NotebookClient(
        notebook,
        timeout=CELL_TIMEOUT_S,
        kernel_name="python3",
        resources={"metadata": {"path": str(tmp_path)}},  # outputs go to a temp folder
    )
    # the python3 kernelspec's argv[0] "python" is replaced by this interpreter
    # (jupyter_client), so the kernel sees the same virtual environment
    client.execute()
    # the scratch folder, so that the site's build can remove it from printed paths
    notebook.metadata["rigidsim_scratch"] = str(tmp_path)
    nbformat.write(notebook, executed_notebooks / path.name)
