"""Persistent contact manifolds: up to four points per body pair, kept across steps.

Each manifold point stores its two anchors in the body frames (``local_a``, ``local_b``),
its normal in A's frame, and the impulses accumulated by the solver ``(normal, tangent1,
tangent2)`` in N s. Every step (Bullet's ``btPersistentManifold`` idea):

1. refresh: recompute the world anchors; drop points whose bodies separated more than
   ``CONTACT_BREAKING_DISTANCE`` along the normal or slid apart more than
   ``CONTACT_DRIFT_DISTANCE`` tangentially;
2. merge: a fresh point within ``CONTACT_MATCH_DISTANCE`` of a cached one replaces it and
   inherits its impulses (this is what makes warm starting work), others are appended;
3. reduce to four: the deepest point, the point farthest from it, then the points that
   maximize the contact polygon's area (largest support area = most stable resting).

Normals point from body A to body B; depth ``(p_a - p_b) . n`` is positive when overlapping.
"""

from __future__ import annotations

import numpy as np

from . import settings
from .quaternions import cross


class Manifold:
    """Contact points of one body pair ``(body_a, body_b)``, ``body_a < body_b``.

    Attributes
    ----------
    local_a, local_b : (k, 3) anchors in the body frames of A and B, m.
    normal_local : (k, 3) unit normal in A's body frame (from A to B).
    impulse : (k, 3) accumulated impulses (normal, tangent 1, tangent 2), N s.
    max_points : int, 1 for pairs with a sphere (a rolling point must not persist).
    """

    def __init__(self, body_a: int, body_b: int, max_points: int) -> None:
        self.body_a, self.body_b, self.max_points = body_a, body_b, max_points
        self.local_a = np.zeros((0, 3))
        self.local_b = np.zeros((0, 3))
        self.normal_local = np.zeros((0, 3))
        self.impulse = np.zeros((0, 3))

    def __len__(self) -> int:
        return len(self.local_a)

    def world_points(self, pose_a, pose_b):
        """World anchors ``(k, 3)`` of A and B and world normals ``(k, 3)``."""
        (ra, xa), (rb, xb) = pose_a, pose_b
        return self.local_a @ ra.T + xa, self.local_b @ rb.T + xb, self.normal_local @ ra.T

    def update(self, pose_a, pose_b, fresh) -> None:
        """Refresh cached points, merge the fresh ``(point_a, point_b, normal)`` arrays, reduce."""
        self._refresh(pose_a, pose_b)
        if fresh is not None:
            self._merge(pose_a, pose_b, *fresh)
        if len(self) > self.max_points:
            self._reduce(pose_a, pose_b)

    def _keep(self, mask) -> None:
        self.local_a, self.local_b = self.local_a[mask], self.local_b[mask]
        self.normal_local, self.impulse = self.normal_local[mask], self.impulse[mask]

    def _refresh(self, pose_a, pose_b) -> None:
        if len(self) == 0:
            return
        point_a, point_b, normal = self.world_points(pose_a, pose_b)
        gap = point_a - point_b
        depth = (gap * normal).sum(axis=1)  # d = (p_a - p_b) . n
        drift_sq = (gap * gap).sum(axis=1) - depth**2  # |tangential part of the gap|^2
        keep = ((depth > -settings.CONTACT_BREAKING_DISTANCE)
                & (drift_sq < settings.CONTACT_DRIFT_DISTANCE**2))
        if not keep.all():  # (keeping every point would copy the arrays for nothing)
            self._keep(keep)

    def _merge(self, pose_a, pose_b, point_a, point_b, normal) -> None:
        """Merge fresh points: dedupe them, match each to at most one cached point."""
        (ra, xa), (rb, xb) = pose_a, pose_b
        depth = ((point_a - point_b) * normal).sum(axis=1)
        if len(depth) > self.max_points:  # many vertex contacts: keep the support polygon
            preferred = np.zeros(len(depth), dtype=bool)
            if len(self):  # hysteresis: among near-ties keep the points we already have
                local = (point_b - xb) @ rb
                gap_sq = ((local[:, None] - self.local_b[None]) ** 2).sum(axis=2)
                preferred = gap_sq.min(axis=1) < settings.CONTACT_MATCH_DISTANCE**2
            chosen = select_support_points(point_b, depth, normal[np.argmax(depth)],
                                           self.max_points, preferred)
            point_a, point_b, normal, depth = (point_a[chosen], point_b[chosen],
                                               normal[chosen], depth[chosen])
        fresh = _distinct_points(point_b, depth, settings.CONTACT_MATCH_DISTANCE)
        point_a, point_b, normal = point_a[fresh], point_b[fresh], normal[fresh]
        new_local_a = (point_a - xa) @ ra  # R^T (p - x)
        new_local_b = (point_b - xb) @ rb
        new_impulse = np.zeros((len(point_a), 3))
        used = [False] * len(self)
        if self.max_points == 1:
            if len(self):
                new_impulse[:] = self.impulse[0]  # the single rolling point keeps its impulse
            used = [True] * len(self)
        elif len(self):
            fresh_index, cached_index = self._match(new_local_b, used)
            new_impulse[fresh_index] = self.impulse[cached_index]
        # a full fresh manifold (3+ points) replaces the cache; a partial one (GJK gives one
        # point per step) is added to it, so the manifold builds up over a few steps
        if len(point_a) >= 3:
            self.local_a, self.local_b = new_local_a, new_local_b
            self.normal_local, self.impulse = normal @ ra, new_impulse
            return
        self._keep(~np.array(used, dtype=bool))
        self.local_a = np.concatenate([self.local_a, new_local_a])
        self.local_b = np.concatenate([self.local_b, new_local_b])
        self.normal_local = np.concatenate([self.normal_local, normal @ ra])
        self.impulse = np.concatenate([self.impulse, new_impulse])

    def _match(self, new_local_b, used: list) -> tuple[list, list]:
        """Greedy one-to-one match of fresh points (deepest first) to cached ones.

        Returns the matched fresh and cached indices; marks matched cached points in ``used``.
        """
        # |cached_i - fresh_j|^2 in B's frame; a match needs < CONTACT_MATCH_DISTANCE^2
        dist_sq = ((self.local_b[:, None] - new_local_b[None]) ** 2).sum(axis=2).tolist()
        limit = settings.CONTACT_MATCH_DISTANCE**2
        fresh_index, cached_index = [], []
        for j in range(len(new_local_b)):
            best, best_i = limit, -1
            for i, row in enumerate(dist_sq):
                if not used[i] and row[j] < best:
                    best, best_i = row[j], i
            if best_i >= 0:
                fresh_index.append(j)
                cached_index.append(best_i)
                used[best_i] = True
        return fresh_index, cached_index

    def _reduce(self, pose_a, pose_b) -> None:
        point_a, point_b, normal = self.world_points(pose_a, pose_b)
        depth = ((point_a - point_b) * normal).sum(axis=1)
        self._keep(select_support_points(point_b, depth, normal[0], self.max_points))


def _distinct_points(points: np.ndarray, depth: np.ndarray, radius: float) -> np.ndarray:
    """Indices of points, deepest first, dropping any within ``radius`` of a kept one."""
    dist_sq = ((points[:, None] - points[None]) ** 2).sum(axis=2).tolist()
    kept: list[int] = []
    for i in np.argsort(-depth, kind="stable").tolist():
        if all(dist_sq[i][j] >= radius * radius for j in kept):
            kept.append(i)
    return np.array(kept, dtype=np.int64)


def select_support_points(points: np.ndarray, depth: np.ndarray, normal: np.ndarray,
                          count: int, preferred: np.ndarray | None = None) -> np.ndarray:
    """Indices of up to ``count`` points: the supporting ones spanning the largest area.

    Supporting points lie within ``SUPPORT_DEPTH_BAND`` of the deepest; among them
    :func:`spread_points` picks the deepest and those spanning the largest area. Slots left
    over take the remaining (speculative) points, nearest first.
    """
    supporting = np.flatnonzero(depth >= depth.max() - settings.SUPPORT_DEPTH_BAND)
    pref = None if preferred is None else preferred[supporting]
    chosen = supporting[spread_points(points[supporting], depth[supporting], normal, count,
                                      pref)].tolist()
    for index in np.argsort(-depth, kind="stable").tolist():
        if len(chosen) >= count:
            break
        if index not in chosen:
            chosen.append(index)
    return np.array(sorted(chosen), dtype=np.int64)


def spread_points(points: np.ndarray, depth: np.ndarray, normal: np.ndarray,
                  count: int, preferred: np.ndarray | None = None) -> np.ndarray:
    """Indices of ``count`` points: the deepest, then those spanning the largest area.

    Parameters
    ----------
    points : (k, 3) world contact points, depth : (k,) m, normal : (3,) unit.
    preferred : (k,) bool, points matching cached ones; they win near-ties (1 mm of depth,
        10 % of distance or area), so a flat face resting on many coplanar vertices keeps
        the same four points from step to step instead of flickering between them.
    """
    bonus = np.zeros(len(depth)) if preferred is None else preferred.astype(np.float64)
    chosen = [int(np.argmax(depth + 1e-3 * bonus))]
    scale = 1.0 + 0.1 * bonus
    if count >= 2:
        far = ((points - points[chosen[0]]) ** 2).sum(axis=1) * scale
        chosen.append(int(np.argmax(far)))
    if count >= 3:
        edge = points[chosen[1]] - points[chosen[0]]
        # signed area of triangle (p0, p1, p) about the normal: ((p1 - p0) x (p - p0)) . n / 2
        area = cross(edge, points - points[chosen[0]]) @ normal * scale
        third = int(np.argmax(np.abs(area)))
        chosen.append(third)
        if count >= 4:
            # the fourth point lies on the other side of edge p0-p1 with the largest area
            opposite = -np.sign(area[third]) * area
            opposite[chosen] = -np.inf
            chosen.append(int(np.argmax(opposite)))
    return np.array(sorted(set(chosen)), dtype=np.int64)
