"""Habitat's ``utils.profiling_utils``: named, nested time ranges around parts of a program.

Habitat pushes these ranges to NVIDIA's NVTX (seen in Nsight Systems) when the environment
variable ``HABITAT_PROFILING`` is set to anything but ``"0"``; otherwise every call is a no-op.
rigidsim has no GPU: with profiling on, each popped range logs its wall-clock duration on the
``rigidsim.default`` logger at DEBUG level (``"A/B: 1.23 ms"``, nested names joined by ``/``)::

    profiling_utils.configure(capture_start_step=2, num_steps_to_capture=5)
    for step in range(8):
        profiling_utils.on_start_step()      # opens "habitat_capture_range" at step 2 ...
        with profiling_utils.RangeContext("physics"):
            sim.step_physics(1 / 60)         # ... and closes it before step 7
"""

from __future__ import annotations

import os
import time
from contextlib import ContextDecorator
from typing import Any

from engine.logging import get_logger

__all__ = ["RangeContext", "configure", "on_start_step", "range_pop", "range_push"]

_enable_profiling = os.environ.get("HABITAT_PROFILING", "0") != "0"


class _ProfilingHelper:
    """The open ranges (name, start time) and the step-capture window."""

    def __init__(self) -> None:
        self.step_count = -1
        self.capture_start_step = -1
        self.capture_end_step = -1
        self.open_ranges: list[tuple[str, float]] = []

    @property
    def range_depth(self) -> int:
        return len(self.open_ranges)


_helper = _ProfilingHelper()


def configure(capture_start_step: int = -1, num_steps_to_capture: int = -1) -> None:
    """Capture steps ``[capture_start_step, capture_start_step + num_steps_to_capture)`` in one
    range named ``habitat_capture_range`` (-1: no capture window)."""
    if num_steps_to_capture == 0 or (capture_start_step >= 0 and num_steps_to_capture < 0):
        raise ValueError(
            f"num_steps_to_capture must be > 0 with a start step, got {num_steps_to_capture!r}"
        )
    _helper.step_count = -1
    _helper.capture_start_step = capture_start_step
    _helper.capture_end_step = (
        capture_start_step + num_steps_to_capture if capture_start_step >= 0 else -1
    )


def on_start_step() -> None:
    """Mark the start of a step: opens or closes the capture range at its bounds."""
    _helper.step_count += 1
    if _helper.step_count == _helper.capture_start_step:
        range_push("habitat_capture_range")
    elif _helper.step_count == _helper.capture_end_step:
        range_pop()


def range_push(msg: str) -> None:
    """Open a nested range named ``msg`` (no-op unless ``HABITAT_PROFILING`` is on)."""
    if _enable_profiling:
        _helper.open_ranges.append((msg, time.perf_counter()))


def range_pop() -> None:
    """Close the innermost range and log its duration (no-op unless profiling is on)."""
    if _enable_profiling and _helper.open_ranges:
        path = "/".join(name for name, _ in _helper.open_ranges)
        _, start = _helper.open_ranges.pop()
        get_logger().debug("%s: %.3f ms", path, 1e3 * (time.perf_counter() - start))


class RangeContext(ContextDecorator):
    """``with RangeContext("name"):`` or ``@RangeContext("name")``: push on entry, pop on exit."""

    def __init__(self, msg: str) -> None:
        self._msg = msg

    def __enter__(self) -> RangeContext:
        range_push(self._msg)
        return self

    def __exit__(self, *exc: Any) -> None:
        range_pop()
