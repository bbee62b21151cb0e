"""Merging fresh narrow-phase points into manifolds, one batch for all rows.

The array steps of :meth:`contacts.ManifoldStore.merge_fresh` (whose docstring gives the rules):
:class:`FreshPoints` (this step's points padded per row) and :class:`LocalPoints` (points in
the body frames), then :func:`select_fresh` (too many fresh points: the supporting polygon),
:func:`distinct_points`, :func:`to_local`, :func:`inherit_impulses` (warm starting),
:func:`combine` and :func:`reduce_points` (at most four: :func:`select_support`). Per-row
choices compare values rounded by :func:`tie_key`, so that the per-pair reference
(:func:`reference_contacts.update_manifold`) makes the same choices.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import settings
from .quaternions import cross

#: point slots per manifold row.
SLOTS = settings.MAX_MANIFOLD_POINTS


class FreshPoints:
    """Narrow-phase points padded per manifold row: ``(r, F, 3)`` arrays and ``valid (r, F)``.

    Built from flat arrays ``row_position (q,)`` (index into the rows being updated, sorted
    ascending) and ``point_a, point_b, normal (q, 3)``.
    """

    def __init__(
        self,
        n_rows: int,
        row_position: np.ndarray,
        point_a: np.ndarray,
        point_b: np.ndarray,
        normal: np.ndarray,
    ) -> None:
        counts = np.bincount(row_position, minlength=n_rows)
        width = max(int(counts.max(initial=0)), 1)
        # slot of each point inside its row: its rank among the points of the same row
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        slot = np.arange(len(row_position)) - starts[row_position]
        self.valid = np.zeros((n_rows, width), dtype=bool)
        self.valid[row_position, slot] = True
        self.point_a, self.point_b = np.zeros((n_rows, width, 3)), np.zeros((n_rows, width, 3))
        self.normal = np.zeros((n_rows, width, 3))
        self.point_a[row_position, slot] = point_a
        self.point_b[row_position, slot] = point_b
        self.normal[row_position, slot] = normal

    def depth(self) -> np.ndarray:
        return ((self.point_a - self.point_b) * self.normal).sum(axis=2)

    def take(self, index: np.ndarray, valid: np.ndarray) -> FreshPoints:
        """Points ``index (r, k)`` of every row, flagged ``valid (r, k)``."""
        out = object.__new__(FreshPoints)
        for name in ("point_a", "point_b", "normal"):
            setattr(out, name, per_row(getattr(self, name), index))
        out.valid = valid
        return out


#: the fields of :class:`LocalPoints`, in its constructor's order
LOCAL_FIELDS = ("local_a", "local_b", "normal_local", "impulse", "valid")


class LocalPoints:
    """Manifold points in the body frames, padded per row (``(r, k, 3)``, ``valid (r, k)``)."""

    def __init__(
        self,
        local_a: np.ndarray,
        local_b: np.ndarray,
        normal_local: np.ndarray,
        impulse: np.ndarray,
        valid: np.ndarray,
    ) -> None:
        self.local_a, self.local_b = local_a, local_b
        self.normal_local, self.impulse, self.valid = normal_local, impulse, valid

    def where(self, keep: np.ndarray) -> LocalPoints:
        """The points flagged by ``keep (r, k)``, moved to the front of each row (stable)."""
        if in_front(keep):  # the stable sort would be the identity: no copies
            return LocalPoints(self.local_a, self.local_b, self.normal_local, self.impulse, keep)
        order = np.argsort(~keep, axis=1, kind="stable")
        local_a, local_b, normal_local, impulse = (
            per_row(array, order)
            for array in (self.local_a, self.local_b, self.normal_local, self.impulse)
        )
        return LocalPoints(local_a, local_b, normal_local, impulse, per_row(keep, order))

    def world(self, frame_a, frame_b):
        """World anchors of A and B and world normals ``(r, k, 3)``; ``frame_x`` holds each
        row's body rotations ``(r, 3, 3)`` and positions ``(r, 3)``."""
        (ra, xa), (rb, xb) = frame_a, frame_b
        # p = R local + x for every slot: einsum over the (r, 3, 3) rotations of each row
        point_a = np.einsum("rij,rsj->rsi", ra, self.local_a) + xa[:, None]
        point_b = np.einsum("rij,rsj->rsi", rb, self.local_b) + xb[:, None]
        return point_a, point_b, np.einsum("rij,rsj->rsi", ra, self.normal_local)


def select_fresh(
    fresh: FreshPoints, cached: LocalPoints, frame_b, max_points, feature
) -> FreshPoints:
    """Rows with more fresh points than they may keep: the supporting polygon only.

    Among near-ties the points matching cached ones win (hysteresis), so a flat face
    resting on many coplanar vertices keeps the same four points from step to step.
    """
    too_many = fresh.valid.sum(axis=1) > max_points
    if not too_many.any():  # every row keeps all its points, already first in their rows
        return fresh
    over = np.flatnonzero(too_many)  # only these rows choose (each row on its own)
    rb, xb = frame_b[0][over], frame_b[1][over]
    point_b, valid, count = fresh.point_b[over], fresh.valid[over], max_points[over]
    depth = ((fresh.point_a[over] - point_b) * fresh.normal[over]).sum(axis=2)
    # fresh anchors in B's frame R^T (p - x), compared with every cached anchor
    local_b = np.einsum("rji,rsj->rsi", rb, point_b - xb[:, None])
    gap_sq = ((local_b[:, :, None] - cached.local_b[over][:, None]) ** 2).sum(axis=3)
    gap_sq = np.where(cached.valid[over][:, None, :], gap_sq, np.inf)
    preferred = gap_sq.min(axis=2) < feature[over, None] ** 2
    deepest = masked_argmax(depth, valid)
    normal = fresh.normal[over][np.arange(len(over)), deepest]
    chosen = select_support(
        point_b, depth, normal, count, valid, preferred, support_band(feature[over])
    )
    order = np.argsort(~chosen, axis=1, kind="stable")[:, :SLOTS]  # chosen first, in order
    # the other rows keep all their points, already in their first SLOTS slots
    out = object.__new__(FreshPoints)
    for name in ("point_a", "point_b", "normal", "valid"):
        kept = getattr(fresh, name)[:, :SLOTS].copy()
        kept[over] = per_row(chosen if name == "valid" else getattr(fresh, name)[over], order)
        setattr(out, name, kept)
    return out


def distinct_points(points: FreshPoints, radius: np.ndarray) -> FreshPoints:
    """Each row's points, deepest first, dropping any within ``radius (r,)`` of a kept one."""
    depth = np.where(points.valid, points.depth(), -np.inf)
    by_depth = np.argsort(-tie_key(depth), axis=1, kind="stable")
    points = points.take(by_depth, per_row(points.valid, by_depth))
    # |p_i - p_j|^2 between the (at most four) points of each row, in B's world anchors
    dist_sq = ((points.point_b[:, :, None] - points.point_b[:, None]) ** 2).sum(axis=3)
    kept = np.zeros_like(points.valid)
    for k in range(points.valid.shape[1]):  # greedy, deepest first: k sees the kept j < k
        near_kept = (kept & (dist_sq[:, k] < (radius * radius)[:, None])).any(axis=1)
        kept[:, k] = points.valid[:, k] & ~near_kept
    if in_front(kept):  # nothing dropped (or only the last points): already in order
        points.valid = kept
        return points
    order = np.argsort(~kept, axis=1, kind="stable")
    return points.take(order, per_row(kept, order))


def to_local(points: FreshPoints, frame_a, frame_b) -> LocalPoints:
    """Fresh world points -> body-frame anchors ``R^T (p - x)``, normals in A's frame."""
    (ra, xa), (rb, xb) = frame_a, frame_b
    local_a = np.einsum("rji,rsj->rsi", ra, points.point_a - xa[:, None])
    local_b = np.einsum("rji,rsj->rsi", rb, points.point_b - xb[:, None])
    normal = np.einsum("rji,rsj->rsi", ra, points.normal)
    return LocalPoints(local_a, local_b, normal, np.zeros(local_a.shape), points.valid)


def inherit_impulses(fresh: LocalPoints, cached: LocalPoints, max_points, feature) -> np.ndarray:
    """Give matched fresh points their cached impulses; returns the used cached slots.

    Greedy one-to-one matching, deepest fresh point first: each takes the nearest unused
    cached point (in B's frame) closer than the row's feature length. A single rolling
    point (``max_points == 1``) always keeps the impulse of the cached one.
    """
    rows = np.arange(len(max_points))
    used = np.zeros_like(cached.valid)
    limit = feature**2
    # |cached_i - fresh_j|^2 in B's frame, (r, fresh j, cached i)
    dist_sq = ((fresh.local_b[:, :, None] - cached.local_b[:, None]) ** 2).sum(axis=3)
    for j in range(fresh.valid.shape[1]):
        candidates = np.where(cached.valid & ~used, dist_sq[:, j], np.inf)
        nearest = candidates.argmin(axis=1)
        matched = fresh.valid[:, j] & (candidates[rows, nearest] < limit)
        fresh.impulse[matched, j] = cached.impulse[matched, nearest[matched]]
        used[matched, nearest[matched]] = True
    rolling = max_points == 1
    if rolling.any():
        fresh.impulse[rolling] = np.where(
            cached.valid[rolling, :1, None], cached.impulse[rolling, :1], 0.0
        )
        used[rolling] = cached.valid[rolling]
    return used


def combine(fresh: LocalPoints, cached: LocalPoints, used: np.ndarray) -> LocalPoints:
    """Three or more fresh points replace a row's cache; fewer join its unused points."""
    replace = fresh.valid.sum(axis=1) >= 3
    keep_cached = cached.valid & ~used & ~replace[:, None]
    joined = [
        np.concatenate([getattr(cached, name), getattr(fresh, name)], axis=1)
        for name in ("local_a", "local_b", "normal_local", "impulse")
    ]
    valid = np.concatenate([keep_cached, fresh.valid], axis=1)
    local_a, local_b, normal_local, impulse = joined
    return LocalPoints(local_a, local_b, normal_local, impulse, valid).where(valid)


def support_band(feature: np.ndarray) -> np.ndarray:
    """(r,) m, the support depth band of each row: ``SUPPORT_DEPTH_BAND`` capped at ``f``."""
    return np.minimum(settings.SUPPORT_DEPTH_BAND, feature)


def feature_length(thickness_a: float, thickness_b: float) -> float:
    """m, a pair's feature length: ``FEATURE_LENGTH_FRACTION`` (a quarter) of the thinner
    body's smallest dimension, at most ``CONTACT_MATCH_DISTANCE`` (pass ``inf`` for the
    stage)."""
    return min(
        settings.CONTACT_MATCH_DISTANCE,
        settings.FEATURE_LENGTH_FRACTION * min(thickness_a, thickness_b),
    )


def reduce_points(points: LocalPoints, frame_a, frame_b, max_points, feature) -> LocalPoints:
    """Rows holding more than ``max_points``: keep the supporting polygon's points."""
    over = np.flatnonzero(points.valid.sum(axis=1) > max_points)
    if len(over) == 0:
        return points
    # only the rows over their limit choose (each row on its own)
    rows = LocalPoints(*(getattr(points, name)[over] for name in LOCAL_FIELDS))
    frames = [(frame[0][over], frame[1][over]) for frame in (frame_a, frame_b)]
    point_a, point_b, normal = rows.world(*frames)
    depth = ((point_a - point_b) * normal).sum(axis=2)
    chosen = points.valid.copy()
    chosen[over] = select_support(
        point_b, depth, normal[:, 0], max_points[over], rows.valid, band=support_band(feature[over])
    )
    return points.where(chosen)


def in_front(flags: np.ndarray) -> bool:
    """True when every row of ``flags (r, k)`` holds its True values before its False ones
    (a stable sort of ``~flags`` per row would change nothing)."""
    return not (flags[:, 1:] & ~flags[:, :-1]).any()


def per_row(array: np.ndarray, index: np.ndarray) -> np.ndarray:
    """``array[r, index[r, k]]`` for every row r: reorders ``(r, k, ...)`` slots per row."""
    return array[np.arange(len(index))[:, None], index]


def tie_key(values: Any) -> Any:
    """``values`` rounded to multiples of ``TIE_QUANTUM``: equal keys are ties."""
    return np.round(values / settings.TIE_QUANTUM)


def masked_argmax(values: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """Per row, the first slot holding the largest valid value (0 for empty rows)."""
    return np.where(valid, tie_key(values), -np.inf).argmax(axis=1)


def select_support(
    points: np.ndarray,
    depth: np.ndarray,
    normal: np.ndarray,
    count: np.ndarray,
    valid: np.ndarray,
    preferred: np.ndarray | None = None,
    band: np.ndarray | None = None,
) -> np.ndarray:
    """(r, k) bool: per row, up to ``count`` points spanning the largest supporting area.

    Reference: :func:`reference_contacts.select_support` (one row).

    Parameters
    ----------
    points : (r, k, 3) world points, depth : (r, k) m, normal : (r, 3) unit.
    count : (r,) int, how many to keep. valid : (r, k) bool, slots holding points.
    preferred : (r, k) bool, points matching cached ones; they win near-ties (1 mm of depth,
        10 % of distance or area).
    band : (r,) m, the depth band of supporting points (``SUPPORT_DEPTH_BAND`` if None).

    Supporting points lie within ``SUPPORT_DEPTH_BAND`` of the row's deepest point. Among
    them: the deepest, the farthest from it, the one spanning the largest triangle with
    those two, then the largest on the other side of that edge. Slots left over take the
    remaining (speculative) points, deepest first.
    """
    rows = np.arange(len(count))
    deepest_depth = np.where(valid, depth, -np.inf).max(axis=1, initial=-np.inf)
    band = np.full(len(count), settings.SUPPORT_DEPTH_BAND) if band is None else band
    supporting = valid & (depth >= deepest_depth[:, None] - band[:, None])
    bonus = np.zeros(depth.shape) if preferred is None else preferred.astype(np.float64)
    scale = 1.0 + settings.PREFERRED_SIZE_BONUS * bonus
    chosen = np.zeros_like(valid)
    first = masked_argmax(depth + settings.PREFERRED_DEPTH_BONUS * bonus, supporting)
    chosen[rows, first] = valid[rows, first]
    p0 = points[rows, first]
    far = ((points - p0[:, None]) ** 2).sum(axis=2) * scale  # |p - p0|^2
    second = masked_argmax(far, supporting)
    chosen[rows, second] |= (count >= 2) & valid[rows, second]
    edge = points[rows, second] - p0
    # signed area of triangle (p0, p1, p) about the normal: ((p1 - p0) x (p - p0)) . n / 2
    area = (cross(edge[:, None], points - p0[:, None]) * normal[:, None]).sum(axis=2) * scale
    third = masked_argmax(np.abs(area), supporting)
    chosen[rows, third] |= (count >= 3) & valid[rows, third]
    # the fourth point lies on the other side of edge p0-p1 with the largest area
    opposite = np.where(supporting & ~chosen, -np.sign(area[rows, third])[:, None] * area, -np.inf)
    fourth = tie_key(opposite).argmax(axis=1)
    chosen[rows, fourth] |= (count >= 4) & np.isfinite(opposite[rows, fourth])
    # fill the slots left over with the deepest remaining points
    remaining = count - chosen.sum(axis=1)
    rest = np.where(valid & ~chosen, depth, -np.inf)
    rank = np.argsort(-tie_key(rest), axis=1, kind="stable")
    take = (np.arange(depth.shape[1]) < remaining[:, None]) & np.isfinite(per_row(rest, rank))
    chosen[np.arange(len(rank))[:, None], rank] |= take
    return chosen
