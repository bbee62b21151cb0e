"""Persistent contact manifolds: up to four points per body pair, kept across steps.

Every manifold point stores its two anchors in the body frames (``local_a``, ``local_b``),
its normal in A's frame, and the impulses accumulated by the solver ``(normal, tangent1,
tangent2)`` in N s. :class:`ManifoldStore` keeps all manifolds of the world in padded
arrays, one row per body pair and ``S = 4`` point slots per row, so every step updates all
of them with one batch of NumPy operations (Bullet's ``btPersistentManifold`` idea):

1. refresh: recompute the world anchors; drop points whose bodies separated more than
   ``CONTACT_BREAKING_DISTANCE`` along the normal or slid apart more than
   ``CONTACT_DRIFT_DISTANCE`` tangentially;
2. merge: too many fresh points are cut to the supporting polygon (:func:`select_support`);
   fresh points closer than ``CONTACT_MATCH_DISTANCE`` to a kept one are dropped (deepest
   wins); a fresh point within ``CONTACT_MATCH_DISTANCE`` of a cached one inherits its
   impulses (this is what makes warm starting work). Three or more fresh points replace the
   cache; fewer are added to it (GJK gives one point per step, so a manifold builds up);
3. reduce to four: the deepest point, the point farthest from it, then the points that
   maximize the contact polygon's area (largest support area = most stable resting).

Small bodies: every row has a *feature length* ``f`` (:func:`feature_length`), a quarter of
the thinnest body's smallest dimension, at most ``CONTACT_MATCH_DISTANCE``. The match, drift
and support-band distances above are capped at ``f``, so the corners of a 1 cm cube stay
four distinct points instead of merging into one (a 2 cm match radius would swallow the
whole cube, leaving one corner point that tips it over and through the floor).

Normals point from body A to body B; depth ``(p_a - p_b) . n`` is positive when overlapping.
Padded arrays: a row's first ``count`` slots hold its points, in no particular order; the
other slots are zero. Per-row choices ("the deepest point of each row") are masked
``argmax`` over the slot axis. Choices compare values rounded to ``TIE_QUANTUM``
(:func:`tie_key`): symmetric bodies (a cylinder on its side) have exact ties, and the first
slot must win them whatever the rounding of the arithmetic before, so that the per-pair
reference path (:func:`reference_contacts.update_manifold`) makes the same choices.
"""

from __future__ import annotations

from collections.abc import Iterator, MutableMapping
from typing import Any

import numpy as np

from . import settings
from .quaternions import cross

#: point slots per manifold row.
SLOTS = settings.MAX_MANIFOLD_POINTS


class ManifoldView:
    """One body pair's manifold, read from the store (``len`` = its number of points)."""

    def __init__(self, store: ManifoldStore, row: int) -> None:
        self._store, self.row = store, row
        self.body_a, self.body_b = (int(i) for i in store.bodies[row])

    def __len__(self) -> int:
        return int(self._store.count[self.row])

    def _slots(self, array: np.ndarray) -> np.ndarray:
        return array[self.row, : len(self)].copy()

    local_a = property(lambda self: self._slots(self._store.local_a))
    local_b = property(lambda self: self._slots(self._store.local_b))
    normal_local = property(lambda self: self._slots(self._store.normal_local))
    impulse = property(lambda self: self._slots(self._store.impulse))


class ManifoldStore(MutableMapping):
    """All manifolds of a world: a mapping ``(body_a, body_b) -> ManifoldView`` over rows.

    Arrays (``R`` rows of capacity, grown by doubling; freed rows are reused lowest first):
    ``bodies (R, 2)``, ``count (R,)`` points in use, ``max_points (R,)`` (1 for pairs with
    a sphere: a rolling point must not persist), ``local_a, local_b, normal_local, impulse
    (R, S, 3)``. Iteration follows insertion order, so solving order is deterministic.

    Contact cache: ``query_rotation (R, 3, 3)`` and ``query_position (R, 3)`` hold B's pose
    in A's frame when the row's pair last went through the narrow phase, ``query_valid
    (R,)`` says the row has one (:meth:`remember_queries`, :meth:`unchanged_rows`).
    """

    def __init__(self, capacity: int = 64) -> None:
        self._rows: dict[tuple[int, int], int] = {}
        self._free: list[int] = []
        self.bodies = np.zeros((0, 2), dtype=np.int64)
        self.count = np.zeros(0, dtype=np.int64)
        self.max_points = np.zeros(0, dtype=np.int64)
        self.feature = np.zeros(0)
        self.local_a = self.local_b = self.normal_local = self.impulse = np.zeros((0, SLOTS, 3))
        self.query_rotation = np.zeros((0, 3, 3))
        self.query_position = np.zeros((0, 3))
        self.query_valid = np.zeros(0, dtype=bool)
        self._grow(capacity)

    def _grow(self, capacity: int) -> None:
        old = len(self.count)
        for name in (
            "bodies",
            "count",
            "max_points",
            "feature",
            "local_a",
            "local_b",
            "normal_local",
            "impulse",
            "query_rotation",
            "query_position",
            "query_valid",
        ):
            array = getattr(self, name)
            grown = np.zeros((capacity,) + array.shape[1:], dtype=array.dtype)
            grown[:old] = array
            setattr(self, name, grown)
        self._free = sorted(self._free + list(range(old, capacity)))

    # -- mapping protocol ------------------------------------------------------------------
    def __getitem__(self, key: tuple[int, int]) -> ManifoldView:
        return ManifoldView(self, self._rows[key])

    def __setitem__(self, key, value) -> None:
        raise TypeError("manifolds are created by ManifoldStore.add, not assigned")

    def __delitem__(self, key: tuple[int, int]) -> None:
        row = self._rows.pop(key)
        self._clear_rows(np.array([row]))
        self.query_valid[row] = False
        self._free.append(row)
        self._free.sort()

    def __iter__(self) -> Iterator[tuple[int, int]]:
        return iter(list(self._rows))

    def __len__(self) -> int:
        return len(self._rows)

    def __contains__(self, key) -> bool:
        return key in self._rows

    def clear(self) -> None:
        for key in list(self._rows):
            del self[key]

    # -- rows --------------------------------------------------------------------------------
    def add(
        self,
        key: tuple[int, int],
        max_points: int,
        feature: float = settings.CONTACT_MATCH_DISTANCE,
    ) -> int:
        """Row of a new, empty manifold for body pair ``key`` (``feature``: its feature
        length in m, see the module docstring)."""
        if not self._free:
            self._grow(2 * len(self.count))
        row = self._free.pop(0)
        self._rows[key] = row
        self.bodies[row] = key
        self.max_points[row] = max_points
        self.feature[row] = feature
        return row

    def row(self, key: tuple[int, int]) -> int | None:
        return self._rows.get(key)

    def rows(self) -> np.ndarray:
        """Rows of all manifolds, in insertion order."""
        return np.fromiter(self._rows.values(), dtype=np.int64, count=len(self._rows))

    def rows_with_points(self) -> np.ndarray:
        """Rows of the manifolds holding at least one point, in insertion order."""
        rows = self.rows()
        return rows[self.count[rows] > 0]

    # -- contact cache ---------------------------------------------------------------------
    @staticmethod
    def relative_poses(
        a: np.ndarray, b: np.ndarray, rotation: np.ndarray, position: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """B's pose in A's frame for body pairs ``a, b (p,)``: ``R_a^T R_b (p, 3, 3)`` and
        ``R_a^T (x_b - x_a) (p, 3)`` (``rotation (n, 3, 3)``, ``position (n, 3)``)."""
        ra_t = np.swapaxes(rotation[a], 1, 2)
        return ra_t @ rotation[b], (ra_t @ (position[b] - position[a])[:, :, None])[..., 0]

    def remember_queries(
        self, rows: np.ndarray, rotation: np.ndarray, position: np.ndarray
    ) -> None:
        """Record the relative pose of the pairs of ``rows`` at this narrow-phase query."""
        if len(rows) == 0:
            return
        relative = self.relative_poses(
            self.bodies[rows, 0], self.bodies[rows, 1], rotation, position
        )
        self.query_rotation[rows], self.query_position[rows] = relative
        self.query_valid[rows] = True

    def unchanged_rows(
        self,
        rows: np.ndarray,
        rotation: np.ndarray,
        position: np.ndarray,
        radius_b: np.ndarray,
        tolerance: float,
    ) -> np.ndarray:
        """(r,) bool: rows whose pair moved relative to each other by less than
        ``tolerance`` (m) since its last query.

        Every point of B within ``radius_b (r,)`` of B's center moved in A's frame by at
        most ``|dx| + ||dR||_F radius_b`` (``||dR v|| <= ||dR||_F ||v||``).
        """
        rot, pos = self.relative_poses(
            self.bodies[rows, 0], self.bodies[rows, 1], rotation, position
        )
        moved_by = (
            np.linalg.norm(pos - self.query_position[rows], axis=1)
            + np.linalg.norm(rot - self.query_rotation[rows], axis=(1, 2)) * radius_b
        )
        return self.query_valid[rows] & (moved_by < tolerance)

    def _clear_rows(self, rows: np.ndarray) -> None:
        self.count[rows] = 0
        for array in (self.local_a, self.local_b, self.normal_local, self.impulse):
            array[rows] = 0.0

    def world_points(self, rows: np.ndarray, rotation: np.ndarray, position: np.ndarray):
        """World anchors of A and B and world normals ``(r, S, 3)`` of ``rows``.

        ``rotation (n, 3, 3)`` and ``position (n, 3)`` are all bodies' poses.
        """
        a, b = self.bodies[rows, 0], self.bodies[rows, 1]
        return self._points(rows).world((rotation[a], position[a]), (rotation[b], position[b]))

    def _points(self, rows: np.ndarray) -> LocalPoints:
        """The points of ``rows`` (copies), valid in their first ``count`` slots."""
        return LocalPoints(
            self.local_a[rows],
            self.local_b[rows],
            self.normal_local[rows],
            self.impulse[rows],
            np.arange(SLOTS) < self.count[rows, None],
        )

    # -- the per-step update ---------------------------------------------------------------
    def update(  # type: ignore[override]  # not MutableMapping.update: the step's merge
        self, rows: np.ndarray, rotation: np.ndarray, position: np.ndarray, fresh: FreshPoints
    ) -> None:
        """Refresh, merge the fresh points into and reduce the manifolds ``rows``.

        Reference: :func:`reference_contacts.update_manifold`, one row at a time (tested).

        ``fresh`` holds this step's narrow-phase points, padded per row (same row order).
        """
        if len(rows) == 0:
            return
        a, b = self.bodies[rows, 0], self.bodies[rows, 1]
        frame_a = (rotation[a], position[a])
        frame_b = (rotation[b], position[b])
        feature = self.feature[rows]
        cached = self._refreshed(rows, frame_a, frame_b, feature)
        max_points = self.max_points[rows]
        points = _select_fresh(fresh, cached, frame_b, max_points, feature)
        points = _distinct(points, feature)
        local = _to_local(points, frame_a, frame_b)
        used = _inherit_impulses(local, cached, max_points, feature)
        merged = _combine(local, cached, used)
        merged = _reduce(merged, frame_a, frame_b, max_points, feature)
        self._clear_rows(rows)
        width = min(SLOTS, merged.valid.shape[1])
        valid = merged.valid[:, :width, None]
        self.count[rows] = merged.valid.sum(axis=1)
        for name in ("local_a", "local_b", "normal_local", "impulse"):  # empty slots stay 0
            getattr(self, name)[rows, :width] = np.where(
                valid, getattr(merged, name)[:, :width], 0.0
            )

    def _refreshed(self, rows, frame_a, frame_b, feature) -> LocalPoints:
        """Cached points of ``rows`` that are still in contact (see step 1), compacted."""
        cached = self._points(rows)
        point_a, point_b, normal = cached.world(frame_a, frame_b)
        gap = point_a - point_b
        depth = (gap * normal).sum(axis=2)  # d = (p_a - p_b) . n
        drift_sq = (gap * gap).sum(axis=2) - depth**2  # |tangential part of the gap|^2
        keep = (depth > -settings.CONTACT_BREAKING_DISTANCE) & (
            drift_sq < np.minimum(settings.CONTACT_DRIFT_DISTANCE, feature)[:, None] ** 2
        )
        return cached.where(cached.valid & keep)


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


def _select_fresh(
    fresh: FreshPoints, cached: LocalPoints, frame_b, max_points, feature
) -> FreshPoints:
    """Rows with more fresh points than they may keep: the supporting polygon only.

    Among near-ties the points matching cached ones win (hysteresis), so a flat face
    resting on many coplanar vertices keeps the same four points from step to step.
    """
    rb, xb = frame_b
    depth = fresh.depth()
    too_many = fresh.valid.sum(axis=1) > max_points
    chosen = fresh.valid.copy()
    if too_many.any():
        # fresh anchors in B's frame R^T (p - x), compared with every cached anchor
        local_b = np.einsum("rji,rsj->rsi", rb, fresh.point_b - xb[:, None])
        gap_sq = ((local_b[:, :, None] - cached.local_b[:, None]) ** 2).sum(axis=3)
        gap_sq = np.where(cached.valid[:, None, :], gap_sq, np.inf)
        preferred = gap_sq.min(axis=2) < feature[:, None] ** 2
        deepest = _masked_argmax(depth, fresh.valid)
        normal = fresh.normal[np.arange(len(depth)), deepest]
        support = select_support(
            fresh.point_b, depth, normal, max_points, fresh.valid, preferred, _band(feature)
        )
        chosen = np.where(too_many[:, None], support, fresh.valid)
    order = np.argsort(~chosen, axis=1, kind="stable")[:, :SLOTS]  # chosen first, in order
    return fresh.take(order, per_row(chosen, order))


def _distinct(points: FreshPoints, radius: np.ndarray) -> FreshPoints:
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
    order = np.argsort(~kept, axis=1, kind="stable")
    return points.take(order, per_row(kept, order))


def _to_local(points: FreshPoints, frame_a, frame_b) -> LocalPoints:
    """Fresh world points -> body-frame anchors ``R^T (p - x)``, normals in A's frame."""
    (ra, xa), (rb, xb) = frame_a, frame_b
    local_a = np.einsum("rji,rsj->rsi", ra, points.point_a - xa[:, None])
    local_b = np.einsum("rji,rsj->rsi", rb, points.point_b - xb[:, None])
    normal = np.einsum("rji,rsj->rsi", ra, points.normal)
    return LocalPoints(local_a, local_b, normal, np.zeros(local_a.shape), points.valid)


def _inherit_impulses(fresh: LocalPoints, cached: LocalPoints, max_points, feature) -> np.ndarray:
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
    fresh.impulse[rolling] = np.where(
        cached.valid[rolling, :1, None], cached.impulse[rolling, :1], 0.0
    )
    used[rolling] = cached.valid[rolling]
    return used


def _combine(fresh: LocalPoints, cached: LocalPoints, used: np.ndarray) -> LocalPoints:
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


def _band(feature: np.ndarray) -> np.ndarray:
    """(r,) m, the support depth band of each row: ``SUPPORT_DEPTH_BAND`` capped at ``f``."""
    return np.minimum(settings.SUPPORT_DEPTH_BAND, feature)


def feature_length(thickness_a: float, thickness_b: float) -> float:
    """m, a pair's feature length: a quarter of the thinner body's smallest dimension, at
    most ``CONTACT_MATCH_DISTANCE`` (pass ``inf`` for the stage)."""
    return min(settings.CONTACT_MATCH_DISTANCE, 0.25 * min(thickness_a, thickness_b))


def _reduce(points: LocalPoints, frame_a, frame_b, max_points, feature) -> LocalPoints:
    """Rows holding more than ``max_points``: keep the supporting polygon's points."""
    over = points.valid.sum(axis=1) > max_points
    if not over.any():
        return points
    point_a, point_b, normal = points.world(frame_a, frame_b)
    depth = ((point_a - point_b) * normal).sum(axis=2)
    chosen = select_support(
        point_b, depth, normal[:, 0], max_points, points.valid, band=_band(feature)
    )
    return points.where(np.where(over[:, None], chosen, points.valid))


def per_row(array: np.ndarray, index: np.ndarray) -> np.ndarray:
    """``array[r, index[r, k]]`` for every row r: reorders ``(r, k, ...)`` slots per row."""
    return array[np.arange(len(index))[:, None], index]


def tie_key(values: Any) -> Any:
    """``values`` rounded to multiples of ``TIE_QUANTUM``: equal keys are ties."""
    return np.round(values / settings.TIE_QUANTUM)


def _masked_argmax(values: np.ndarray, valid: np.ndarray) -> np.ndarray:
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
    first = _masked_argmax(depth + settings.PREFERRED_DEPTH_BONUS * bonus, supporting)
    chosen[rows, first] = valid[rows, first]
    p0 = points[rows, first]
    far = ((points - p0[:, None]) ** 2).sum(axis=2) * scale  # |p - p0|^2
    second = _masked_argmax(far, supporting)
    chosen[rows, second] |= (count >= 2) & valid[rows, second]
    edge = points[rows, second] - p0
    # signed area of triangle (p0, p1, p) about the normal: ((p1 - p0) x (p - p0)) . n / 2
    area = (cross(edge[:, None], points - p0[:, None]) * normal[:, None]).sum(axis=2) * scale
    third = _masked_argmax(np.abs(area), supporting)
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
