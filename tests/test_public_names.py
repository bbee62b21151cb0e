"""The public names: every name in every ``__all__`` imports, and ``engine.__version__``.

``from engine import *`` once failed with ``ModuleNotFoundError`` because ``__all__`` still
listed a module that had moved; a star import of each package, in a fresh interpreter so that
no earlier import hides a missing module, catches that.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def all_modules() -> list[str]:
    """Every module of the three packages, by file (``__main__`` runs a job: left out)."""
    names = []
    for top in ("engine", "render", "navmesh"):
        for path in sorted((ROOT / top).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            if parts[-1] == "__main__":
                continue
            names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


MODULES = all_modules()


def test_the_module_list_is_not_empty() -> None:
    assert {"engine", "render", "navmesh", "engine.physics.world"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_every_name_in_all_resolves(name: str) -> None:
    module = importlib.import_module(name)
    names = list(getattr(module, "__all__", []))
    if name in ("engine", "render", "navmesh"):
        assert names, f"{name} has no __all__"
    assert len(names) == len(set(names)), f"{name}.__all__ repeats a name"
    missing = [n for n in names if not hasattr(module, n)]
    assert missing == [], f"{name}.__all__ names what it does not have: {missing}"


@pytest.mark.parametrize("package", ["engine", "render", "navmesh"])
def test_star_import_in_a_fresh_interpreter(package: str) -> None:
    code = (
        f"from {package} import *\n"
        f"import {package}\n"
        f"missing = [n for n in {package}.__all__ if n not in globals()]\n"
        "assert not missing, missing\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]


def test_engine_version_comes_from_the_package_metadata() -> None:
    import engine

    try:
        expected = version("rigidsim")
    except PackageNotFoundError:
        expected = "0+unknown"
    assert engine.__version__ == expected
    assert engine.__version__[0].isdigit()
