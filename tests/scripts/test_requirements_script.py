"""scripts/requirements.py: the requirement lines scripts/test.sh installs into the notebooks'
and habitat-lab's environments must be exactly what pyproject.toml declares (a dependency
forgotten there would make the notebooks' environment differ from ``pip install '.[notebook]'``)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: pip vendors the same parser
    from pip._vendor import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "requirements.py"


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), *args], capture_output=True, text=True, check=False
    )


def declared() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def test_core_and_notebook_extra_are_listed_once_each_in_order() -> None:
    project = declared()
    expected = list(
        dict.fromkeys(project["dependencies"] + project["optional-dependencies"]["notebook"])
    )
    result = run("notebook")
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == expected


def test_no_extra_gives_the_core_dependencies() -> None:
    assert run().stdout.splitlines() == declared()["dependencies"]


def test_extras_only_leaves_the_core_out() -> None:
    lines = run("gym", "viewer", "--extras-only").stdout.splitlines()
    extras = declared()["optional-dependencies"]
    assert lines == extras["gym"] + extras["viewer"]
    assert "numpy>=1.24" not in lines


@pytest.mark.parametrize("extra", ["bogus", "Notebook"])
def test_an_unknown_extra_is_refused_naming_it(extra: str) -> None:
    result = run(extra)
    assert result.returncode == 2
    assert extra in result.stderr and "notebook" in result.stderr
    assert result.stdout == ""
