"""Shared pytest fixtures (where the real Habitat test assets live, the demo dataset, the
executed notebooks) and how the suite is spread over the cores.

The assets are Habitat-sim's MIT-licensed test assets, committed in ``tests/habitat_data``
(see its README); ``RIGIDSIM_HABITAT_DATA`` names another copy with the same layout.

``scripts/test.sh`` runs the suite with pytest-xdist (``-n auto --dist loadfile``). Each
worker process builds its own session fixtures (the demo dataset into its own temporary
folder). :func:`pytest_xdist_make_scheduler` keeps every test file on one worker (its module
fixtures, such as the tutorial run or a navmesh build, are built once), except that each
notebook runs on its own and the tests that start a Ray cluster share one worker
(:data:`SHARED_GROUPS`); :func:`pytest_collection_modifyitems` sends the groups that take
minutes out first (:data:`FIRST`), so that none is left running alone at the end. The executed
notebooks go to a folder all workers share, where the documentation site's test waits for
them (``executed_notebooks``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from browser_support import browser, page  # noqa: E402,F401 - fixtures for the page tests

#: Habitat's test assets as committed in the repository (Habitat's ``data/`` layout)
BUNDLED_HABITAT_DATA = Path(__file__).resolve().parent / "habitat_data"
#: node-id prefixes whose tests share one xdist worker across files: every Ray cluster on one
#: worker (one cluster at a time); each notebook alone (they are the longest tests)
SHARED_GROUPS = {
    "tests/batch/test_ray_backend.py": "ray",
    "tests/examples/test_examples.py::test_batch_sweep_bounces_follow_e_squared[ray]": "ray",
}
NOTEBOOK_RUNS = "tests/notebooks/test_notebooks.py::test_notebook_executes_in_fast_mode"
#: the notebooks, longest first (measured in fast mode: 2 min down to 20 s), so that the last
#: ones finish together
NOTEBOOKS_LONGEST_FIRST = (
    "managed_rigid_object_tutorial",
    "02_contacts_and_solver",
    "06_many_simulations",
    "05_navigation_basics",
    "07_viewer_contacts",
    "01_rigid_body_integration",
    "04_navmesh",
    "08_camera_models",
    "03_rasterizer",
)
#: node-id prefixes of the groups that take minutes, in the order they are sent out: the
#: notebooks first (the site's test waits for their executed copies), then the site (the
#: longest unit) and the others
FIRST = (
    *(f"{NOTEBOOK_RUNS}[{name}]" for name in NOTEBOOKS_LONGEST_FIRST),
    NOTEBOOK_RUNS,
    "tests/notebooks/test_site.py",
    "tests/engine/test_tutorial.py",
    "tests/reliability/test_soak.py",
    "tests/batch/test_ray_backend.py",
    "tests/examples/test_examples.py",
)


def habitat_data_dir() -> Path:
    """Return the folder holding Habitat's ``test_assets`` and physics configs."""
    # resolved: template handles are resolved paths, so a symlinked copy still matches
    override = os.environ.get("RIGIDSIM_HABITAT_DATA")
    if override:
        return Path(override).resolve()
    return BUNDLED_HABITAT_DATA


@pytest.fixture(scope="session")
def habitat_data() -> Path:
    path = habitat_data_dir()
    if not path.is_dir():
        pytest.fail(
            f"Habitat test assets not found at {path}: RIGIDSIM_HABITAT_DATA names a folder "
            "that does not exist (unset it to use tests/habitat_data)"
        )
    return path


@pytest.fixture(scope="session")
def test_assets(habitat_data: Path) -> Path:
    return habitat_data / "test_assets"


@pytest.fixture(scope="session")
def executed_notebooks(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Where the notebook tests leave executed copies for the docs site's test to reuse
    (``RIGIDSIM_EXECUTED_NOTEBOOKS`` names a folder to keep them across sessions). Under
    xdist the folder is shared by the session's workers (beside their temporary folders)."""
    kept = os.environ.get("RIGIDSIM_EXECUTED_NOTEBOOKS")
    if kept:
        Path(kept).mkdir(parents=True, exist_ok=True)
        return Path(kept)
    if os.environ.get("PYTEST_XDIST_WORKER"):  # set by xdist in its workers
        shared = tmp_path_factory.getbasetemp().parent / "executed_notebooks"
        shared.mkdir(exist_ok=True)
        return shared
    return tmp_path_factory.mktemp("executed_notebooks")


@pytest.fixture(scope="session")
def demo_data(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The generated demo dataset, built once per test session into a temporary folder."""
    from engine.demo import demo_data_path

    return demo_data_path(tmp_path_factory.mktemp("demo_dataset"))


def worker_group(nodeid: str) -> str:
    """The unit of work an xdist worker takes whole: the test's file, or its shared group."""
    if nodeid.startswith(NOTEBOOK_RUNS):
        return nodeid
    for prefix, group in SHARED_GROUPS.items():
        if nodeid.startswith(prefix):
            return group
    return nodeid.split("::", 1)[0]


@pytest.hookimpl(tryfirst=True, optionalhook=True)  # before xdist's own; only with xdist
def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    """``--dist loadfile`` with :func:`worker_group` as the unit, in collection order."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class GroupScheduling(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return worker_group(nodeid)

    config.option.loadscopereorder = False  # keep FIRST first (not the largest files first)
    return GroupScheduling(config, log)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """On xdist's workers, put the slow groups (:data:`FIRST`) at the head of the queue."""
    if not hasattr(config, "workerinput"):
        return

    def rank(item: pytest.Item) -> int:
        found = [i for i, prefix in enumerate(FIRST) if item.nodeid.startswith(prefix)]
        return found[0] if found else len(FIRST)

    items.sort(key=rank)  # stable: collection order within a rank
