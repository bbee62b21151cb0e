"""The benchmark's operation counter counts exactly the NumPy operations it documents."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

from op_counter import OpCounter  # noqa: E402

pytestmark = pytest.mark.skipif(
    sys.version_info[:2] not in ((3, 11), (3, 12)), reason="reads CPython 3.11/3.12 frames"
)
HERE = (str(Path(__file__).resolve().parent),)


def tiny(a: np.ndarray, b: np.ndarray):
    """9 NumPy operations: 5 operators, 1 store, 1 subscript, 2 calls (see the comments)."""
    c = a + b  # operator 1
    c[0] = 1.0  # store 1
    d = c[1:]  # subscript 1
    n = len(c) + 1  # a builtin and an int operator: not counted
    numbers = [1, 2]
    numbers[0] = n  # a list store: not counted
    total = np.sum(d)  # call 1
    largest = c.max()  # call 2 (a method of an ndarray)
    c *= 2.0  # operator 2 (in place)
    negated = -c  # operator 3 (unary)
    mask = c > 0.5  # operator 4 (comparison)
    return total + largest, negated, mask, numbers[1]  # operator 5 (two NumPy scalars)


def outer(a: np.ndarray) -> np.ndarray:
    return tiny(a, a)[1] * 2.0  # 1 subscript of a tuple (not counted) + operator: 9 + 1


def test_counts_each_documented_operation_once():
    a, b = np.arange(4.0), np.ones(4)
    counter = OpCounter(roots=HERE)
    with counter:
        tiny(a, b)
    assert dict(counter.counts) == {"operator": 5, "store": 1, "subscript": 1, "call": 2}
    assert counter.by_function == {("test_op_counter.py", "tiny"): 9}
    assert counter.instructions > 40  # every bytecode of tiny, NumPy's or not


def test_nested_frames_count_and_runs_repeat_exactly():
    a = np.arange(4.0)
    totals = []
    for _ in range(3):
        counter = OpCounter(roots=HERE)
        with counter:
            outer(a)
        totals.append(counter.total)
    assert totals == [10, 10, 10]


def test_frames_outside_the_roots_and_outside_the_block_are_not_counted(tmp_path):
    before = sys.gettrace()
    counter = OpCounter(roots=(str(tmp_path),))
    with counter:
        tiny(np.arange(4.0), np.ones(4))
    assert sys.gettrace() is before  # the previous trace function is back
    tiny(np.arange(4.0), np.ones(4))
    assert counter.total == 0
