"""``benchmarks/drop_gates.py``: its ``--set`` parsing and one short drop.

The settings it applies must be the ones named (typed like the field's default, a bad name
or value refused before any drop runs), and a drop must read the same gates as the
benchmark's own probe (``physics_scenes.penetration``).
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

_FILE = Path(__file__).resolve().parents[2] / "benchmarks" / "drop_gates.py"


@pytest.fixture(scope="module")
def gates():
    spec = importlib.util.spec_from_file_location("rigidsim_drop_gates", _FILE)
    module = importlib.util.module_from_spec(spec)
    sys.modules["rigidsim_drop_gates"] = module
    spec.loader.exec_module(module)
    return module


def test_settings_are_typed_like_their_defaults(gates):
    parsed = gates.parse_settings(["velocity_iterations=8", "feature_manifolds=true"])
    assert parsed == {"velocity_iterations": 8, "feature_manifolds": True}
    assert type(parsed["velocity_iterations"]) is int


@pytest.mark.parametrize("text", ["no_such_field=1", "velocity_iterations", "warm_starting=maybe"])
def test_bad_settings_are_refused_naming_them(gates, text):
    with pytest.raises(SystemExit, match=text.split("=")[0]):
        gates.parse_settings([text])


def test_a_short_drop_reads_the_gates_and_applies_its_settings(gates):
    """Ten cubes for 1.2 s: the cubes have landed, nothing is deeper than the benchmark's
    floor gate (20 mm), and a different iteration count gives a different drop."""
    default = gates.drop("plane-column-10", 0, 1.2, {})
    assert 0.0 <= default["floor"] <= 0.02 and 0.0 <= default["pair"] <= 0.05
    assert 0 <= default["asleep"] <= 10
    fewer = gates.drop("plane-column-10", 0, 1.2, {"velocity_iterations": 2})
    assert fewer != default
