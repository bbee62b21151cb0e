"""Shared tools of the bad-input tests (``test_bad_inputs_*.py``).

Every example calls one public function with a value it must refuse and asserts two things
with :func:`assert_refused`: the exception type (``ValueError`` / ``TypeError``), and an
unchanged :func:`world_hash.world_hash` (bodies, objects, template libraries, navmesh,
agents), with every body still finite. The hypothesis strategies below draw the bad values:
:func:`bad_vector` (junk, wrong lengths, non-finite components) and :func:`bad_number`
(junk, non-finite, out of range). ``BAD_INPUTS_CHECKED`` counts the examples run (printed
when a module's ``sim`` is torn down, with ``pytest -s``).
"""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from world_hash import bodies_are_finite, world_hash

EXAMPLES = settings(
    max_examples=25,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
REFUSED = (ValueError, TypeError)
BAD_INPUTS_CHECKED = {"count": 0}


def objects(sim) -> list:
    manager = sim.get_rigid_object_manager()
    return [manager.get_object_by_id(i) for i in sorted(manager._objects)]


def assert_refused(sim, call, errors=REFUSED, match: str | None = None) -> None:
    """``call()`` raises one of ``errors`` (message matching ``match``), world unchanged."""
    before = world_hash(sim)
    with pytest.raises(errors, match=match):
        call()
    assert world_hash(sim) == before
    assert bodies_are_finite(sim.get_physics_world())
    BAD_INPUTS_CHECKED["count"] += 1


# -- strategies ----------------------------------------------------------------------------------
finite = st.floats(allow_nan=False, allow_infinity=False, width=64)
non_finite = st.sampled_from([math.nan, math.inf, -math.inf])
junk = st.one_of(
    st.none(),
    st.text(max_size=4),
    st.binary(max_size=4),
    st.dictionaries(st.text(max_size=2), finite, max_size=2),
    st.just(object()),
)


def bad_vector(n: int):
    """Anything a setter of an n-vector must refuse."""
    with_non_finite = st.lists(st.one_of(finite, non_finite), min_size=n, max_size=n).filter(
        lambda v: not all(math.isfinite(x) for x in v)
    )
    return st.one_of(
        junk,
        st.lists(finite, max_size=n - 1),
        st.lists(finite, min_size=n + 1, max_size=n + 3),
        with_non_finite,
        st.lists(st.text(max_size=2), min_size=n, max_size=n),
    )


def bad_number(low: float | None = None, high: float | None = None, low_open: bool = False):
    """Non-numbers, non-finite numbers and numbers outside ``[low, high]``."""
    parts = [junk, non_finite, st.booleans()]
    if low is not None:
        below = finite.filter(lambda x: x <= low if low_open else x < low)
        parts.append(below)
    if high is not None:
        parts.append(finite.filter(lambda x: x > high))
    return st.one_of(*parts)
