"""Merging fresh narrow-phase points into manifolds, one batch for all rows.

The array steps of :meth:`contacts.ManifoldStore.merge_fresh` (whose docstring gives the rules):
:class:`FreshPoints` (this step's points padded per row) and :class:`LocalPoints` (points in
the body frames), then :func:`select_fresh` (too many fresh points: the supporting polygon),
:func:`distinct_points`, :func:`to_local`, :func:`inherit_impulses` (warm starting),
:func:`combine` and :func:`reduce_points` (at most four). Which points a row keeps is the
slot choice of :mod:`slot_choice` (:func:`slot_choice.select_with_corners`,
:func:`slot_choice.select_support`; its names are importable from here too). Per-row
choices compare values rounded by :func:`slot_choice.tie_key`, so that the per-pair
reference (:func:`reference_manifolds.update_manifold`) makes the same choices.

Call counts: the merge runs every step on arrays of a few hundred numbers, so its cost is
the number of NumPy calls, not the arithmetic. A point's fields therefore live in one array
(:class:`FreshPoints`, :class:`LocalPoints`; the field names are views), the body frames of a
row in one array (:class:`RowFrames`), and the greedy loops run only where a choice depends
on an earlier one (:func:`distinct_points`, :func:`inherit_impulses`). Method forms
(``x.argsort()``, ``x.nonzero()[0]``) replace ``np.argsort`` and ``np.flatnonzero``: the same
C function without several Python wrapper calls each.
"""

from __future__ import annotations

import numpy as np

from ..core import settings

# the slot choice; corner_points and select_support stay importable from here
from .slot_choice import corner_points as corner_points
from .slot_choice import masked_argmax, per_row, select_with_corners, support_band, tie_key
from .slot_choice import select_support as select_support

#: point slots per manifold row.
SLOTS = settings.MAX_MANIFOLD_POINTS


class FreshPoints:
    """Narrow-phase points padded per manifold row: ``data (r, F, 3, 3)`` holds each slot's
    ``point_a, point_b, normal`` (one array, so reordering a row's points is one NumPy call
    for all three; the names are views of it), ``valid (r, F)``.

    Built from flat arrays ``row_position (q,)`` (index into the rows being updated, sorted
    ascending) and ``point_a, point_b, normal (q, 3)``; ``key (q,)``, the points' feature
    keys (:mod:`keyed_manifolds`), padded the same way into ``key (r, F)`` (0 if None).
    """

    point_a = property(lambda self: self.data[:, :, 0])
    point_b = property(lambda self: self.data[:, :, 1])
    normal = property(lambda self: self.data[:, :, 2])

    def __init__(
        self,
        n_rows: int,
        row_position: np.ndarray,
        point_a: np.ndarray,
        point_b: np.ndarray,
        normal: np.ndarray,
        key: np.ndarray | None = None,
    ) -> None:
        counts = np.bincount(row_position, minlength=n_rows)
        width = max(int(counts.max(initial=0)), 1)
        # slot of each point inside its row: its rank among the points of the same row
        # (row_position is sorted: a row's points start at the points of the rows before it)
        starts = np.cumsum(counts) - counts
        slot = np.arange(len(row_position)) - starts[row_position]
        self.valid = np.arange(width) < counts[:, None]  # a row's points fill its first slots
        self.data = np.zeros((n_rows, width, 3, 3))
        for field, value in enumerate((point_a, point_b, normal)):
            self.data[row_position, slot, field] = value
        self.key = np.zeros((n_rows, width), dtype=np.int64)
        if key is not None:
            self.key[row_position, slot] = key

    def depth(self) -> np.ndarray:
        return ((self.point_a - self.point_b) * self.normal).sum(axis=2)

    def take(self, index: np.ndarray, valid: np.ndarray) -> FreshPoints:
        """Points ``index (r, k)`` of every row, flagged ``valid (r, k)`` (keys dropped)."""
        return FreshPoints.of(per_row(self.data, index), valid)

    def rows(self, mask: np.ndarray) -> FreshPoints:
        """The rows flagged by ``mask (r,)``, with their keys, padded to their own longest
        row (the merge reads a width above ``SLOTS`` as a row with too many points)."""
        valid = self.valid[mask]
        width = max(int(valid.sum(axis=1).max(initial=0)), 1)
        out = FreshPoints.of(self.data[mask, :width], valid[:, :width])
        out.key = self.key[mask, :width]
        return out

    @staticmethod
    def of(data: np.ndarray, valid: np.ndarray) -> FreshPoints:
        """Fresh points from their ``data (r, k, 3, 3)`` and ``valid (r, k)`` arrays."""
        out = object.__new__(FreshPoints)
        out.data, out.valid = data, valid
        return out


class RowFrames:
    """The body frames of each manifold row, in the order of a point's fields:
    ``rotation (r, 3, 3, 3)`` holds ``R_a, R_b, R_a`` (the frames of anchor A, anchor B and
    the normal) and ``position (r, 2, 3)`` holds ``x_a, x_b`` (a normal has no offset).
    One array for the three frames lets one einsum move all of a point's fields."""

    def __init__(self, rotation: np.ndarray, position: np.ndarray) -> None:
        self.rotation, self.position = rotation, position

    @staticmethod
    def of_pairs(pairs: np.ndarray, rotation: np.ndarray, position: np.ndarray) -> RowFrames:
        """Frames of body pairs ``pairs (r, 2)`` from all bodies' ``rotation (n, 3, 3)`` and
        ``position (n, 3)``."""
        return RowFrames(rotation[pairs[:, [0, 1, 0]]], position[pairs])

    def take(self, rows: np.ndarray) -> RowFrames:
        return RowFrames(self.rotation[rows], self.position[rows])

    @property
    def b(self) -> tuple[np.ndarray, np.ndarray]:
        """B's rotations ``(r, 3, 3)`` and positions ``(r, 3)``."""
        return self.rotation[:, 1], self.position[:, 1]


#: ``EARLIER[i, j]``: slot j comes before slot i (a strictly lower triangle)
EARLIER = np.tri(SLOTS, SLOTS, -1, dtype=bool)

#: the fields of a manifold point, in the order of the last-but-one axis of its data
POINT_FIELDS = ("local_a", "local_b", "normal_local", "impulse")


class LocalPoints:
    """Manifold points in the body frames, padded per row: ``data (r, k, 4, 3)`` holds each
    slot's ``local_a, local_b, normal_local, impulse`` (:data:`POINT_FIELDS`; one array, so a
    gather, a reorder or a store write is one NumPy call for all four; the names are views
    of it), ``valid (r, k)``."""

    local_a = property(lambda self: self.data[:, :, 0])
    local_b = property(lambda self: self.data[:, :, 1])
    normal_local = property(lambda self: self.data[:, :, 2])
    impulse = property(lambda self: self.data[:, :, 3])

    def __init__(self, data: np.ndarray, valid: np.ndarray) -> None:
        self.data, self.valid = data, valid

    def where(self, keep: np.ndarray) -> LocalPoints:
        """The points flagged by ``keep (r, k)``, moved to the front of each row (stable)."""
        if in_front(keep):  # the stable sort would be the identity: no copies
            return LocalPoints(self.data, keep)
        order = (~keep).argsort(axis=1, kind="stable")
        return LocalPoints(per_row(self.data, order), per_row(keep, order))

    def world(self, frames: RowFrames):
        """World anchors of A and B and world normals ``(r, k, 3)`` (views of one array)."""
        # p = R local + x for every slot and field: one einsum over each row's three frames
        # (R_a local_a, R_b local_b, R_a normal_local), then the anchors' offsets x_a, x_b
        world = np.einsum("rfij,rsfj->rsfi", frames.rotation, self.data[:, :, :3])
        world[:, :, :2] += frames.position[:, None]
        return world[:, :, 0], world[:, :, 1], world[:, :, 2]


def select_fresh(
    fresh: FreshPoints, cached: LocalPoints, frames: RowFrames, max_points, feature
) -> FreshPoints:
    """Rows with more fresh points than they may keep: the supporting polygon only.

    Among near-ties the points matching cached ones win (hysteresis), so a flat face
    resting on many coplanar vertices keeps the same four points from step to step.
    """
    too_many = fresh.valid.sum(axis=1) > max_points
    if not too_many.any():  # every row keeps all its points, already first in their rows
        return fresh
    over = too_many.nonzero()[0]  # only these rows choose (each row on its own)
    rb, xb = frames.rotation[over, 1], frames.position[over, 1]
    data, valid, count = fresh.data[over], fresh.valid[over], max_points[over]
    point_a, point_b, normal = data[:, :, 0], data[:, :, 1], data[:, :, 2]
    depth = ((point_a - point_b) * normal).sum(axis=2)
    # fresh anchors in B's frame R^T (p - x), compared with every cached anchor
    local_b = np.einsum("rji,rsj->rsi", rb, point_b - xb[:, None])
    gap_sq = ((local_b[:, :, None] - cached.local_b[over][:, None]) ** 2).sum(axis=3)
    gap_sq = np.where(cached.valid[over][:, None, :], gap_sq, np.inf)
    preferred = gap_sq.min(axis=2) < feature[over, None] ** 2
    deepest = masked_argmax(depth, valid)
    chosen = select_with_corners(
        point_b,
        depth,
        normal,
        normal[np.arange(len(over)), deepest],
        count,
        valid,
        preferred,
        support_band(feature[over]),
    )
    order = (~chosen).argsort(axis=1, kind="stable")[:, :SLOTS]  # chosen first, in order
    # the other rows keep all their points, already in their first SLOTS slots
    kept = FreshPoints.of(fresh.data[:, :SLOTS].copy(), fresh.valid[:, :SLOTS].copy())
    kept.data[over], kept.valid[over] = per_row(data, order), per_row(chosen, order)
    return kept


def distinct_points(points: FreshPoints, radius: np.ndarray) -> FreshPoints:
    """Each row's points, deepest first, dropping any within ``radius (r,)`` of a kept one
    pushing the same way (normals less than about 45 degrees apart, ``n_i . n_j >=
    STAGE_CORNER_COSINE``): a vertex in a corner holds a wall and a floor contact at one
    point, two constraints, and dropping the shallower floor one let a cone's tip struck
    into a wall sink 4 cm below the floor."""
    depth = np.where(points.valid, points.depth(), -np.inf)
    by_depth = (-tie_key(depth)).argsort(axis=1, kind="stable")
    points = points.take(by_depth, per_row(points.valid, by_depth))
    # |p_i - p_j|^2 between the (at most four) points of each row, in B's world anchors
    dist_sq = ((points.point_b[:, :, None] - points.point_b[:, None]) ** 2).sum(axis=3)
    k = points.valid.shape[1]  # at most SLOTS (select_fresh keeps no more)
    # near[r, i, j]: row r's valid point j comes before i (is deeper) and lies within radius
    near = (dist_sq < (radius * radius)[:, None, None]) & points.valid[:, None, :]
    near &= (points.normal[:, :, None] * points.normal[:, None]).sum(axis=3) >= (
        settings.STAGE_CORNER_COSINE
    )
    near &= EARLIER[:k, :k]
    # greedy, deepest first: point i is kept unless a kept point before it is near. Only
    # the slots i with a near point in some row need the loop (in slot order, so every
    # kept[:, j < i] is final when i is decided); the others keep their valid flag
    kept = points.valid.copy()
    for i in near.any(axis=(0, 2)).nonzero()[0].tolist():
        kept[:, i] &= ~(kept & near[:, i]).any(axis=1)
    if in_front(kept):  # nothing dropped (or only the last points): already in order
        points.valid = kept
        return points
    order = (~kept).argsort(axis=1, kind="stable")
    return points.take(order, per_row(kept, order))


def to_local(points: FreshPoints, frames: RowFrames) -> LocalPoints:
    """Fresh world points -> body-frame anchors ``R^T (p - x)``, normals ``R_a^T n`` (no
    offset: its x is 0), all three in one einsum; impulses 0."""
    r, k = points.valid.shape
    offset = np.zeros((r, 1, 3, 3))  # x_a, x_b, 0 per row
    offset[:, 0, :2] = frames.position
    data = np.zeros((r, k, 4, 3))  # the impulse field stays 0
    data[:, :, :3] = np.einsum("rfji,rsfj->rsfi", frames.rotation, points.data - offset)
    return LocalPoints(data, points.valid)


def inherit_impulses(fresh: LocalPoints, cached: LocalPoints, max_points, feature) -> np.ndarray:
    """Give matched fresh points their cached impulses; returns the used cached slots.

    Greedy one-to-one matching, deepest fresh point first: each takes the nearest unused
    cached point (in B's frame) closer than the row's feature length. A single rolling
    point (``max_points == 1``) always keeps the impulse of the cached one.
    """
    # |cached_i - fresh_j|^2 in B's frame, (r, fresh j, cached i); inf for empty cached slots
    dist_sq = ((fresh.local_b[:, :, None] - cached.local_b[:, None]) ** 2).sum(axis=3)
    dist_sq = np.where(cached.valid[:, None, :], dist_sq, np.inf)
    within = (dist_sq < (feature**2)[:, None, None]) & fresh.valid[:, :, None]
    if (within.sum(axis=1) <= 1).all():
        used = _match_without_conflicts(fresh, cached, dist_sq, within)
    else:
        used = _match_greedily(fresh, cached, dist_sq, feature**2)
    rolling = max_points == 1
    if rolling.any():
        fresh.impulse[rolling] = np.where(
            cached.valid[rolling, :1, None], cached.impulse[rolling, :1], 0.0
        )
        used[rolling] = cached.valid[rolling]
    return used


def _match_greedily(fresh: LocalPoints, cached: LocalPoints, dist_sq, limit) -> np.ndarray:
    """The greedy matching, one fresh slot j at a time (each row on its own)."""
    rows = np.arange(len(limit))
    used = np.zeros_like(cached.valid)
    for j in range(fresh.valid.shape[1]):
        candidates = np.where(used, np.inf, dist_sq[:, j])
        nearest = candidates.argmin(axis=1)
        matched = fresh.valid[:, j] & (candidates[rows, nearest] < limit)
        fresh.impulse[matched, j] = cached.impulse[matched, nearest[matched]]
        used[matched, nearest[matched]] = True
    return used


def _match_without_conflicts(fresh: LocalPoints, cached: LocalPoints, dist_sq, within):
    """The greedy matching when no cached point is within reach of two fresh points
    (``within (r, j, i)``: cached i closer than the feature length to valid fresh j): no
    point can then take another's match, so every fresh point takes its nearest cached
    point at once (the same first-of-equals choice as one greedy step)."""
    nearest = dist_sq.argmin(axis=2)  # (r, j)
    matched = within.any(axis=2)  # the nearest is within reach
    fresh.impulse[...] = np.where(matched[..., None], per_row(cached.impulse, nearest), 0.0)
    slots = np.arange(cached.valid.shape[1])
    return ((nearest[:, :, None] == slots) & matched[:, :, None]).any(axis=1)


def combine(fresh: LocalPoints, cached: LocalPoints, used: np.ndarray) -> LocalPoints:
    """Three or more fresh points replace a row's cache; fewer join its unused points."""
    replace = fresh.valid.sum(axis=1) >= 3
    keep_cached = cached.valid & ~used & ~replace[:, None]
    data = np.concatenate([cached.data, fresh.data], axis=1)
    valid = np.concatenate([keep_cached, fresh.valid], axis=1)
    return LocalPoints(data, valid).where(valid)


def still_touching(cached: LocalPoints, frames: RowFrames, feature) -> np.ndarray:
    """(r, k) bool: the valid ``cached`` points whose bodies separated less than
    ``CONTACT_BREAKING_DISTANCE`` along the normal and whose anchors drifted apart less
    than ``CONTACT_DRIFT_DISTANCE`` (capped at ``feature (r,)``) tangentially."""
    point_a, point_b, normal = cached.world(frames)
    gap = point_a - point_b
    depth = (gap * normal).sum(axis=2)  # d = (p_a - p_b) . n
    drift_sq = (gap * gap).sum(axis=2) - depth**2  # |tangential part of the gap|^2
    drift_limit = np.minimum(settings.CONTACT_DRIFT_DISTANCE, feature)[:, None] ** 2
    return cached.valid & (depth > -settings.CONTACT_BREAKING_DISTANCE) & (drift_sq < drift_limit)


def feature_length(thickness_a: float, thickness_b: float) -> float:
    """m, a pair's feature length: ``FEATURE_LENGTH_FRACTION`` (a quarter) of the thinner
    body's smallest dimension, at most ``CONTACT_MATCH_DISTANCE`` (pass ``inf`` for the
    stage)."""
    return min(
        settings.CONTACT_MATCH_DISTANCE,
        settings.FEATURE_LENGTH_FRACTION * min(thickness_a, thickness_b),
    )


def reduce_points(points: LocalPoints, frames: RowFrames, max_points, feature) -> LocalPoints:
    """Rows holding more than ``max_points``: keep the supporting polygon's points."""
    over = (points.valid.sum(axis=1) > max_points).nonzero()[0]
    if len(over) == 0:
        return points
    # only the rows over their limit choose (each row on its own)
    rows = LocalPoints(points.data[over], points.valid[over])
    point_a, point_b, normal = rows.world(frames.take(over))
    depth = ((point_a - point_b) * normal).sum(axis=2)
    chosen = points.valid.copy()
    chosen[over] = select_with_corners(
        point_b,
        depth,
        normal,
        normal[:, 0],
        max_points[over],
        rows.valid,
        band=support_band(feature[over]),
    )
    return points.where(chosen)


def in_front(flags: np.ndarray) -> bool:
    """True when every row of ``flags (r, k)`` holds its True values before its False ones
    (a stable sort of ``~flags`` per row would change nothing)."""
    return not (flags[:, 1:] & ~flags[:, :-1]).any()
