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
   wins); a fresh point within ``CONTACT_MATCH_DISTANCE`` of a cached one in B's frame
   inherits its impulses (this is what makes warm starting work), also from a cached point
   step 1 dropped: B's anchor names B's feature (a box corner), whose load persists while it
   slides (Box2D v3 keys its warm start by feature ids the same way). Three or more fresh
   points replace the cache; fewer are added to it (GJK gives one point per step, so a
   manifold builds up);
3. reduce to four: the deepest point, the point farthest from it, then the points that
   maximize the contact polygon's area (largest support area = most stable resting).

Fresh rows: a row whose pair's contacts are a whole manifold every step (every pair
without a capsule, the stage's included: boxes, hulls, spheres; ``keyable (R,)``) skips
steps 1-3 when ``SolverSettings.feature_manifolds`` is on: its points are this step's fresh
points, cut to four with the points at last step's feature keys (``point_key (R, S)``)
winning near-ties, warm-started from the nearest cached point in B's frame; the stage's
rows with fewer than three fresh points keep their untaken cached points still touching
(step 1's test and step 2's rule: :mod:`keyed_manifolds`, Box2D v3's and Jolt's manifolds).

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
from dataclasses import dataclass
from itertools import repeat

import numpy as np

from ..core import settings
from ..core.bodies import STAGE_ID
from .keyed_manifolds import keyed_points
from .manifold_merge import (
    POINT_FIELDS,
    SLOTS,
    FreshPoints,
    LocalPoints,
    RowFrames,
    combine,
    distinct_points,
    feature_length,
    inherit_impulses,
    per_row,
    reduce_points,
    select_fresh,
    select_support,
    still_touching,
    tie_key,
    to_local,
)

#: re-exported: the merge steps live in manifold_merge.py
__all__ = [
    "SLOTS",
    "FreshPoints",
    "LocalPoints",
    "ManifoldStore",
    "ManifoldView",
    "feature_length",
    "per_row",
    "select_support",
    "tie_key",
]


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


@dataclass
class GraphMemo:
    """A result computed from the contact graph and the graph's bytes (``key``): the solve
    stage keeps its solver order here (``solve_stage.solver_order``) and reuses it while
    the graph is unchanged. ``value`` None: nothing kept yet."""

    key: bytes = b""
    value: tuple | None = None


class ManifoldStore(MutableMapping):
    """All manifolds of a world: a mapping ``(body_a, body_b) -> ManifoldView`` over rows.

    Arrays (``R`` rows of capacity, grown by doubling; freed rows are reused lowest first):
    ``bodies (R, 2)``, ``count (R,)`` points in use, ``max_points (R,)`` (1 for pairs with
    a sphere: a rolling point must not persist), ``keyable (R,)`` (the row may be rebuilt
    from fresh points by feature keys), ``point_key (R, S)`` each slot's feature key (0:
    none; every real key names a rule of order > 0), ``points (R, S, 4, 3)`` each slot's
    ``local_a, local_b, normal_local, impulse`` (:data:`manifold_merge.POINT_FIELDS`), with
    the views ``local_a, local_b, normal_local, impulse (R, S, 3)``: one array so that the
    merge reads and writes all four with one NumPy call. Iteration follows insertion order,
    so solving order is deterministic.

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
        self.keyable = np.zeros(0, dtype=bool)
        self.point_key = np.zeros((0, SLOTS), dtype=np.int64)
        self.feature = np.zeros(0)
        self.points = np.zeros((0, SLOTS, len(POINT_FIELDS), 3))
        self.query_rotation = np.zeros((0, 3, 3))
        self.query_position = np.zeros((0, 3))
        self.query_valid = np.zeros(0, dtype=bool)
        self.solver_order = GraphMemo()  # the solve stage's memo (solve_stage.solver_order)
        self._grow(capacity)

    def _grow(self, capacity: int) -> None:
        old = len(self.count)
        for name in (
            "bodies",
            "count",
            "max_points",
            "keyable",
            "point_key",
            "feature",
            "points",
            "query_rotation",
            "query_position",
            "query_valid",
        ):
            array = getattr(self, name)
            grown = np.zeros((capacity,) + array.shape[1:], dtype=array.dtype)
            grown[:old] = array
            setattr(self, name, grown)
        self._free = sorted(self._free + list(range(old, capacity)))

    # the fields of every slot (R, S, 3): views of ``points``, so writing them writes it
    local_a = property(lambda self: self.points[:, :, 0])
    local_b = property(lambda self: self.points[:, :, 1])
    normal_local = property(lambda self: self.points[:, :, 2])
    impulse = property(lambda self: self.points[:, :, 3])

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
        keyable: bool = False,
    ) -> int:
        """Row of a new, empty manifold for body pair ``key`` (``feature``: its feature
        length in m; ``keyable``: its contacts are a whole manifold every step, see the
        module docstring)."""
        if not self._free:
            self._grow(2 * len(self.count))
        row = self._free.pop(0)
        self._rows[key] = row
        self.bodies[row] = key
        self.max_points[row] = max_points
        self.feature[row] = feature
        self.keyable[row] = keyable
        return row

    def row(self, key: tuple[int, int], default: int | None = None) -> int | None:
        """Row of the manifold of body pair ``key``, ``default`` when it has none."""
        return self._rows.get(key, default)

    def rows_of(self, keys: list[tuple[int, int]], default: int | None = None) -> list:
        """:meth:`row` of every key of ``keys`` (one method call for a whole pair list)."""
        # map runs dict.get in C: no Python loop over the (hundreds of) pairs of a step
        return list(map(self._rows.get, keys, repeat(default, len(keys))))

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
        shift, turn = pos - self.query_position[rows], rot - self.query_rotation[rows]
        # |dx| and ||dR||_F written out: np.linalg.norm's own formula, without its checks
        moved_by = (
            np.sqrt((shift * shift).sum(axis=1))
            + np.sqrt((turn * turn).sum(axis=(1, 2))) * radius_b
        )
        return self.query_valid[rows] & (moved_by < tolerance)

    def _clear_rows(self, rows: np.ndarray) -> None:
        self.count[rows] = 0
        self.points[rows] = 0.0
        self.point_key[rows] = 0

    def world_points(self, rows: np.ndarray, rotation: np.ndarray, position: np.ndarray):
        """World anchors of A and B and world normals ``(r, S, 3)`` of ``rows``.

        ``rotation (n, 3, 3)`` and ``position (n, 3)`` are all bodies' poses.
        """
        frames = RowFrames.of_pairs(self.bodies[rows], rotation, position)
        return self._points(rows).world(frames)

    def _points(self, rows: np.ndarray) -> LocalPoints:
        """The points of ``rows`` (copies), valid in their first ``count`` slots."""
        return LocalPoints(self.points[rows], np.arange(SLOTS) < self.count[rows, None])

    # -- the per-step update ---------------------------------------------------------------
    def merge_fresh(
        self, rows: np.ndarray, rotation: np.ndarray, position: np.ndarray, fresh: FreshPoints
    ) -> None:
        """Refresh, merge the fresh points into and reduce the manifolds ``rows``.

        Reference: :func:`reference_contacts.update_manifold`, one row at a time (tested).

        ``fresh`` holds this step's narrow-phase points, padded per row (same row order).
        """
        if len(rows) == 0:
            return
        frames = RowFrames.of_pairs(self.bodies[rows], rotation, position)
        feature, max_points = self.feature[rows], self.max_points[rows]
        every = self._points(rows)  # all cached points: their impulses for warm starting
        # the ones still touching (slots unmoved: a slot is the same point as in every)
        cached = LocalPoints(every.data, still_touching(every, frames, feature))
        points = select_fresh(fresh, cached, frames, max_points, feature)
        points = distinct_points(points, feature)
        local = to_local(points, frames)
        used = inherit_impulses(local, every, max_points, feature)
        merged = combine(local, cached, used)
        merged = reduce_points(merged, frames, max_points, feature)
        self._write_rows(rows, merged)  # merged points have no feature keys

    def replace_fresh(
        self, rows: np.ndarray, rotation: np.ndarray, position: np.ndarray, fresh: FreshPoints
    ) -> None:
        """The manifolds ``rows`` become their fresh points (``fresh``, padded per row, with
        their keys), cut to four by keys and warm-started from the cached points
        (:func:`keyed_manifolds.keyed_points`).

        Reference: :func:`reference_manifolds.keyed_manifold`, one row at a time (tested)."""
        if len(rows) == 0:
            return
        frames = RowFrames.of_pairs(self.bodies[rows], rotation, position)
        points, key = keyed_points(
            fresh,
            fresh.key,
            frames,
            self._points(rows),
            self.point_key[rows],
            self.max_points[rows],
            self.feature[rows],
            self.bodies[rows, 0] == STAGE_ID,  # the stage's rows hold untaken cached points
        )
        self._write_rows(rows, points, key)

    def _write_rows(self, rows: np.ndarray, points: LocalPoints, key=None) -> None:
        """Store ``points`` (at most ``SLOTS`` valid a row, in their first slots) as the
        manifolds ``rows``, with their feature keys ``key (r, k)`` (None: no keys, 0)."""
        width = min(SLOTS, points.valid.shape[1])
        if width < SLOTS:  # else every slot is written below
            self._clear_rows(rows)
        valid = points.valid[:, :width, None, None]
        self.count[rows] = points.valid.sum(axis=1)
        # all four fields of every slot in one write; empty slots stay 0
        self.points[rows, :width] = np.where(valid, points.data[:, :width], 0.0)
        if key is None:
            self.point_key[rows] = 0
        else:
            self.point_key[rows, :width] = np.where(valid[:, :, 0, 0], key[:, :width], 0)
