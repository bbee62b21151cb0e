"""Argument checks shared by the object API (:mod:`physics_object`, :mod:`object_properties`).

Every setter of a ``ManagedRigidObject`` validates first (ValueError/TypeError naming the
value) and only then writes the world's ``body_*`` arrays, so bad input changes nothing.
Validation includes overflow: a setter computes its candidate result (the new pose, the
velocity after an impulse, the velocity change a force makes over one fixed step), checks it
is finite (:func:`finite_result`), and only then commits it. Positions and velocity-control
targets must moreover stay within ``MAX_COORDINATE`` (the 32-bit float range Habitat keeps
them in, :func:`within_range`), so ``translate([1e308, 0, 0])`` or a velocity-control target
of 1e308 m/s is refused the first time, before anything changes, not at a later use.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np

from engine import mn

from ..core.settings import MAX_COORDINATE

__all__ = [
    "DeadObjectError",
    "angle_argument",
    "finite_result",
    "number_argument",
    "quiet_overflow",
    "within_range",
]


def number_argument(
    value: Any, name: str, low: float = -math.inf, high: float = math.inf, low_open: bool = False
) -> float:
    """``value`` as a float, if it is a finite number in ``[low, high]`` (``(low, high]`` when
    ``low_open``); else TypeError / ValueError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise TypeError(f"{name} must be a number, got {value!r}")
    number = float(value)
    if not math.isfinite(number) or number < low or number > high or (low_open and number <= low):
        bound = ">" if low_open else ">="
        raise ValueError(f"{name} must be finite, {bound} {low} and <= {high}, got {value!r}")
    return number


def quiet_overflow(method):
    """Run ``method`` with NumPy's overflow warnings off: it checks its results itself."""

    @functools.wraps(method)
    def wrapped(*args, **kwargs):
        with np.errstate(over="ignore", invalid="ignore"):
            return method(*args, **kwargs)

    return wrapped


def finite_result(value: np.ndarray, name: str, what: str) -> np.ndarray:
    """``value`` if every component is finite, else a ValueError naming the argument."""
    if not np.all(np.isfinite(value)):
        raise ValueError(
            f"{name} is too large: it would make a non-finite {what} "
            f"({np.asarray(value).tolist()}); the object is unchanged"
        )
    return value


def within_range(value: np.ndarray, name: str, what: str) -> np.ndarray:
    """``value`` if every component is finite and at most ``MAX_COORDINATE`` in magnitude,
    else a ValueError naming the argument ``name`` and the ``what`` it would make."""
    finite_result(value, name, what)
    if np.any(np.abs(value) > MAX_COORDINATE):
        raise ValueError(
            f"{name} is too large: it would make the {what} {np.asarray(value).tolist()}, "
            f"beyond +-{MAX_COORDINATE:.8g} (the 32-bit float range Habitat keeps it in); "
            f"the object is unchanged"
        )
    return value


def angle_argument(value: Any) -> float:
    """An angle (a number in radians, ``mn.Rad`` or ``mn.Deg``) as finite radians."""
    return float(
        mn.Rad(
            number_argument(float(mn.Rad(value)) if isinstance(value, mn.Deg) else value, "angle")
        )
    )


class DeadObjectError(RuntimeError):
    """Raised when a removed object (``is_alive == False``) is used."""
