"""Collision detection: broad phase (AABB overlap) and narrow phase (contact points).

Broad phase: world AABBs of all bodies from their body-frame AABB and rotation
(``half_world = |R| half_body``), then every overlapping pair ``(a, b)``, ``a < b``, found
with one broadcast comparison while the moving bodies times all bodies stay small, by sort
and sweep above that (O(n log n + overlaps), so a thousand bodies cost no n^2 table).

Narrow phase returns, per pair, world-frame arrays

* ``point_a (k, 3)``: the deepest point of A inside B,
* ``point_b (k, 3)``: the deepest point of B inside A,
* ``normal (k, 3)``: unit, **from A to B**,

so the penetration depth is ``(point_a - point_b) . normal`` (positive = overlapping).
Contacts are generated three ways; the pair table (:mod:`pair_table`) picks the way for
two shape kinds (methods 1 and 2 for polyhedra run batched over all pairs of a step in
:mod:`batched_pairs` and :mod:`batched_stage`):

1. polyhedron vs polyhedron (boxes, hulls, tessellated cylinders/cones): python-fcl gives
   the normal and depth; we then keep every vertex of one body that lies inside the other
   (its hull planes, inflated by ``SPECULATIVE_DISTANCE``), measured against the contact
   plane. A box resting on a box gets its four corners even when fcl reports one point.
2. body vs stage triangle mesh: fcl only names the touched triangles; contacts are the
   body's hull vertices lying in a triangle's prism just below its plane, with the
   triangle's normal (stable resting on a 2-triangle floor), spheres use the exact closest
   point on the triangle (Ericson, Real-Time Collision Detection, 5.1.5).
3. anything else (capsules, edge-edge cases): fcl's points (:mod:`contact_helpers`).
"""

from __future__ import annotations

import numpy as np

from ..core import settings
from ..core.quaternions import cross, quat_to_matrix
from ..core.shapes import ShapeKind
from .contact_helpers import (
    center_decides,
    contact_arrays,
    fcl_raw_contacts,
    level_with,
    midpoint_contacts,
    new_contact_side,
    segment_in_body,
    triangle_table,
)


def world_aabbs(
    center_local: np.ndarray,
    half_local: np.ndarray,
    position: np.ndarray,
    rotation: np.ndarray,
    matrices: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """World AABBs ``(n, 3)`` min and max of boxes given in the body frame (``rotation``:
    quaternions ``(n, 4)``; ``matrices (n, 3, 3)``: their rotation matrices, if known).

    ``center_w = x + R c``, ``half_w = |R| h`` (Arvo's transformed-box bound).
    """
    r = quat_to_matrix(rotation) if matrices is None else matrices
    center = position + np.einsum("nij,nj->ni", r, center_local)
    half = np.einsum("nij,nj->ni", np.abs(r), half_local)
    return center - half, center + half


def overlapping_pairs(
    aabb_min: np.ndarray, aabb_max: np.ndarray, candidates: np.ndarray, active: np.ndarray
) -> np.ndarray:
    """Pairs ``(p, 2)`` of indices into the body arrays, ``a < b``, whose AABBs overlap.

    Pairs come sorted by ``(a, b)``, so their order does not depend on who is active. With
    ``k`` active candidates, the brute-force ``(k, c)`` test (:func:`all_pairs_overlaps`,
    the readable version) runs while ``k c <= BROAD_PHASE_BRUTE_FORCE``; above it, sort and
    sweep (:func:`sweep_and_prune_overlaps`, ``O(c log c + overlaps)``). Both return the
    same pairs (tested).

    Parameters
    ----------
    aabb_min, aabb_max : (n, 3) float
        World AABBs of all bodies.
    candidates : (c,) int
        Collidable bodies to test.
    active : (n,) bool
        Bodies that can move this step; a pair needs at least one.
    """
    movers = candidates[active[candidates]]
    if len(movers) * len(candidates) <= settings.BROAD_PHASE_BRUTE_FORCE:
        return all_pairs_overlaps(aabb_min, aabb_max, candidates, active)
    return sweep_and_prune_overlaps(aabb_min, aabb_max, candidates, active)


def _sorted_pairs(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Pairs ``(p, 2)`` as ``(min, max)``, sorted by first then second index."""
    first, second = np.minimum(a, b), np.maximum(a, b)
    order = np.lexsort((second, first))
    return np.stack([first[order], second[order]], axis=1)


def all_pairs_overlaps(
    aabb_min: np.ndarray, aabb_max: np.ndarray, candidates: np.ndarray, active: np.ndarray
) -> np.ndarray:
    """:func:`overlapping_pairs` by brute force: the ``k`` active candidates against all
    ``c`` candidates, one ``(k, c)`` comparison per axis and bound (``O(k c)``)."""
    moving = active[candidates]
    movers = candidates[moving]
    # overlap iff lo_m <= hi_c and lo_c <= hi_m on all three axes: the six tests as one
    # comparison [lo_m; -hi_m] <= [hi_c; -lo_c] of (6, k) with (6, c) bounds, then all six
    # (the long axes last and contiguous: 2-3x faster than a loop of (k, c) tests per axis
    # and bound, and than reducing a (k, c, 6) array over its short last axis)
    lo, hi = aabb_min[candidates], aabb_max[candidates]
    limits = np.ascontiguousarray(np.concatenate([hi, -lo], axis=1).T)  # (6, c)
    bounds = np.ascontiguousarray(np.concatenate([lo, -hi], axis=1)[moving].T)  # (6, k)
    overlap = (bounds[:, :, None] <= limits[:, None]).all(axis=0)  # (k, c)
    im, ic = np.nonzero(overlap)
    a, b = movers[im], candidates[ic]
    # each pair once: two movers meet twice, keep the one seen from the lower index (a
    # mover also meets itself: b = a is active and not above a, so it is dropped too)
    keep = ~active[b] | (a < b)
    return _sorted_pairs(a[keep], b[keep])


def sweep_and_prune_overlaps(
    aabb_min: np.ndarray, aabb_max: np.ndarray, candidates: np.ndarray, active: np.ndarray
) -> np.ndarray:
    """:func:`overlapping_pairs` by sort and sweep (Baraff 1992; Ericson 7.5.1).

    Along the axis where the boxes spread most, sort the boxes by their lower bound; box
    ``i``'s overlaps on that axis are the boxes ``j`` after it in that order whose lower
    bound is ``<= hi_i`` (one ``searchsorted``). Those candidate pairs are then tested on
    all three axes and kept if one of the two bodies is active.
    """
    lo, hi = aabb_min[candidates], aabb_max[candidates]
    axis = int(np.argmax((lo + hi).var(axis=0)))  # the axis the centers spread along most
    order = np.argsort(lo[:, axis], kind="stable")
    lo, hi = lo[order], hi[order]
    first = np.arange(1, len(order) + 1)  # box i's partners start right after it
    stop = np.searchsorted(lo[:, axis], hi[:, axis], side="right")  # first lo_j > hi_i
    count = np.maximum(stop - first, 0)
    i = np.repeat(np.arange(len(order)), count)
    # j runs over first_i .. stop_i - 1 for every i: a flat arange minus each run's start
    j = np.arange(len(i)) - np.repeat(np.cumsum(count) - count, count) + np.repeat(first, count)
    # overlap on all three axes: the (e, 3) tests at once, then their three columns (the
    # columns written out: .all over a length-3 axis pays per row)
    each = (lo[i] <= hi[j]) & (lo[j] <= hi[i])
    overlap = each[:, 0] & each[:, 1] & each[:, 2]
    a, b = candidates[order[i[overlap]]], candidates[order[j[overlap]]]
    keep = active[a] | active[b]
    return _sorted_pairs(a[keep], b[keep])


def boxes_separated(
    center_a: np.ndarray,
    rotation_a: np.ndarray,
    half_a: np.ndarray,
    center_b: np.ndarray,
    rotation_b: np.ndarray,
    half_b: np.ndarray,
) -> np.ndarray:
    """(p,) bool: oriented boxes A and B are disjoint (separating axis test, 15 axes).

    Ericson, Real-Time Collision Detection, 4.4.1 (Gottschalk's OBB test). Box k has world
    center ``center_k (p, 3)``, axes = columns of ``rotation_k (p, 3, 3)`` and half extents
    ``half_k (p, 3)``. With ``R = R_a^T R_b`` (B's axes in A's frame) and ``t = R_a^T (c_b -
    c_a)``, the boxes are apart iff on some axis L the center distance exceeds the sum of
    the projected radii: ``|t . L| > r_a(L) + r_b(L)``.
    """
    rel = np.swapaxes(rotation_a, 1, 2) @ rotation_b  # R_ij = a_i . b_j
    t = (np.swapaxes(rotation_a, 1, 2) @ (center_b - center_a)[:, :, None])[..., 0]
    abs_rel = np.abs(rel) + settings.BOX_TEST_PARALLEL_GUARD  # (nearly) parallel edges
    # axes a_i: |t_i| > h_a_i + sum_j h_b_j |R_ij|
    apart = (np.abs(t) > half_a + (abs_rel @ half_b[:, :, None])[..., 0]).any(1)
    # axes b_j: |t . R_:j| > sum_i h_a_i |R_ij| + h_b_j
    t_b = (t[:, None, :] @ rel)[:, 0]
    apart |= (np.abs(t_b) > (half_a[:, None, :] @ abs_rel)[:, 0] + half_b).any(1)
    # axes a_i x b_j (i1, i2 = i+1, i+2 mod 3; same for j):
    # |t_i2 R_i1j - t_i1 R_i2j| > h_a_i1 |R_i2j| + h_a_i2 |R_i1j| + h_b_j1 |R_ij2| + h_b_j2 |R_ij1|
    n1, n2 = np.array([1, 2, 0]), np.array([2, 0, 1])  # i+1, i+2 mod 3
    dist = np.abs(t[:, n2, None] * rel[:, n1, :] - t[:, n1, None] * rel[:, n2, :])
    radius_a = half_a[:, n1, None] * abs_rel[:, n2, :] + half_a[:, n2, None] * abs_rel[:, n1, :]
    radius_b = half_b[:, None, n1] * abs_rel[:, :, n2] + half_b[:, None, n2] * abs_rel[:, :, n1]
    apart |= (dist > radius_a + radius_b).reshape(len(t), 9).any(1)
    return apart


def round_stage_contacts(stage_shape, object_stage, shape_b, pose_b, probe_b):
    """Contacts of a round body shape B (sphere, capsule) with the stage mesh A (method 2).

    ``probe_b`` is B's shape grown by ``STAGE_SPECULATIVE_DISTANCE``: fcl finds the triangles
    near B; a sphere then gets the exact closest point, a capsule the exact closest points of
    its two end spheres (only when neither touches, a ridge under its middle: fcl's points
    with the deepest triangle's normal). (Polyhedra are batched in :mod:`batched_stage`.)
    """
    mid, _, depths, tri_ids = contact_arrays(fcl_raw_contacts(object_stage, probe_b))
    if len(depths) == 0:
        return None
    depths = depths - settings.STAGE_SPECULATIVE_DISTANCE  # probe depth -> shape depth
    tri_ids = np.unique(tri_ids[tri_ids >= 0])
    tris = stage_shape.ray_triangles[tri_ids]  # (t, 3, 3) world (the stage frame is world)
    rb, xb = pose_b
    center = rb @ shape_b.body_from_shape[:3, 3] + xb
    table = triangle_table(stage_shape)
    if shape_b.kind == ShapeKind.CAPSULE:  # its two end spheres (fcl's capsule depths are off)
        normal = _outward_normals(table, tri_ids, tris[:, 0], shape_b, pose_b, False)
        ends = _capsule_end_contacts(tris, normal, shape_b, pose_b)
        if ends is not None:
            return ends
    # a sphere, or a ridge under a capsule's middle: the center decides a wall's side
    normal = _outward_normals(table, tri_ids, tris[:, 0], shape_b, pose_b, True)
    if shape_b.kind == ShapeKind.SPHERE:
        return _sphere_triangle_contacts(tris, normal, center, shape_b.radius)
    fcl_normal = normal[np.argmax(depths)]
    return midpoint_contacts(mid, np.tile(fcl_normal, (len(mid), 1)), depths)


def _capsule_end_contacts(tris, normal, capsule, pose):
    """Contacts of a capsule's two end spheres (centers: the ends of its axis segment,
    :func:`contact_helpers.segment_in_body`) with the triangles, each the exact closest
    point (:func:`_sphere_triangle_contacts`); None when neither end touches."""
    rotation, position = pose
    start, end, radius = segment_in_body(capsule)
    found = [
        _sphere_triangle_contacts(tris, normal, rotation @ point + position, radius)
        for point in (start, end)
    ]
    found = [contact for contact in found if contact is not None]
    if not found:
        return None
    return tuple(np.concatenate(part) for part in zip(*found, strict=True))


def _outward_normals(table, tri_ids, origin, shape, pose, center_always_decides):
    """Unit normals ``(t, 3)`` of the triangles ``tri_ids`` (rows of the stage's
    :func:`contact_helpers.triangle_table`) through ``origin (t, 3)`` turned to their
    outward side for a round shape (:func:`contact_helpers.new_contact_side`: its center
    is the shape's center, its farthest points in front and behind lie one radius beyond
    the ends of its segment).

    With ``center_always_decides`` (a sphere; a capsule whose middle rests on a ridge) the
    center's side of a wall-like triangle is the outward side. Otherwise (a capsule's end
    spheres) the center decides only as for polyhedra, where it is level with the
    triangle (or the triangle is backed) or the plane passes clear of it
    (:func:`contact_helpers.center_decides`), else the front: a capsule lying across a
    platform's edge, its center 1.3 cm past the side face above the top, had that face
    turned towards its center, and the end hanging beyond the edge, pushed along it, went
    14.5 cm into the platform.
    """
    rotation, position = pose
    normal = table["normal"][tri_ids]
    start, end, radius = segment_in_body(shape)
    ends = np.stack([rotation @ start + position, rotation @ end + position])  # (2, 3)
    center = 0.5 * (ends[0] + ends[1])
    offset = (normal * origin).sum(axis=1)  # n . p0
    center_height = normal @ center - offset
    end_heights = normal @ ends.T - offset[:, None]  # (t, 2)
    max_height = end_heights.max(axis=1) + radius
    decides = center_always_decides
    if not center_always_decides:
        level = level_with(table, tri_ids, center[1])
        min_height = end_heights.min(axis=1) - radius
        decides = center_decides(level, center_height, max_height, min_height)
    return normal * new_contact_side(normal[:, 1], center_height, max_height, decides)[:, None]


def _barycentric_inside(tris, points, tolerance=settings.BARYCENTRIC_TOLERANCE):
    """(t,) bool: point ``points[i] (3,)`` projected into triangle ``tris[i] (3, 3)`` is inside."""
    e0, e1 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    d00, d01, d11 = (e0 * e0).sum(1), (e0 * e1).sum(1), (e1 * e1).sum(1)
    rel = points - tris[:, 0]
    d20, d21 = (rel * e0).sum(1), (rel * e1).sum(1)
    # barycentric (v, w) of the projection: solves [d00 d01; d01 d11] [v; w] = [d20; d21]
    denom = d00 * d11 - d01 * d01
    v = (d11 * d20 - d01 * d21) / denom
    w = (d00 * d21 - d01 * d20) / denom
    return (v >= -tolerance) & (w >= -tolerance) & (v + w <= 1 + tolerance)


def _sphere_triangle_contacts(tris, normal, center, radius):
    """Deepest sphere-triangle contact (closest point on the triangles to the center)."""
    closest = closest_points_on_triangles(tris, center)
    offset = center - closest
    distance = np.linalg.norm(offset, axis=1)
    best = int(np.argmin(distance))
    if distance[best] > radius + settings.STAGE_SPECULATIVE_DISTANCE:
        return None
    # a center in front of the outward side has an offset direction (exact, also at an
    # edge); one on or behind the plane is pushed out along the outward normal
    in_front = (offset[best] * normal[best]).sum() > settings.SPHERE_CENTER_ON_SURFACE
    n = offset[best] / distance[best] if in_front else normal[best]
    point_a = closest[best][None]
    point_b = (center - radius * n)[None]
    return point_a, point_b, n[None]


def closest_points_on_triangles(tris: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Closest point ``(t, 3)`` on each triangle ``(t, 3, 3)`` to one point ``(3,)``.

    Inside the prism: the plane projection; otherwise the closest of the three edge points
    (segment point ``a + clamp(((p - a).(b - a)) / |b - a|^2, 0, 1) (b - a)``).
    """
    e0, e1 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    n = cross(e0, e1)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), settings.TINY)
    projected = point - ((point - tris[:, 0]) * n).sum(axis=1)[:, None] * n
    inside = _barycentric_inside(tris, projected)
    best = projected.copy()
    best_dist = np.where(inside, np.linalg.norm(point - projected, axis=1), np.inf)
    for i, j in ((0, 1), (1, 2), (2, 0)):
        a, ab = tris[:, i], tris[:, j] - tris[:, i]
        s = np.clip(((point - a) * ab).sum(1) / np.maximum((ab * ab).sum(1), settings.TINY), 0, 1)
        candidate = a + s[:, None] * ab
        dist = np.linalg.norm(point - candidate, axis=1)
        better = (dist < best_dist) & ~inside
        best[better], best_dist[better] = candidate[better], dist[better]
    return best
