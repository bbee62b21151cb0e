"""A new manifold row for a body pair that first touches (both collision paths call it).

The row's point capacity: 1 when a sphere is involved (a rolling sphere touches at one
point, and old points left behind on its surface would hold it back), else
``MAX_MANIFOLD_POINTS``; its *feature length* from the two bodies' thickness
(:func:`contacts.feature_length`; the stage counts as infinitely thick).
"""

from __future__ import annotations

import math

from ..core.bodies import STAGE_ID, Bodies
from ..core.settings import MAX_MANIFOLD_POINTS
from ..core.shapes import ShapeKind
from .contacts import ManifoldStore, feature_length


def add_manifold_row(bodies: Bodies, store: ManifoldStore, key: tuple[int, int]) -> int:
    """A new manifold row for pair ``key``: 1 point when a sphere rolls, else 4; its feature
    length from the bodies' thickness (the stage counts as infinitely thick)."""
    shapes = bodies.shapes[key[0]] + bodies.shapes[key[1]]
    rolling = any(s.kind == ShapeKind.SPHERE for s in shapes)
    thickness = [math.inf if i == STAGE_ID else 2.0 * bodies.body_min_half_extent[i] for i in key]
    return store.add(key, 1 if rolling else MAX_MANIFOLD_POINTS, feature_length(*thickness))
