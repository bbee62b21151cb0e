r"""Whether a segment crosses a stage triangle: the vertex-to-foot test of the stage-hull rule.

A hull vertex ``x`` behind a stage triangle ``t`` (signed height ``h < 0`` along its
outward normal ``n_t``, inside its prism) rests on it only when the segment from ``x`` to
its foot ``f = x - h n_t`` on the triangle stays inside the stage's solid, i.e. crosses no
other stage triangle: a vertex 2.3 cm below a 4 cm table top is in the prism of the top
face, 6.3 cm behind it, but its way up to the top passes the slab's bottom face first; it
is outside the solid, and pushing it up to the top would pull the body through the slab.

The segment ``x -> f`` crosses triangle ``s`` (unit normal ``n_s``, corner ``p_s``) when its
ends lie strictly on opposite sides of the plane,

.. math::

    d_0 = n_s \cdot (x - p_s), \quad d_1 = n_s \cdot (f - p_s), \quad
    d_0 d_1 < 0, \; |d_0|, |d_1| > \varepsilon,

and the crossing point ``x + d_0 / (d_0 - d_1) (f - x)`` lies inside ``s`` (barycentric
test, Ericson 3.4). A plane through either end (``|d| <= STAGE_CROSSING_TOLERANCE``) is no
crossing: the triangles sharing the foot's plane (a floor's neighbours) or its edge (the
foot on the edge of a slab's top is on the front face's plane too) never count.

Cost: only the triangles whose boxes overlap the segment's box are tested, found in the
stage grid (:mod:`stage_grid`) in one query for every segment of the step; a vertex has few
passed triangles, and a segment is short (at most ``STAGE_BELOW_FRACTION`` of the hull's
extent), so each meets a handful of triangles.
Reference: :func:`segment_crosses_stage_reference` (one segment, all triangles).
"""

from __future__ import annotations

import numpy as np

from ..core import settings
from ..core.reference_geometry import dot as dot3
from ..core.vectors import dot
from .contact_helpers import triangle_table
from .stage_grid import candidate_triangles_reference, stage_grid


def segments_cross_stage(
    mesh_shape, start: np.ndarray, end: np.ndarray, own: np.ndarray
) -> np.ndarray:
    """(k,) bool: segment ``start[i] -> end[i]`` (``(k, 3)``, world, m) crosses a triangle
    of the stage ``mesh_shape`` other than ``own[i]`` (its foot's triangle)."""
    tolerance = settings.STAGE_CROSSING_TOLERANCE
    lo = np.minimum(start, end) - tolerance
    hi = np.maximum(start, end) + tolerance
    segment, tri = stage_grid(mesh_shape).candidates(lo, hi)
    other = tri != own[segment]
    segment, tri = segment[other], tri[other]
    table = triangle_table(mesh_shape)
    normal, corner = table["normal"][tri], mesh_shape.ray_triangles[tri, 0]
    d0 = dot(normal, start[segment] - corner)  # signed distances of both ends, (e,)
    d1 = dot(normal, end[segment] - corner)
    strict = (d0 * d1 < 0) & (np.abs(d0) > tolerance) & (np.abs(d1) > tolerance)
    fraction = d0 / np.where(strict, d0 - d1, 1.0)
    point = start[segment] + fraction[:, None] * (end[segment] - start[segment])
    hit = strict & _inside(table, tri, point - corner)
    return np.bincount(segment[hit], minlength=len(start)) > 0


def _inside(table: dict, tri: np.ndarray, relative: np.ndarray) -> np.ndarray:
    """(e,) bool: points ``relative (e, 3)`` to their triangle's corner 0 project inside
    triangle ``tri (e,)`` (barycentric, within ``BARYCENTRIC_TOLERANCE``)."""
    d20, d21 = dot(relative, table["e0"][tri]), dot(relative, table["e1"][tri])
    d00, d01, d11, denom = (table[key][tri] for key in ("d00", "d01", "d11", "denom"))
    v = (d11 * d20 - d01 * d21) / denom
    w = (d00 * d21 - d01 * d20) / denom
    tolerance = settings.BARYCENTRIC_TOLERANCE
    return (v >= -tolerance) & (w >= -tolerance) & (v + w <= 1 + tolerance)


def segment_crosses_stage_reference(
    mesh_shape, start: np.ndarray, end: np.ndarray, own: int
) -> bool:
    """Plain version of :func:`segments_cross_stage` for one segment ``start -> end``
    (``(3,)`` each): every triangle whose box overlaps the segment's, one at a time."""
    tolerance = settings.STAGE_CROSSING_TOLERANCE
    lo = np.minimum(start, end) - tolerance
    hi = np.maximum(start, end) + tolerance
    table = triangle_table(mesh_shape)
    for s in candidate_triangles_reference(mesh_shape.ray_triangles, lo[None], hi[None])[0]:
        if s == own:
            continue
        normal, corner = table["normal"][s], mesh_shape.ray_triangles[s][0]
        d0, d1 = dot3(normal, start - corner), dot3(normal, end - corner)
        if not (d0 * d1 < 0 and abs(d0) > tolerance and abs(d1) > tolerance):
            continue
        point = start + (d0 / (d0 - d1)) * (end - start)
        relative = point - corner
        d20, d21 = dot3(relative, table["e0"][s]), dot3(relative, table["e1"][s])
        d00, d01, d11, denom = (table[key][s] for key in ("d00", "d01", "d11", "denom"))
        v = (d11 * d20 - d01 * d21) / denom
        w = (d00 * d21 - d01 * d20) / denom
        barycentric = settings.BARYCENTRIC_TOLERANCE
        if v >= -barycentric and w >= -barycentric and v + w <= 1 + barycentric:
            return True
    return False


def crossed_faces(candidate, best, corner, second, normal, height) -> np.ndarray:
    """(g, T) bool: the triangles each hull crosses where no vertex rests on them, in jobs
    with vertex contacts (``candidate (g, T, V)``, resting triangles ``best (g, V)``,
    corner contacts ``corner (g, T, V)`` on ``second (g, V)``; outward ``normal (g, T,
    3)`` and heights ``height (g, T, V)``, see :func:`batched_stage._stage_group`).

    A vertex behind triangle t's plane is *loose* for t when it holds no contact on a
    triangle facing t's way (``|n_s . n_t| >= STAGE_CORNER_COSINE``). Triangle t is
    crossed when a vertex lies in front of its plane and a loose one behind it, deeper
    than every vertex behind it that is held: a thin slab's side cutting a cone that rests
    on the floor, its rim vertices above and below the slab behind the side's plane and
    held by the floor or by nothing. Vertices resting on a floor are behind the floor's
    plane and its neighbours' but held by them; a box resting on a slab's top and
    overhanging its edge has its vertices in the air as deep behind the top's plane as
    those held on it: neither is crossed.
    Reference: :func:`crossed_faces_reference`."""
    holds = np.zeros(height.shape, dtype=bool)  # triangle s holds a contact of vertex v
    g, v = np.nonzero(candidate.any(axis=1))
    holds[g, best[g, v], v] = True
    g, v = np.nonzero(corner.any(axis=1))
    holds[g, second[g, v], v] = True
    # triangles s facing t's way, |n_t . n_s| >= cos 45, (g, T, T); then the vertices held
    # by one of them: a boolean matrix product, (g, T, V)
    facing = np.abs(np.einsum("gti,gsi->gts", normal, normal)) >= settings.STAGE_CORNER_COSINE
    held = facing @ holds
    behind = height < 0
    loose = np.where(behind & ~held, -height, 0.0).max(axis=2)  # the deepest loose, (g, T)
    kept = np.where(behind & held, -height, 0.0).max(axis=2)  # the deepest held
    contacted = np.asarray(holds.any(axis=(1, 2)))  # jobs with a vertex contact, (g,)
    return (loose > kept) & (height.max(axis=2) > 0) & contacted[:, None]


def crossed_faces_reference(holding: list[list[int]], normals: list, heights: list) -> list[int]:
    """Plain version of :func:`crossed_faces` for one job: the positions of its crossed
    triangles, given ``holding[k]``, the positions of the triangles holding vertex k's
    contacts, and every triangle's outward normal and vertex heights."""
    if not any(holding):
        return []
    crossed = []
    for i, (normal, height) in enumerate(zip(normals, heights, strict=True)):
        loose, kept = 0.0, 0.0  # the deepest loose and held vertices behind the plane
        for k, positions in enumerate(holding):
            if height[k] >= 0:
                continue
            facing = any(
                abs(dot3(normal, normals[j])) >= settings.STAGE_CORNER_COSINE for j in positions
            )
            if facing:
                kept = max(kept, -height[k])
            else:
                loose = max(loose, -height[k])
        if loose > kept and max(height) > 0:
            crossed.append(i)
    return crossed


def crossed_face_points(records: list, faces: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Contacts ``(point_a, point_b, normal)`` (``(k, 3)`` each) of fcl's probe ``records``
    on crossed triangles ``faces = {id: (outward normal (3,), least vertex height)}``, both
    paths: a record on such a triangle whose fcl normal lies within 60 degrees of the
    triangle's (``STAGE_CROSSED_FACE_ALIGNMENT``; the way out is through the face) takes
    the triangle's normal, its depth turned from the probe's into the shape's and at most
    the hull's deepest vertex behind the plane (as the edge-crossing fallback's)."""
    point_a, point_b, normals = [], [], []
    for record in records:
        face = faces.get(int(record.b1))
        if face is None:
            continue
        normal, least_height = face
        if abs(dot3(np.asarray(record.normal, dtype=np.float64), normal)) < (
            settings.STAGE_CROSSED_FACE_ALIGNMENT
        ):
            continue
        depth = abs(record.penetration_depth) - settings.STAGE_SPECULATIVE_DISTANCE
        depth = min(depth, -least_height)
        middle = np.asarray(record.pos, dtype=np.float64)
        point_a.append(middle + 0.5 * depth * normal)
        point_b.append(middle - 0.5 * depth * normal)
        normals.append(normal)
    if not normals:
        empty = np.zeros((0, 3))
        return empty, empty, empty
    return np.array(point_a), np.array(point_b), np.array(normals)
