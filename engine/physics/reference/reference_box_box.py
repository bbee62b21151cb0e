"""Reference path of :mod:`box_box`: analytic contacts of one box pair, in plain loops.

The same separating-axis test and face clipping as the batched module (whose docstring
gives the equations), written for a single pair the way box2d-lite's ``Collide`` is: 15
axes in a loop, the incident face's corners clipped against the reference rectangle one
candidate at a time. ``SolverSettings.use_vectorized = False`` routes box pairs here;
tests prove both paths give the same contacts.

A box is ``(center (3,), axes (3, 3), half (3,))`` in the world, ``axes[k]`` its k-th unit
axis (a row; the columns of the shape's world rotation).
"""

from __future__ import annotations

import math

import numpy as np

from ..core import settings
from ..core.reference_geometry import Contact, cross3, dot

#: the reference rectangle's corners in units of its half extents, counter-clockwise.
CORNER_SIGNS = ((1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0))
#: clipping candidates per face pair and the first edge feature (``box_box``'s numbers)
FACE_CANDIDATES = 24
EDGE_FEATURE = 36 * FACE_CANDIDATES


def tie(value: float) -> float:
    """``value`` rounded to multiples of ``TIE_QUANTUM`` (:func:`contacts.tie_key`)."""
    return round(value / settings.TIE_QUANTUM) if math.isfinite(value) else value


def box_box_contacts_reference(box_a, box_b) -> list[Contact] | None:
    """Contacts of boxes ``box_a`` and ``box_b`` (normals A -> B), in candidate order; None
    for an overlap deeper than ``BOX_DEEP_OVERLAP`` (the caller's polyhedron path).

    Mirrors :func:`box_box.box_box_contacts` for one pair."""
    axes, separations, distances = separating_axes_reference(box_a, box_b)
    if max(separations) < -settings.BOX_DEEP_OVERLAP:
        return None
    if max(separations) > settings.SPECULATIVE_DISTANCE:
        return []
    axis = choose_axis_reference(separations)
    sign = 1.0 if distances[axis] >= 0.0 else -1.0
    normal = axes[axis] * sign
    if axis < 6:
        return face_contacts_reference(box_a, box_b, axis, normal)
    return edge_contact_reference(box_a, box_b, axis, normal)


def separating_axes_reference(box_a, box_b):
    """The 15 axes, their separations ``s(u)`` (-inf for parallel edges) and ``u . (c_b - c_a)``.

    Mirrors :func:`box_box.separating_axes`."""
    (center_a, axes_a, half_a), (center_b, axes_b, half_b) = box_a, box_b
    axes = [axes_a[k] for k in range(3)] + [axes_b[k] for k in range(3)]
    is_axis = [True] * 6
    for i in range(3):
        for j in range(3):
            edge = cross3(axes_a[i], axes_b[j])
            length = math.sqrt(dot(edge, edge))
            is_axis.append(length > settings.BOX_PARALLEL_EDGES)
            axes.append(edge / length if is_axis[-1] else edge)
    gap = center_b - center_a
    separations, distances = [], []
    for u, usable in zip(axes, is_axis, strict=True):
        radius_a = sum(half_a[k] * abs(dot(u, axes_a[k])) for k in range(3))
        radius_b = sum(half_b[k] * abs(dot(u, axes_b[k])) for k in range(3))
        distance = dot(u, gap)
        distances.append(distance)
        separations.append(abs(distance) - radius_a - radius_b if usable else -math.inf)
    return axes, separations, distances


def _first_best(values: list[float], start: int, stop: int) -> int:
    """Index in ``[start, stop)`` of the first largest ``tie(value)``."""
    keys = [tie(values[k]) for k in range(start, stop)]
    return start + keys.index(max(keys))


def choose_axis_reference(separations: list[float]) -> int:
    """A's best face; B's if clearly better; an edge if clearly better than that face.

    Mirrors :func:`box_box.choose_axis`."""
    rel, tol = settings.BOX_AXIS_RELATIVE, settings.BOX_AXIS_ABSOLUTE
    face = _first_best(separations, 0, 3)
    face_b = _first_best(separations, 3, 6)
    if tie(separations[face_b]) > tie(rel * separations[face] + tol):
        face = face_b
    edge = _first_best(separations, 6, 15)
    if tie(separations[edge]) > tie(rel * separations[face] + tol):
        return edge
    return face


def face_contacts_reference(box_a, box_b, axis: int, normal: np.ndarray) -> list[Contact]:
    """Clipped contacts of a face axis (0-2: a face of A, 3-5: of B).

    Mirrors ``box_box._face_contacts`` for one pair."""
    ref_is_a = axis < 3
    (center_r, axes_r, half_r), (center_i, axes_i, half_i) = (
        (box_a, box_b) if ref_is_a else (box_b, box_a)
    )
    n_ref = normal if ref_is_a else -normal  # out of the reference face, towards I
    i = axis % 3
    face_center = center_r + half_r[i] * n_ref
    k1, k2 = (i + 1) % 3, (i + 2) % 3
    tangent_u, tangent_v = axes_r[k1], axes_r[k2]
    extent = (half_r[k1], half_r[k2])
    # the incident face: most anti-parallel to n_ref, outward normal m
    alignment = [dot(axes_i[k], n_ref) for k in range(3)]
    j = _first_best([abs(value) for value in alignment], 0, 3)
    facing = alignment[j] >= 0.0  # the incident face is on I's -b_j side
    m = axes_i[j] * -(1.0 if facing else -1.0)
    face_code = 6 * axis + 2 * j + int(facing)  # the contacts' feature numbers (box_box)
    incident_center = center_i + m * half_i[j]
    j1, j2 = (j + 1) % 3, (j + 2) % 3
    side_1, side_2 = axes_i[j1] * half_i[j1], axes_i[j2] * half_i[j2]
    quad = []
    for s1, s2 in CORNER_SIGNS:
        corner = incident_center + s1 * side_1 + s2 * side_2
        relative = corner - face_center
        quad.append((dot(relative, tangent_u), dot(relative, tangent_v)))
    along = dot(m, n_ref)
    base = dot(m, incident_center - face_center)
    slope_u, slope_v = dot(m, tangent_u), dot(m, tangent_v)
    contacts: list[Contact] = []
    for k, (u, v) in enumerate(clip_candidates_reference(quad, extent)):
        if u is None:
            continue
        # t solves m . (p_ref + t n_ref - f) = 0 for p_ref = o + u U + v V on the reference
        # face; the point lies -t behind it
        t = (base - u * slope_u - v * slope_v) / along
        if -t > -settings.SPECULATIVE_DISTANCE:
            p_ref = face_center + u * tangent_u + v * tangent_v
            p_inc = p_ref + t * n_ref
            pair = (p_ref, p_inc) if ref_is_a else (p_inc, p_ref)
            feature = k + FACE_CANDIDATES * face_code
            contacts.append(Contact(pair[0], pair[1], normal, feature))
    return contacts


def clip_candidates_reference(quad: list, extent: tuple) -> list:
    """The 24 candidates ``(u, v)`` of :func:`box_box.clip_candidates`, ``(None, None)``
    where a candidate is not a corner of the overlap of the rectangle and ``quad`` (each
    corner is found once, see :mod:`box_box`)."""
    tol = settings.BOX_CLIP_TOLERANCE
    e_u, e_v = extent
    out = []
    grown = settings.SPECULATIVE_DISTANCE
    for u, v in quad:  # the quad's corners inside the rectangle grown by `grown`
        inside = abs(u) <= e_u + grown and abs(v) <= e_v + grown
        out.append((u, v) if inside else (None, None))
    edges = [
        (quad[(k + 1) % 4][0] - quad[k][0], quad[(k + 1) % 4][1] - quad[k][1]) for k in range(4)
    ]
    area = sum(quad[k][0] * quad[(k + 1) % 4][1] for k in range(4)) - sum(
        quad[k][1] * quad[(k + 1) % 4][0] for k in range(4)
    )
    orientation = 1.0 if area >= 0.0 else -1.0
    for s_u, s_v in CORNER_SIGNS:  # the rectangle's corners inside the quad
        r_u, r_v = s_u * e_u, s_v * e_v
        inside = all(
            (edges[k][0] * (r_v - quad[k][1]) - edges[k][1] * (r_u - quad[k][0])) * orientation
            >= -tol * math.sqrt(edges[k][0] ** 2 + edges[k][1] ** 2)
            for k in range(4)
        )
        # a rectangle corner on a counted quad corner is that corner already
        on_corner = any(
            out[k][0] is not None
            and (r_u - quad[k][0]) ** 2 + (r_v - quad[k][1]) ** 2
            < settings.BOX_DUPLICATE_DISTANCE**2
            for k in range(4)
        )
        out.append((r_u, r_v) if inside and not on_corner else (None, None))
    for k in range(4):  # quad edge k crossing the sides u = +-e_u, v = +-e_v
        for fixed, level in ((0, e_u), (0, -e_u), (1, e_v), (1, -e_v)):
            run = edges[k][fixed]
            if run == 0.0:
                out.append((None, None))
                continue
            s = (level - quad[k][fixed]) / run
            free = 1 - fixed
            free_value = quad[k][free] + s * edges[k][free]
            margin = tol / max(math.sqrt(edges[k][0] ** 2 + edges[k][1] ** 2), settings.TINY)
            # strictly inside both edges: a crossing at a corner is that corner
            if margin < s < 1.0 - margin and abs(free_value) < extent[free] - tol:
                out.append((level, free_value) if fixed == 0 else (free_value, level))
            else:
                out.append((None, None))
    return out


def edge_contact_reference(box_a, box_b, axis: int, normal: np.ndarray) -> list[Contact]:
    """The closest points of A's and B's supporting edges (one contact, or none).

    Mirrors ``box_box._edge_contacts`` for one pair."""
    (center_a, axes_a, half_a), (center_b, axes_b, half_b) = box_a, box_b
    i, j = (axis - 6) // 3, (axis - 6) % 3
    mid_a, mid_b = center_a.copy(), center_b.copy()
    for k in range(3):  # A's corner furthest along n, B's furthest along -n; edge axes free
        if k != i:
            mid_a = mid_a + axes_a[k] * (half_a[k] * (1.0 if dot(axes_a[k], normal) >= 0 else -1.0))
        if k != j:
            mid_b = mid_b - axes_b[k] * (half_b[k] * (1.0 if dot(axes_b[k], normal) >= 0 else -1.0))
    dir_a, dir_b = axes_a[i], axes_b[j]
    r = mid_a - mid_b
    b, c, f = dot(dir_a, dir_b), dot(dir_a, r), dot(dir_b, r)
    s = min(max((b * f - c) / (1.0 - b * b), -half_a[i]), half_a[i])
    t = min(max(f + s * b, -half_b[j]), half_b[j])
    s = min(max(t * b - c, -half_a[i]), half_a[i])
    contact = Contact(mid_a + s * dir_a, mid_b + t * dir_b, normal, EDGE_FEATURE + axis)
    return [contact] if contact.depth > -settings.SPECULATIVE_DISTANCE else []
