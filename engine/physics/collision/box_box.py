"""Analytic box-box contacts for all pairs at once: separating axes, then clipping.

Two boxes (centers ``c``, axes the columns of ``R``, half extents ``e``) are apart when
some axis separates their projections (the separating axis theorem). For boxes 15 axes
suffice: the 3 face normals of A, the 3 of B and the 9 cross products ``a_i x b_j`` of
their edges (Gottschalk et al., OBBTree 1996; Ericson, *Real-Time Collision Detection*
4.4.1). Along a unit axis ``u`` the separation is ::

    s(u) = |u . (c_b - c_a)| - sum_k e_a,k |u . a_k| - sum_k e_b,k |u . b_k|,

positive for a gap, negative for an overlap of depth -s. The axis with the largest
separation is the contact normal (from A to B); as in box2d-lite's ``Collide``, faces win
near-ties (``BOX_AXIS_RELATIVE``, ``BOX_AXIS_ABSOLUTE``), first A's, then B's, and an edge
axis is taken only when it is clearly better. The pair has contacts when that separation
is below ``SPECULATIVE_DISTANCE`` (speculative contacts). A pair overlapping by more than
``BOX_DEEP_OVERLAP`` (bodies created inside each other) is left to the general polyhedron
path (fcl's normal and vertex contacts, :mod:`narrow_phase`), whose rules for such
overlaps are tested to push piles apart without driving the lowest bodies into the floor.

* **Face axis** (box2d-lite's clipping, in 3D): the chosen face of the *reference* box,
  a rectangle, and the face of the other (*incident*) box most anti-parallel to it, a
  quadrilateral. In the reference face's 2D frame the contact region is the overlap of
  the rectangle and the projected quadrilateral, and its corners are the contact points:
  the quad's corners inside the rectangle, the rectangle's corners inside the quad and
  the crossings of their edges (24 candidates, fixed, so every pair is the same array
  work; Sutherland-Hodgman clipping yields the same polygon). Each corner is carried
  along the normal onto the incident face: depth = how far that point lies behind the
  reference face. Points deeper than ``-SPECULATIVE_DISTANCE`` are kept. The quad's
  corners count up to ``SPECULATIVE_DISTANCE`` outside the rectangle (as the vertex
  contacts' grown hull planes do): a box resting a few mm off the edge of the one below
  keeps its four corners, and a stack of such boxes stands straight (measured: top drift
  0.8 mm with the grown rectangle, 11 mm without). Each corner is
  found once: the quad's corners count on the rectangle's boundary, the rectangle's
  corners unless they sit on a counted quad corner (a perfectly aligned stack), the edge
  crossings only strictly inside both edges.
* **Edge axis**: one point, the closest points of the two supporting edges (Ericson 5.1.9).

Every contact has a *feature number* naming the features it comes from (Box2D v3's
contact ids), the same at the same features in the next step: a face contact's candidate
index ``k`` (0-23) plus ``FACE_CANDIDATES`` times the face code ``6 axis + 2 j + f`` (the
reference face's axis, the incident face's axis ``j`` and side ``f``); an edge contact
``EDGE_FEATURE + axis``. The feature-keyed manifolds (:mod:`keyed_manifolds`) match
last step's warm start by it.

Contacts come back flat (pair index, candidate index, ``point_a``, ``point_b``, ``normal``,
``depth = (point_a - point_b) . normal``) in pair order, then candidate order: the order
of the per-pair reference :func:`reference_box_box.box_box_contacts_reference`, which this
module must agree with (tested, and both are tested against fcl's normal and depth).
"""

from __future__ import annotations

import numpy as np

from ..core import settings
from ..core.vectors import vecdot
from .contacts import tie_key

#: the reference rectangle's corners (in units of its half extents), counter-clockwise,
#: and the incident quad's corners in the same order.
CORNER_SIGNS = np.array([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]])
#: index k+1 and k+2 (mod 3) of a 3-vector's components, for the cross products.
NEXT, AFTER = np.array([1, 2, 0]), np.array([2, 0, 1])
#: the next corner of a quad, k+1 (mod 4).
FOLLOWING = np.array([1, 2, 3, 0])
#: the other two axes of axis k: k + 1 and k + 2 (mod 3)
OTHER_AXES = np.array([[1, 2], [2, 0], [0, 1]])
#: a 2D vector times this is its left perpendicular: (x, y) -> (-y, x)
PERPENDICULAR = np.array([[0.0, 1.0], [-1.0, 0.0]])
#: clipping candidates per face pair, and the feature number of the first edge contact
#: (after every face code's candidates: 36 face codes)
FACE_CANDIDATES = 24
EDGE_FEATURE = 36 * FACE_CANDIDATES


def _apply(matrices: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """``M v`` for stacks ``(g, k, 3) x (g, 3) -> (g, k)``: row k of M dotted with v."""
    return (matrices @ vectors[:, :, None])[..., 0]


def box_shape_frames(rotation: np.ndarray, position: np.ndarray, body_from_shape: np.ndarray):
    """World centers ``(g, 3)`` and rotations ``(g, 3, 3)`` of box shapes: body poses
    ``(R, x)`` composed with the shapes' body-frame poses ``body_from_shape (g, 4, 4)``."""
    center = _apply(rotation, body_from_shape[:, :3, 3]) + position  # R t + x
    return center, rotation @ body_from_shape[:, :3, :3]


def separating_axes(center_a, rot_a, half_a, center_b, rot_b, half_b):
    """The 15 candidate axes ``(g, 15, 3)`` (unit; parallel edge pairs give zeros), their
    separations ``(g, 15)`` (-inf for no axis) and the signed projections ``u . (c_b - c_a)``.

    Reference: :func:`reference_box_box.separating_axes_reference`.
    """
    axes_a, axes_b = rot_a.swapaxes(-1, -2), rot_b.swapaxes(-1, -2)  # rows: box axes
    # a_i x b_j for every i, j, (g, 9, 3), then normalized where the edges are not parallel
    # (a x b)_k = a_{k+1} b_{k+2} - a_{k+2} b_{k+1}, written out (np.cross is slow on small arrays)
    a_1, a_2 = axes_a[:, :, None, NEXT], axes_a[:, :, None, AFTER]
    b_1, b_2 = axes_b[:, None, :, NEXT], axes_b[:, None, :, AFTER]
    edges = (a_1 * b_2 - a_2 * b_1).reshape(-1, 9, 3)
    length = np.sqrt(vecdot(edges, edges))
    is_axis = length > settings.BOX_PARALLEL_EDGES
    edges = edges / np.where(is_axis, length, 1.0)[..., None]
    axes = np.concatenate([axes_a, axes_b, edges], axis=1)
    # radii of the boxes along each axis: sum_k e_k |u . a_k|, (g, 15); (axes @ R)[u, k] = u . a_k
    radius_a = (np.abs(axes @ rot_a) @ half_a[:, :, None])[..., 0]
    radius_b = (np.abs(axes @ rot_b) @ half_b[:, :, None])[..., 0]
    distance = _apply(axes, center_b - center_a)  # u . (c_b - c_a), (g, 15)
    separation = np.abs(distance) - radius_a - radius_b
    separation[:, 6:] = np.where(is_axis, separation[:, 6:], -np.inf)
    return axes, separation, distance


def choose_axis(separation: np.ndarray) -> np.ndarray:
    """(g,) index of the contact axis: A's best face, B's if clearly better, then an edge
    only if clearly better than that face (box2d-lite's tolerances; ties to the first).

    Reference: :func:`reference_box_box.choose_axis_reference`.
    """
    rows = np.arange(len(separation))
    key = tie_key(separation)
    face_a = key[:, 0:3].argmax(axis=1)
    face_b = 3 + key[:, 3:6].argmax(axis=1)
    edge = 6 + key[:, 6:15].argmax(axis=1)
    rel, tol = settings.BOX_AXIS_RELATIVE, settings.BOX_AXIS_ABSOLUTE
    better_b = key[rows, face_b] > tie_key(rel * separation[rows, face_a] + tol)
    face = np.where(better_b, face_b, face_a)
    better_edge = key[rows, edge] > tie_key(rel * separation[rows, face] + tol)
    return np.where(better_edge, edge, face)


def box_box_contacts(center_a, rot_a, half_a, center_b, rot_b, half_b):
    """Contacts of ``g`` box pairs (centers ``(g, 3)``, rotations ``(g, 3, 3)`` whose columns
    are the box axes, half extents ``(g, 3)``), see the module docstring.

    Returns flat ``pair (q,)``, ``local (q,)`` (candidate index inside the pair),
    ``point_a, point_b, normal (q, 3)`` (normals from A to B) and ``deep (g,)``: pairs
    overlapping by more than ``BOX_DEEP_OVERLAP``, which get no contacts here.
    """
    parts, deep = box_box_parts(center_a, rot_a, half_a, center_b, rot_b, half_b)
    if len(parts) < 2:
        empty = np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64), *[np.zeros((0, 3))] * 3
        return *(parts[0][:5] if parts else empty), deep
    pair, local, point_a, point_b, normal, _ = (np.concatenate(p) for p in zip(*parts, strict=True))
    order = np.lexsort((local, pair))  # by pair, then by candidate
    return pair[order], local[order], point_a[order], point_b[order], normal[order], deep


def box_box_parts(center_a, rot_a, half_a, center_b, rot_b, half_b):
    """:func:`box_box_contacts` before its merge: ``parts``, a list of at most two
    ``(pair, local, point_a, point_b, normal, feature)`` tuples (the face pairs' contacts, the edge
    pairs'), each in (pair, candidate) order, no pair in both, and ``deep (g,)``. A caller
    that sorts all its contacts by (pair, candidate) anyway (the narrow phase's
    :class:`~pair_rules.ContactBatch`) takes the parts as they are and saves the merge
    (5 concatenations, a lexsort and 5 gathers, in most steps of a tumbling pile)."""
    axes, separation, distance = separating_axes(center_a, rot_a, half_a, center_b, rot_b, half_b)
    rows = np.arange(len(separation))
    axis = choose_axis(separation)
    # n = u sign(u . (c_b - c_a)): from A to B (+u when the centers coincide along u)
    sign = np.where(distance[rows, axis, None] >= 0.0, 1.0, -1.0)  # (g, 1)
    normal = axes[rows, axis] * sign
    deepest = separation.max(axis=1)  # the pair's separation (negative: overlap depth)
    deep = deepest < -settings.BOX_DEEP_OVERLAP
    close = (deepest <= settings.SPECULATIVE_DISTANCE) & ~deep
    frames = (center_a, rot_a, half_a, center_b, rot_b, half_b)
    face_pairs = np.flatnonzero(close & (axis < 6))
    edge_pairs = np.flatnonzero(close & (axis >= 6))
    parts = []  # each already in (pair, candidate) order
    if len(face_pairs):
        parts.append(_face_contacts(face_pairs, axis[face_pairs], normal[face_pairs], frames))
    if len(edge_pairs):
        parts.append(_edge_contacts(edge_pairs, axis[edge_pairs], normal[edge_pairs], frames))
    return parts, deep


def _face_contacts(pairs, axis, normal, frames):
    """Clipped face contacts of ``pairs`` whose axis is a face of A (0-2) or B (3-5).

    Reference: :func:`reference_box_box.face_contacts_reference`."""
    center_a, rot_a, half_a, center_b, rot_b, half_b = (f[pairs] for f in frames)
    g = np.arange(len(pairs))
    ref_is_a = axis < 3
    pick = ref_is_a[:, None]
    # reference box R and incident box I
    center_r, center_i = np.where(pick, center_a, center_b), np.where(pick, center_b, center_a)
    half_r, half_i = np.where(pick, half_a, half_b), np.where(pick, half_b, half_a)
    pick_matrix = pick[..., None]
    axes_r = np.where(pick_matrix, rot_a, rot_b).swapaxes(-1, -2)  # rows: box axes
    axes_i = np.where(pick_matrix, rot_b, rot_a).swapaxes(-1, -2)
    n_ref = np.where(pick, normal, -normal)  # out of the reference face, towards I
    i = axis % 3
    face_center = center_r + half_r[g, i, None] * n_ref
    # the reference rectangle: its axes U, V (rows of tangents) and half sizes
    g_column = g[:, None]
    in_face = OTHER_AXES[i]  # (g, 2): i + 1, i + 2 (mod 3)
    tangents, extent = axes_r[g_column, in_face], half_r[g_column, in_face]  # (g, 2, 3), (g, 2)
    # incident face: the face of I most anti-parallel to n_ref, outward normal m
    alignment = _apply(axes_i, n_ref)  # b_k . n_ref
    j = tie_key(np.abs(alignment)).argmax(axis=1)
    facing = alignment[g, j] >= 0.0  # the incident face is on I's -b_j side
    m = np.where(facing, -1.0, 1.0)[:, None] * axes_i[g, j]
    offset = center_i + half_i[g, j, None] * m - face_center  # f - o, incident face center
    # its corners f + s1 A1 + s2 A2 in CORNER_SIGNS order, relative to o, (g, 4, 3), with
    # the half sides A1, A2 (rows of sides) along axes j + 1, j + 2 of I
    across = OTHER_AXES[j]
    sides = axes_i[g_column, across] * half_i[g_column, across, None]
    corners = offset[:, None] + CORNER_SIGNS @ sides
    quad = corners @ tangents.swapaxes(-1, -2)  # (g, 4, 2) in the reference face's 2D frame
    uv, valid = clip_candidates(quad, extent)
    # the incident face plane m . x = m . f seen from p_ref = o + u U + v V along n_ref:
    # p_inc = p_ref + t n_ref with t = (m . (f - o) - u m . U - v m . V) / (m . n_ref);
    # the point lies -t behind the reference face (its depth)
    along = vecdot(m, n_ref)  # m . n_ref, at most -1/sqrt(3)
    base = vecdot(m, offset)
    slope = _apply(tangents, m)  # (g, 2): m . U, m . V
    t = (base[:, None] - (uv @ slope[:, :, None])[..., 0]) / along[:, None]
    valid &= t < settings.SPECULATIVE_DISTANCE  # -t > -SPECULATIVE_DISTANCE
    k_g, k_c = np.nonzero(valid)
    p_ref = face_center[k_g] + (uv[k_g, k_c, None] @ tangents[k_g])[:, 0]  # o + u U + v V
    p_inc = p_ref + t[k_g, k_c, None] * n_ref[k_g]
    ref_is_a_k = pick[k_g]
    point_a = np.where(ref_is_a_k, p_ref, p_inc)
    point_b = np.where(ref_is_a_k, p_inc, p_ref)
    face_code = 6 * axis + 2 * j + facing  # reference face, incident face and its side
    feature = k_c + FACE_CANDIDATES * face_code[k_g]
    return pairs[k_g], k_c, point_a, point_b, normal[k_g], feature


def clip_candidates(quad: np.ndarray, extent: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The corners of (rectangle ``|u| <= e_u, |v| <= e_v``) and (convex ``quad (g, 4, 2)``):
    ``uv (g, 24, 2)`` candidates and ``valid (g, 24)`` (see the module docstring's order).

    Reference: :func:`reference_box_box.clip_candidates_reference`."""
    tol = settings.BOX_CLIP_TOLERANCE
    g = len(quad)
    # 0-3: the quad's corners inside the rectangle grown by SPECULATIVE_DISTANCE
    extent_row = extent[:, None]  # (g, 1, 2)
    grown = extent_row + settings.SPECULATIVE_DISTANCE
    quad_inside = (np.abs(quad) <= grown).all(axis=2)
    # 4-7: the rectangle's corners inside the quad: on the inner side of its 4 edges
    rect = CORNER_SIGNS * extent_row  # (g, 4, 2)
    following = quad[:, FOLLOWING]  # q_{k+1}
    edge = following - quad  # q_{k+1} - q_k, (g, 4, 2)
    # twice the quad's signed area: its orientation (+1 counter-clockwise)
    area = vecdot(quad[..., 0], following[..., 1]) - vecdot(quad[..., 1], following[..., 0])
    orientation = np.where(area >= 0.0, 1.0, -1.0)
    to_corner = rect[:, :, None] - quad[:, None]  # r_c - q_k, (g, 4 corners, 4 edges, 2)
    # 2D cross product e_k x (r_c - q_k) = (r_c - q_k) . perp(e_k), times the orientation
    # (the same products and sum as e_x r_y - e_y r_x), (g, 4, 4)
    inward = (edge @ PERPENDICULAR) * orientation[:, None, None]
    cross = vecdot(to_corner, inward[:, None])
    edge_length = np.sqrt(vecdot(edge, edge))
    rect_inside = (cross >= -tol * edge_length[:, None]).all(axis=2)
    # a rectangle corner on a kept quad corner is that corner already (an aligned stack)
    on_corner = vecdot(to_corner, to_corner) < settings.BOX_DUPLICATE_DISTANCE**2
    rect_inside &= ~(on_corner & quad_inside[:, None, :]).any(axis=2)
    # 8-23: edge k of the quad crossing side s of the rectangle (u = +-e_u, v = +-e_v)
    crossing, crossing_valid = _edge_crossings(quad, edge, edge_length, extent)
    uv = np.concatenate([quad, rect, crossing.reshape(g, 16, 2)], axis=1)
    valid = np.concatenate([quad_inside, rect_inside, crossing_valid.reshape(g, 16)], axis=1)
    return uv, valid


#: rectangle side s (u = +e_u, u = -e_u, v = +e_v, v = -e_v) fixes coordinate SIDE_FIXED[s]
#: at SIDE_SIGN[s] times its extent; SIDE_FREE[s] is the other coordinate
SIDE_FIXED, SIDE_FREE = np.array([0, 0, 1, 1]), np.array([1, 1, 0, 0])
SIDE_SIGN = np.array([1.0, -1.0, 1.0, -1.0])
#: the sides fixing u (s = 0, 1) and those fixing v (s = 2, 3)
FIXES_U, FIXES_V = SIDE_FIXED == 0, SIDE_FIXED == 1


def _edge_crossings(quad, edge, edge_length, extent):
    """Points ``(g, 4, 4, 2)`` where quad edge k crosses rectangle side s (u = +e_u, u = -e_u,
    v = +e_v, v = -e_v) strictly inside both (``(g, 4, 4)`` bool): a crossing at a corner
    of either is that corner, counted once by the corner tests."""
    tol = settings.BOX_CLIP_TOLERANCE
    # side s fixes coordinate SIDE_FIXED[s] at `level`; the other must be within extent
    level = SIDE_SIGN * extent[:, SIDE_FIXED]  # (g, 4)
    start = quad[:, :, SIDE_FIXED]  # q_k's fixed coordinate, (g, 4 edges, 4 sides)
    run = edge[:, :, SIDE_FIXED]
    parallel = run == 0.0
    # q_k + s e_k reaches the side at s = (level - q_k) / e_k
    s = (level[:, None] - start) / np.where(parallel, 1.0, run)
    free_value = quad[:, :, SIDE_FREE] + s * edge[:, :, SIDE_FREE]  # the other coordinate
    margin = tol / np.maximum(edge_length, settings.TINY)[..., None]  # tol as a fraction of e_k
    valid = (
        ~parallel
        & (s > margin)
        & (s < 1.0 - margin)
        & (np.abs(free_value) < extent[:, None, SIDE_FREE] - tol)
    )
    # the point (u, v): the fixed coordinate exactly on the side, the free one where it crosses
    on_side = level[:, None]
    point = np.stack(
        [np.where(FIXES_U, on_side, free_value), np.where(FIXES_V, on_side, free_value)], axis=3
    )
    return point, valid


def _edge_contacts(pairs, axis, normal, frames):
    """One point per edge-edge pair: the closest points of A's and B's supporting edges.

    Reference: :func:`reference_box_box.edge_contact_reference`."""
    center_a, rot_a, half_a, center_b, rot_b, half_b = (f[pairs] for f in frames)
    g = np.arange(len(pairs))
    i, j = np.divmod(axis - 6, 3)  # edge axis 6 + 3 i + j is a_i x b_j
    axes_a, axes_b = rot_a.swapaxes(-1, -2), rot_b.swapaxes(-1, -2)
    # A's edge: its corner furthest along n, with the coordinate along a_i set to 0
    weight_a = half_a * np.where(_apply(axes_a, normal) >= 0.0, 1.0, -1.0)
    weight_a[g, i] = 0.0
    mid_a = center_a + (weight_a[:, None] @ axes_a)[:, 0]  # c + sum_k w_k a_k
    # B's edge: its corner furthest along -n, the coordinate along b_j set to 0
    weight_b = half_b * np.where(_apply(axes_b, normal) >= 0.0, 1.0, -1.0)
    weight_b[g, j] = 0.0
    mid_b = center_b - (weight_b[:, None] @ axes_b)[:, 0]
    dir_a, dir_b = axes_a[g, i], axes_b[g, j]
    # closest points of the lines mid_a + s d_a, mid_b + t d_b (unit d), clamped to the edges
    r = mid_a - mid_b
    b, c, f = vecdot(dir_a, dir_b), vecdot(dir_a, r), vecdot(dir_b, r)
    length_a, length_b = half_a[g, i], half_b[g, j]
    low_a = -length_a
    s = np.clip((b * f - c) / (1.0 - b * b), low_a, length_a)
    t = np.clip(f + s * b, -length_b, length_b)
    s = np.clip(t * b - c, low_a, length_a)
    point_a = mid_a + s[:, None] * dir_a
    point_b = mid_b + t[:, None] * dir_b
    keep = vecdot(point_a - point_b, normal) > -settings.SPECULATIVE_DISTANCE
    k = np.flatnonzero(keep)
    local = np.zeros(len(k), dtype=np.int64)
    return pairs[k], local, point_a[k], point_b[k], normal[k], EDGE_FEATURE + axis[k]
