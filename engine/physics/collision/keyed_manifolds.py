"""Fresh manifolds: each step's contacts *are* the manifold, chosen by feature keys.

Box2D v3 (``b2UpdateContact``) and Jolt (``ContactConstraintManager``) rebuild every
manifold from the narrow phase each step and carry last step's impulses over to the
matching points. Every contact names the features it comes from by a *key*, unique
inside its body pair (:data:`pair_rules.RULE_SHIFT`: a box corner on a face, a clipping
candidate of two faces, a hull vertex on the stage ...). For the rows updated this step:

1. a row with more fresh points than it keeps: the supporting polygon
   (:func:`manifold_merge.select_with_corners`), points whose key a cached point has
   winning near-ties (hysteresis: a face resting on many coplanar candidates keeps the
   same four from step to step; keys are unique in a row, so this is one comparison of
   every fresh key with the row's at most four cached keys);
2. the fresh points replace the row's points (anchors in the body frames, as stored);
3. warm start as Jolt's: each fresh point, in slot order, takes the impulses ``(normal,
   tangent1, tangent2)`` of the nearest unused cached point closer than the row's feature
   length in B's frame (:func:`manifold_merge.inherit_impulses`: B's anchor names B's
   feature, a box corner, which keeps its load while it slides); a rolling point
   (``max_points == 1``, a sphere) always takes the cached point's. Matching the impulses
   by key instead (Box2D v3's ids) was measured worse: a pair's keys change when the
   reference face passes from one box to the other or the pair goes from the clipping to
   the deep-overlap rule, and the impacts of the falling columns then lost their warm
   start (``docs/physics_performance.md``);
4. a row that *holds* (the stage's rows) with fewer than three fresh points also keeps its
   cached points that no fresh point took and that still touch (the merge's rule,
   :func:`manifold_merge.still_touching`), cut to ``max_points`` by the corner slot choice
   (:func:`manifold_merge.select_with_corners`, around the first point's normal, as the
   merge's :func:`manifold_merge.reduce_points`): a hull vertex pushed past a wall's
   surface gets no fresh contact (``STAGE_BELOW_FRACTION``), and its cached point holds
   the body (without it a cone pushed against walls fell through the stage).

Against the merge (:mod:`manifold_merge`, kept for pairs with a capsule,
:mod:`manifold_rows`, and for every pair with the switch off): no drop of near points, no
distance matching for the support's ties, no refresh of cached points and no reduction of
cached and fresh points together (except in a holding row, step 4).

Reference: :func:`reference_manifolds.keyed_manifold` (one row, plain loops; tested).
"""

from __future__ import annotations

import numpy as np

from .manifold_merge import (
    SLOTS,
    FreshPoints,
    LocalPoints,
    RowFrames,
    inherit_impulses,
    masked_argmax,
    per_row,
    select_with_corners,
    still_touching,
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
    hold: np.ndarray | None = None,
) -> tuple[LocalPoints, np.ndarray]:
    """The new points of ``r`` rows and their keys ``(r, k)``, ``k <= SLOTS`` (module
    docstring).

    ``fresh``: this step's points of each row, padded (first slots valid), ``key (r, F)``
    their keys; ``frames``: the rows' body frames; ``cached``: the rows' stored points
    (their ``count`` first slots valid), ``cached_key (r, S)`` their keys; ``max_points``
    and ``feature (r,)``: each row's point capacity and feature length (m); ``hold (r,)``:
    the rows that keep untaken cached points still touching (step 4; None: no row).
    """
    data, valid = fresh.data, fresh.valid  # point_a, point_b, normal (world)
    # 1. too many points: the supporting polygon, the features of last step winning ties
    too_many = valid.sum(axis=1) > max_points
    if too_many.any():
        # known[r, j]: fresh j has the key of a valid cached point
        same = (key[:, :, None] == cached_key[:, None, :]) & cached.valid[:, None, :]
        data, valid, key = _support(
            data, valid, key, same.any(axis=2), too_many, max_points, feature
        )
    # 2. world points -> body-frame anchors R^T (p - x) and A's normal R_a^T n, one einsum
    r, width = valid.shape
    offset = np.zeros((r, 1, 3, 3))
    offset[:, 0, :2] = frames.position
    local = np.zeros((r, width, 4, 3))  # local_a, local_b, normal_local, impulse (0)
    local[:, :, :3] = np.einsum("rfji,rsfj->rsfi", frames.rotation, data - offset)
    points = LocalPoints(local, valid)
    # 3. warm start: the nearest unused cached point in B's frame (and rolling points)
    used = inherit_impulses(points, cached, max_points, feature)
    if hold is None:
        return points, key
    # 4. holding rows with fewer than three fresh points and an untaken cached point
    need = hold & (valid.sum(axis=1) < 3) & (cached.valid & ~used).any(axis=1)
    if not need.any():
        return points, key
    return _hold_cached(points, key, cached, cached_key, used, frames, need, max_points, feature)


def _hold_cached(points, key, cached, cached_key, used, frames, need, max_points, feature):
    """``points, key`` with the rows ``need`` joined by their untaken cached points still
    touching (cached first, as the merge's :func:`manifold_merge.combine`), cut to
    ``max_points`` (module docstring, step 4); every row padded to ``SLOTS`` slots."""
    rows = need.nonzero()[0]
    sub = frames.take(rows)
    held = LocalPoints(cached.data[rows], cached.valid[rows])
    keep = still_touching(held, sub, feature[rows]) & ~used[rows]
    data = np.concatenate([held.data, points.data[rows]], axis=1)
    valid = np.concatenate([keep, points.valid[rows]], axis=1)
    keys = np.concatenate([cached_key[rows], key[rows]], axis=1)
    order = (~valid).argsort(axis=1, kind="stable")  # the kept points first, in order
    data, valid, keys = per_row(data, order), per_row(valid, order), per_row(keys, order)
    over = valid.sum(axis=1) > max_points[rows]
    if over.any():  # the corner slot choice around the first point's normal
        merged = LocalPoints(data[over], valid[over])
        point_a, point_b, normal = merged.world(sub.take(over.nonzero()[0]))
        chosen = valid.copy()
        chosen[over] = select_with_corners(
            point_b,
            ((point_a - point_b) * normal).sum(axis=2),
            normal,
            normal[:, 0],
            max_points[rows][over],
            valid[over],
            band=support_band(feature[rows][over]),
        )
        order = (~chosen).argsort(axis=1, kind="stable")
        data, valid, keys = per_row(data, order), per_row(chosen, order), per_row(keys, order)
    r, width = points.valid.shape
    out = LocalPoints(np.zeros((r, SLOTS, 4, 3)), np.zeros((r, SLOTS), dtype=bool))
    out_key = np.zeros((r, SLOTS), dtype=key.dtype)
    out.data[:, :width], out.valid[:, :width], out_key[:, :width] = points.data, points.valid, key
    out.data[rows], out.valid[rows] = data[:, :SLOTS], valid[:, :SLOTS]
    out_key[rows] = keys[:, :SLOTS]
    return out, out_key


def _support(data, valid, key, known, too_many, max_points, feature):
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
        known[over],
        support_band(feature[over]),
    )
    order = (~chosen).argsort(axis=1, kind="stable")[:, :SLOTS]  # chosen first, in order
    over_key = per_row(key[over], order)
    # the other rows hold at most SLOTS points, already in their first slots
    data, valid, key = data[:, :SLOTS].copy(), valid[:, :SLOTS].copy(), key[:, :SLOTS].copy()
    data[over], valid[over], key[over] = per_row(rows, order), per_row(chosen, order), over_key
    return data, valid, key
