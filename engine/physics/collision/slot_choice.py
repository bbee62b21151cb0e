"""The slot choice of a manifold row: which of its points a manifold keeps.

A row holds at most ``MAX_MANIFOLD_POINTS`` (four) points. When more compete (this step's
fresh points, or the cached and fresh points merged), :func:`select_support` keeps the
supporting polygon around the row's normal (Bullet's ``btPersistentManifold::sortCachedPoints``
idea: the deepest point, then the largest area), and :func:`select_with_corners` shares the
slots out where the points push along two or three directions (a body in a corner of the
stage: the floor and walls, :func:`corner_points`). Per-row choices compare values rounded by
:func:`tie_key`, so that the per-pair reference (:mod:`reference_manifolds`) makes the same
choices. Used by the merge (:mod:`manifold_merge`) and the fresh manifolds
(:mod:`keyed_manifolds`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core import settings
from ..core.quaternions import cross


def support_band(feature: np.ndarray) -> np.ndarray:
    """(r,) m, the support depth band of each row: ``SUPPORT_DEPTH_BAND`` capped at ``f``."""
    return np.minimum(settings.SUPPORT_DEPTH_BAND, feature)


def per_row(array: np.ndarray, index: np.ndarray) -> np.ndarray:
    """``array[r, index[r, k]]`` for every row r: reorders ``(r, k, ...)`` slots per row."""
    return array[np.arange(len(index))[:, None], index]


def tie_key(values: Any) -> Any:
    """``values`` rounded to multiples of ``TIE_QUANTUM``: equal keys are ties."""
    # rint, halves to even, is what np.round(x) (0 decimals) calls, minus 3 Python calls
    return np.rint(values / settings.TIE_QUANTUM)


def masked_argmax(values: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """Per row, the first slot holding the largest valid value (0 for empty rows)."""
    return np.where(valid, tie_key(values), -np.inf).argmax(axis=1)


def select_with_corners(
    points: np.ndarray,
    depth: np.ndarray,
    normals: np.ndarray,
    normal: np.ndarray,
    count: np.ndarray,
    valid: np.ndarray,
    preferred: np.ndarray | None = None,
    band: np.ndarray | None = None,
) -> np.ndarray:
    """:func:`select_support`, but a row whose points push along two or three directions (a
    body in a corner of the stage: floor and walls) keeps the supporting polygon of the
    floor and the deepest point of each other direction, so a deep wall contact can take
    neither every slot nor all but one (one floor point lets the body tip about it into
    the floor: a cube's edge pressed into a skirting board sank 2.6 cm).

    Reference: :func:`reference_manifolds.select_with_corners` (one row).

    ``normals (r, k, 3)``: each point's unit normal; ``normal (r, 3)``: the row's reference
    normal (its deepest point's). A point is in another direction when ``n . n_ref <
    STAGE_CORNER_COSINE`` (about 45 degrees); a third direction is also that far from the
    second. Points of rows keeping at least 4 points reserve slots (one per extra
    direction), speculative ones too (a wall the body slides along keeps a cached point, so
    its outward side is remembered, :func:`batched_stage._outward_side`). In such a row the
    reference becomes the deepest touching floor-like point's normal (``n_y >=
    FLOOR_NORMAL_Y``, the world's up: the surface bearing the body's weight), if any; its
    direction's points span the polygon (:func:`select_support`) and slots still free take
    the deepest of the rest.
    """
    corners = corner_points(depth, normals, normal, count, valid)
    if corners is None:  # the usual case: every point pushes along the row's normal
        return select_support(points, depth, normal, count, valid, preferred, band)
    reserved, normal, own = corners
    left = count - reserved.sum(axis=1)  # slots left for the row's own supporting polygon
    chosen = select_support(points, depth, normal, left, own & ~reserved, preferred, band)
    chosen |= reserved
    # slots still free (the floor holds fewer points than its share): the deepest others
    free = count - chosen.sum(axis=1)
    rest = np.where(valid & ~chosen, depth, -np.inf)
    rank = (-tie_key(rest)).argsort(axis=1, kind="stable")
    take = (np.arange(depth.shape[1]) < free[:, None]) & np.isfinite(per_row(rest, rank))
    chosen[np.arange(len(count))[:, None], rank] |= take
    return chosen


def corner_points(depth, normals, normal, count, valid):
    """The corner rows' choice (see :func:`select_with_corners`), or None when no row has
    points in another direction: ``reserved (r, k)`` (the deepest point of each extra
    direction), the rows' reference normals ``(r, 3)`` (the floor's, where they have one)
    and ``own (r, k)`` (the points along it: all valid points of a row without a corner)."""
    cosine = settings.STAGE_CORNER_COSINE
    # speculative points too: a wall the body slides along keeps its side in the cache
    kept = valid & (count >= 4)[:, None]
    turned = kept & ((normals * normal[:, None]).sum(axis=2) < cosine)
    corner = turned.any(axis=1)
    if not corner.any():
        return None
    rows = np.arange(len(depth))
    # the reference of a corner row: its deepest touching floor-like point's normal
    floor = kept & (depth >= 0.0) & (normals[:, :, 1] >= settings.FLOOR_NORMAL_Y)
    on_floor = corner & floor.any(axis=1)
    normal = np.where(on_floor[:, None], normals[rows, masked_argmax(depth, floor)], normal)
    along = (normals * normal[:, None]).sum(axis=2)
    turned = kept & (along < cosine)
    second = masked_argmax(depth, turned)
    has_second = turned[rows, second]
    reserved = np.zeros_like(valid)
    reserved[rows, second] = has_second
    # a third direction: turned from both the row's normal and the second one's
    second_normal = normals[rows, second]
    third_ok = turned & ((normals * second_normal[:, None]).sum(axis=2) < cosine)
    third = masked_argmax(depth, third_ok)
    reserved[rows, third] |= has_second & third_ok[rows, third]
    own = valid & ((along >= cosine) | ~corner[:, None])
    return reserved, normal, own


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

    Reference: :func:`reference_manifolds.select_support` (one row).

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
    # (the edge repeated per slot: cross then needs no broadcast_arrays, 10 Python calls)
    edges = edge[:, None].repeat(points.shape[1], axis=1)
    area = (cross(edges, points - p0[:, None]) * normal[:, None]).sum(axis=2) * scale
    third = masked_argmax(np.abs(area), supporting)
    chosen[rows, third] |= (count >= 3) & valid[rows, third]
    # the fourth point lies on the other side of edge p0-p1 with the largest area
    opposite = np.where(supporting & ~chosen, -np.sign(area[rows, third])[:, None] * area, -np.inf)
    fourth = tie_key(opposite).argmax(axis=1)
    chosen[rows, fourth] |= (count >= 4) & np.isfinite(opposite[rows, fourth])
    # fill the slots left over with the deepest remaining points
    remaining = count - chosen.sum(axis=1)
    if not (remaining > 0).any():  # every row has all its points: nothing to fill
        return chosen
    rest = np.where(valid & ~chosen, depth, -np.inf)
    rank = (-tie_key(rest)).argsort(axis=1, kind="stable")
    take = (np.arange(depth.shape[1]) < remaining[:, None]) & np.isfinite(per_row(rest, rank))
    chosen[rows[:, None], rank] |= take
    return chosen
