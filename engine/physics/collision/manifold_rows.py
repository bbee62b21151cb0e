"""A new manifold row for a body pair that first touches (both collision paths call it).

The row's point capacity: 1 when a sphere is involved (a rolling sphere touches at one
point, and old points left behind on its surface would hold it back), else
``MAX_MANIFOLD_POINTS``; its *feature length* from the two bodies' thickness
(:func:`contacts.feature_length`; the stage counts as infinitely thick); whether it may be
rebuilt from fresh points by feature keys (:mod:`keyed_manifolds`): every pair of two
bodies without a capsule, whose rules give a whole manifold each step. A capsule's
contacts come from fcl, one or two points a step, and build up by the merge; the stage's
rows keep the merge too, whose cached points still hold a body pressed into a wall or a
corner when its vertices have passed the surface (with fresh stage manifolds the CI
soak's cone and cube pushed against walls sank 2.8 and 5.1 cm).
"""

from __future__ import annotations

import math

from ..core.bodies import STAGE_ID, Bodies
from ..core.settings import MAX_MANIFOLD_POINTS
from ..core.shapes import ShapeKind
from .contacts import ManifoldStore, feature_length


def add_manifold_row(bodies: Bodies, store: ManifoldStore, key: tuple[int, int]) -> int:
    """A new manifold row for pair ``key``: 1 point when a sphere rolls, else 4; its feature
    length from the bodies' thickness (the stage counts as infinitely thick); keyable
    unless the stage or a capsule is involved (module docstring)."""
    kinds = {s.kind for s in bodies.shapes[key[0]] + bodies.shapes[key[1]]}
    rolling = ShapeKind.SPHERE in kinds
    thickness = [math.inf if i == STAGE_ID else 2.0 * bodies.body_min_half_extent[i] for i in key]
    points = 1 if rolling else MAX_MANIFOLD_POINTS
    keyable = STAGE_ID not in key and (rolling or ShapeKind.CAPSULE not in kinds)
    return store.add(key, points, feature_length(*thickness), keyable)
