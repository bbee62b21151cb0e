"""Execute every notebook in ``notebooks/`` headless, in fast mode.

Each notebook runs top to bottom in a fresh kernel (``ipykernel``), with ``RIGIDSIM_FAST=1``
(small frames, fewer steps) and a per-cell timeout. The kernel's interpreter is
``RIGIDSIM_NOTEBOOK_PYTHON`` where set: ``scripts/test.sh`` sets it to ``.venv-notebook``, an
environment with rigidsim and its ``notebook`` extra alone, so a notebook that imports what
that extra does not bring fails here (checked by
``test_the_notebook_environment_has_the_notebook_extra_alone``); unset, the kernel runs in this
interpreter's environment. A cell that raises fails the test with the cell's traceback.
Notebooks are committed without outputs; the test checks that too. Each executed notebook is
kept in the session's ``executed_notebooks`` folder, where the documentation site's test
(``test_site.py``) takes it instead of running the notebook a second time.
"""

from __future__ import annotations

import ast
import json
import os
import subprocess
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOK_DIR = Path(__file__).resolve().parents[2] / "notebooks"
KERNEL_NAME = "rigidsim-notebook"  # the kernel of RIGIDSIM_NOTEBOOK_PYTHON
#: what the notebook extra brings (import names), and what only other extras bring
NOTEBOOK_EXTRA_MODULES = ("ipykernel", "nbclient", "matplotlib_inline", "gymnasium", "k3d")
NOTEBOOK_EXTRA_MODULES += ("msgpack", "cloudpickle", "engine", "render", "navmesh")
OTHER_EXTRAS_MODULES = ("pytest", "sphinx", "ray", "playwright", "hypothesis", "pybullet")
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


def notebook_python() -> Path | None:
    """The interpreter of the notebooks' own environment (None: this one)."""
    named = os.environ.get("RIGIDSIM_NOTEBOOK_PYTHON")
    return Path(named) if named else None


def notebook_kernel(folder: Path, monkeypatch: pytest.MonkeyPatch) -> str:
    """The name of the kernel to run: ``python3`` (this interpreter), or a kernel spec written
    to ``folder`` (found through ``JUPYTER_PATH``) that starts ``RIGIDSIM_NOTEBOOK_PYTHON``."""
    python = notebook_python()
    if python is None:
        return "python3"
    spec = folder / "jupyter" / "kernels" / KERNEL_NAME
    spec.mkdir(parents=True)
    argv = [str(python), "-m", "ipykernel_launcher", "-f", "{connection_file}"]
    kernel = {"argv": argv, "display_name": "rigidsim notebook extra", "language": "python"}
    (spec / "kernel.json").write_text(json.dumps(kernel), encoding="utf-8")
    monkeypatch.setenv("JUPYTER_PATH", str(folder / "jupyter"))
    return KERNEL_NAME


def test_the_notebook_environment_has_the_notebook_extra_alone() -> None:
    python = notebook_python()
    if python is None:
        pytest.skip("RIGIDSIM_NOTEBOOK_PYTHON is not set (scripts/test.sh sets it)")
    probe = "import importlib.util as u, sys; print([m for m in sys.argv[1:] if u.find_spec(m)])"
    modules = [*NOTEBOOK_EXTRA_MODULES, *OTHER_EXTRAS_MODULES]
    root = str(NOTEBOOK_DIR.parent)
    found = subprocess.run(
        [str(python), "-c", probe, *modules],
        capture_output=True,
        text=True,
        check=True,
        cwd=root,
        env={**os.environ, "PYTHONPATH": root},
    ).stdout
    present = set(ast.literal_eval(found))
    assert set(NOTEBOOK_EXTRA_MODULES) <= present, (
        f"{python} lacks {set(NOTEBOOK_EXTRA_MODULES) - present}"
    )
    assert not present & set(OTHER_EXTRAS_MODULES), f"{python} has more than the notebook extra"


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
        kernel_name=notebook_kernel(tmp_path, monkeypatch),
        resources={"metadata": {"path": str(tmp_path)}},  # outputs go to a temp folder
    )
    # the python3 kernelspec's argv[0] "python" is replaced by this interpreter
    # (jupyter_client), so the kernel sees the same virtual environment
    try:
        client.execute()
    except BaseException:
        # the site's test (maybe on another xdist worker) stops waiting for this copy
        (executed_notebooks / f"{path.name}.failed").touch()
        raise
    # the scratch folder, so that the site's build can remove it from printed paths
    notebook.metadata["rigidsim_scratch"] = str(tmp_path)
    written = executed_notebooks / f".{path.name}.writing"
    nbformat.write(notebook, written)
    os.replace(written, executed_notebooks / path.name)  # whole, or not there
    (executed_notebooks / f"{path.name}.failed").unlink(missing_ok=True)
