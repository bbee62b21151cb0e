"""The records and input checks of the PathFinder API: path queries, obstacle hits, points.

``ShortestPath`` / ``MultiGoalShortestPath`` carry a query (start, end or ends) and receive
its answer from ``PathFinder.find_path``; ``HitRecord`` is ``closest_obstacle_surface_point``'s
answer. Field names and defaults are Habitat-sim's (``habitat_sim.nav``). ``as_point`` turns
any 3-sequence into a finite ``(3,) float64`` array or raises an exception naming the value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike


def nan3() -> np.ndarray:
    """A vector of three NaN: Habitat's answer for "no point"."""
    return np.full(3, np.nan)


@dataclass
class ShortestPath:
    """Query and result of ``PathFinder.find_path`` between two points."""

    requested_start: np.ndarray = field(default_factory=lambda: np.zeros(3))
    requested_end: np.ndarray = field(default_factory=lambda: np.zeros(3))
    points: list = field(default_factory=list)  # list of (3,) float64 waypoints
    geodesic_distance: float = math.inf  # meters, inf when no path exists


@dataclass
class MultiGoalShortestPath:
    """Query and result of ``PathFinder.find_path`` to the closest of several ends."""

    requested_start: np.ndarray = field(default_factory=lambda: np.zeros(3))
    requested_ends: list = field(default_factory=list)  # list of (3,) points
    points: list = field(default_factory=list)
    geodesic_distance: float = math.inf
    closest_end_point_index: int = -1  # index into requested_ends of the chosen end


@dataclass
class HitRecord:
    """Closest obstacle: ``hit_pos`` (3,), ``hit_normal`` (3,) unit XZ vector from the wall
    toward the query point, ``hit_dist`` meters (``max_search_radius`` when none found).
    ``HitRecord()`` is a record of no hit (zero vectors, infinite distance)."""

    hit_pos: np.ndarray = field(default_factory=lambda: np.zeros(3))
    hit_normal: np.ndarray = field(default_factory=lambda: np.zeros(3))
    hit_dist: float = math.inf


def as_point(value: ArrayLike, name: str = "point") -> np.ndarray:
    """Return ``value`` as a finite ``(3,) float64`` array or raise naming ``name``."""
    if value is None:
        raise TypeError(f"{name} must be a 3-vector, got None")
    try:
        point = np.array(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError) as err:
        raise TypeError(f"{name} must be a 3-vector of numbers, got {value!r}") from err
    if point.shape != (3,):
        raise ValueError(f"{name} must have 3 components, got shape {point.shape}")
    if not np.all(np.isfinite(point)):
        raise ValueError(f"{name} must be finite, got {point.tolist()}")
    return point
