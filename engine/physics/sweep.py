"""CCD-lite: sweep fast bodies against non-dynamic geometry so they cannot tunnel.

A body that moved more than ``CCD_MOTION_FRACTION`` of its smallest half extent ``r`` in one
step casts a ray from its old center along the motion against the stage, static and
kinematic bodies. If the ray hits at distance ``s`` before the body's travel ``L`` plus
``r``, the body is put back to ``old + (s - r + CCD_PENETRATION) u`` (u = motion direction):
just touching the wall, a hair inside it, so next step's narrow phase sees the contact and
the solver bounces it. This is conservative for spheres (exact when hitting face-on) and a
good approximation for compact bodies; velocities are left to the contact solver.
"""

from __future__ import annotations

import numpy as np

from . import settings
from .bodies import DYNAMIC, Bodies
from .queries import cast_ray_bodies


def sweep_fast_bodies(bodies: Bodies, moving: np.ndarray, old_position: np.ndarray) -> None:
    """Pull back bodies in ``moving (k,)`` that passed through static geometry this step;
    ``old_position (k, 3)`` are their centers before the step."""
    b = bodies
    if len(moving) == 0:
        return
    travel = b.body_position[moving] - old_position
    length = np.linalg.norm(travel, axis=1)
    radius = b.body_min_half_extent[moving]
    fast = length > settings.CCD_MOTION_FRACTION * np.maximum(radius, 1e-6)
    if not np.any(fast):
        return
    n = b.count
    obstacle = b.body_alive[:n] & b.body_collidable[:n] & (b.body_motion_type[:n] != DYNAMIC)
    for k in np.nonzero(fast)[0]:
        index = moving[k]
        direction = travel[k] / length[k]
        reach = length[k] + radius[k]
        start = old_position[k]
        lo = np.minimum(start, start + direction * reach) - radius[k]
        hi = np.maximum(start, start + direction * reach) + radius[k]
        near = obstacle & np.all((b.body_aabb_min[:n] <= hi) & (b.body_aabb_max[:n] >= lo), axis=1)
        hits = cast_ray_bodies(b, np.nonzero(near)[0], start, direction, reach)
        if not hits:
            continue
        allowed = max(hits[0][0] - radius[k] + settings.CCD_PENETRATION, 0.0)
        if allowed < length[k]:
            b.body_position[index] = start + direction * allowed
