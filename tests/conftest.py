"""Shared pytest fixtures: where the real Habitat test assets live.

The assets are Habitat-sim's MIT-licensed test assets, committed in ``tests/habitat_data``
(see its README); ``RIGIDSIM_HABITAT_DATA`` names another copy with the same layout.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from browser_support import browser, page  # noqa: E402,F401 - fixtures for the page tests

#: Habitat's test assets as committed in the repository (Habitat's ``data/`` layout)
BUNDLED_HABITAT_DATA = Path(__file__).resolve().parent / "habitat_data"


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
    (``RIGIDSIM_EXECUTED_NOTEBOOKS`` names a folder to keep them across sessions)."""
    kept = os.environ.get("RIGIDSIM_EXECUTED_NOTEBOOKS")
    if kept:
        Path(kept).mkdir(parents=True, exist_ok=True)
        return Path(kept)
    return tmp_path_factory.mktemp("executed_notebooks")


@pytest.fixture(scope="session")
def demo_data(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The generated demo dataset, built once per test session into a temporary folder."""
    from engine.demo import demo_data_path

    return demo_data_path(tmp_path_factory.mktemp("demo_dataset"))
