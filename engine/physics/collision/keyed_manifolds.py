"""Feature-keyed manifolds: each step's fresh contacts *are* the manifold, warm-started by key.

Box2D v3 (``b2UpdateContact``: ``b2ManifoldPoint.id`` matched against the old manifold's
ids) and Jolt (``ContactConstraintManager``: a fresh manifold per body pair and step, last
step's impulses carried over to the matching points) rebuild every manifold from the
narrow phase each step. Every contact names the features it comes from by a *key*, unique
inside its body pair (:data:`pair_rules.RULE_SHIFT`: a box corner on a face, a clipping
candidate of two faces, a hull vertex on the stage ...), so last step's point at the same
features is found by comparing keys, not positions. For the rows updated this step:

1. warm start: a fresh point whose key equals a cached point's takes that point's
   impulses ``(normal, tangent1, tangent2)``; keys are unique in a row, so this is one
   comparison of every fresh key with the row's (at most four) cached keys. A rolling
   point (``max_points == 1``, a sphere) always takes the cached point's impulses;
2. a row with more fresh points than it keeps: the supporting polygon
   (:func:`manifold_merge.select_with_corners`), points whose key matched a cached one
   winning near-ties (hysteresis: a face resting on many coplanar candidates keeps the
   same four from step to step);
3. the fresh points replace the row's points (anchors in the body frames, as stored).

Against the merge (:mod:`manifold_merge`, kept for pairs with a capsule, whose contacts
are one or two closest points a step and build a manifold up over steps): no refresh of
cached points, no drop of near points, no distance matching with greedy loops, no
reduction of cached and fresh points together.

Reference: :func:`reference_manifolds.keyed_manifold` (one row, plain loops; tested).
"""

from __future__ import annotations

import numpy as np

from .manifold_merge import (
    SLOTS,
    FreshPoints,
    LocalPoints,
    RowFrames,
    masked_argmax,
    per_row,
    select_with_corners,
    support_band,
)


def keyed_points(
    fresh: FreshPoints,
    key: np.ndarray,
    frames: RowFrames,
    cached: LocalPoints,
    cached_key: np.ndarray,
    max_points: np.ndarray,
    feature: np.ndarray,
) -> tuple[LocalPoints, np.ndarray]:
    """The new points of ``r`` rows and their keys ``(r, k)``, ``k <= SLOTS`` (module
    docstring).

    ``fresh``: this step's points of each row, padded (first slots valid), ``key (r, F)``
    their keys; ``frames``: the rows' body frames; ``cached``: the rows' stored points
    (their ``count`` first slots valid), ``cached_key (r, S)`` their keys; ``max_points``
    and ``feature (r,)``: each row's point capacity and feature length (m).
    """
    r, width = fresh.valid.shape
    # 1. warm start by key: same[r, j, i] = fresh j has cached i's key
    same = (key[:, :, None] == cached_key[:, None, :]) & cached.valid[:, None, :]
    matched = same.any(axis=2)
    data = np.zeros((r, width, 4, 3))  # point_a, point_b, normal (world), impulse
    data[:, :, :3] = fresh.data
    data[:, :, 3] = np.where(matched[..., None], per_row(cached.impulse, same.argmax(axis=2)), 0.0)
    valid = fresh.valid
    # 2. too many points: the supporting polygon, cached keys winning near-ties
    too_many = valid.sum(axis=1) > max_points
    if too_many.any():
        data, valid, key = _support(data, valid, key, matched, too_many, max_points, feature)
    # a rolling point keeps the impulses of the cached one, whatever its key
    rolling = max_points == 1
    if rolling.any():
        data[rolling, 0, 3] = np.where(cached.valid[rolling, :1], cached.impulse[rolling, 0], 0.0)
    # 3. world points -> body-frame anchors R^T (p - x) and A's normal R_a^T n, one einsum
    offset = np.zeros((r, 1, 3, 3))
    offset[:, 0, :2] = frames.position
    data[:, :, :3] = np.einsum("rfji,rsfj->rsfi", frames.rotation, data[:, :, :3] - offset)
    return LocalPoints(data, valid), key


def _support(data, valid, key, matched, too_many, max_points, feature):
    """``data, valid, key`` of every row cut to ``SLOTS`` slots: the rows ``too_many``
    keep their supporting polygon's points (in slot order), the others their first points."""
    over = too_many.nonzero()[0]  # only these rows choose (each row on its own)
    rows = data[over]
    point_a, point_b, normal = rows[:, :, 0], rows[:, :, 1], rows[:, :, 2]
    depth = ((point_a - point_b) * normal).sum(axis=2)
    deepest = masked_argmax(depth, valid[over])
    chosen = select_with_corners(
        point_b,
        depth,
        normal,
        normal[np.arange(len(over)), deepest],
        max_points[over],
        valid[over],
        matched[over],
        support_band(feature[over]),
    )
    order = (~chosen).argsort(axis=1, kind="stable")[:, :SLOTS]  # chosen first, in order
    over_key = per_row(key[over], order)
    # the other rows hold at most SLOTS points, already in their first slots
    data, valid, key = data[:, :SLOTS].copy(), valid[:, :SLOTS].copy(), key[:, :SLOTS].copy()
    data[over], valid[over], key[over] = per_row(rows, order), per_row(chosen, order), over_key
    return data, valid, key
