"""A new manifold row for a body pair that first touches (both collision paths call it).

The row's point capacity: 1 when a sphere is involved (a rolling sphere touches at one
point, and old points left behind on its surface would hold it back), else
``MAX_MANIFOLD_POINTS``; its *feature length* from the two bodies' thickness
(:func:`contacts.feature_length`; the stage counts as infinitely thick); whether it may be
rebuilt from fresh points by feature keys (:mod:`keyed_manifolds`): every pair without a
capsule, the stage's included, whose rules give a whole manifold each step (box-box, the
hull rules, a hull's vertices on the stage's triangles, a rolling sphere's single point). A
capsule's contacts come from fcl, one or two points a step, and build up by the merge.
(The stage's rows merged too until the corner slot choice of the stage's contacts landed:
fresh stage manifolds then let the CI soak's cone and cube pushed against walls sink 2.8
and 5.1 cm; on the corner rules the soak passes with every row fresh, the stage's rows
holding their untaken cached points, :mod:`keyed_manifolds`, step 4;
``docs/physics_performance.md``.)
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
    unless a capsule is involved (module docstring)."""
    kinds = {s.kind for s in bodies.shapes[key[0]] + bodies.shapes[key[1]]}
    rolling = ShapeKind.SPHERE in kinds
    thickness = [math.inf if i == STAGE_ID else 2.0 * bodies.body_min_half_extent[i] for i in key]
    points = 1 if rolling else MAX_MANIFOLD_POINTS
    keyable = rolling or ShapeKind.CAPSULE not in kinds
    return store.add(key, points, feature_length(*thickness), keyable)
