r"""Where a hull crosses the stage: a vertex's way out of a triangle, and faces crossed.

**A vertex's way out.** A hull vertex ``x`` behind a stage triangle ``t`` (signed height
``h < 0`` along its outward normal ``n_t``, inside its prism) rests on it only when the
segment from ``x`` to its foot ``f = x - h n_t`` on the triangle stays inside the stage's
solid, i.e. crosses no other stage triangle: a vertex 2.3 cm below a 4 cm table top is in
the prism of the top face, 6.3 cm behind it, but its way up to the top passes the slab's
bottom face first; it is outside the solid, and pushing it up to the top would pull the
body through the slab. The segment crosses triangle ``s`` (unit normal ``n_s``) when its
ends lie strictly on opposite sides of the plane, with the vertex's height ``d_0 = h_s``
above ``s`` and the foot's

.. math::

    d_1 = n_s \cdot (f - p_s) = h_s - h_t \, (n_s \cdot n_t), \qquad
    d_0 d_1 < 0, \; |d_0|, |d_1| > \varepsilon,

(``STAGE_CROSSING_TOLERANCE``: a plane through the foot, a floor's neighbour or the front
face at the edge of a slab's top, is no crossing), and the crossing point
``x - (d_0 / (d_0 - d_1)) h_t n_t`` lies inside ``s`` (barycentric test, Ericson 3.4).
Both heights and the normals' products are the rule's own arrays, so the test costs a
few operations on ``(k, T)`` arrays for the ``k`` passed candidates against the job's ``T``
triangles (those near the body: a segment to a floor-like or wall-like triangle near the
body stays within the body's box grown by the probe's reach, so the triangles it crosses
are among them). A stage lying in one plane (a floor) has nothing to cross: skipped.

**Faces crossed.** :func:`crossed_faces`: a triangle the hull cuts where no vertex rests on
it (a thin slab's side across a cone lying on the floor), whose fcl points
:func:`crossed_face_points` turns into contacts with the triangle's normal.

References: :mod:`reference.reference_crossings` (``way_out_crossed_reference``,
``crossed_faces_reference``).
"""

from __future__ import annotations

import numpy as np

from ..core import settings
from ..core.reference_geometry import dot as dot3
from ..core.vectors import dot


def ways_out_crossed(table, ids, tris, passed, normal, height, alignment, verts) -> np.ndarray:
    """(g, T, V) bool: the ``passed (g, T, V)`` vertex-triangle candidates (``h < 0``) whose
    way out crosses another of the job's triangles (see the module docstring); ``ids (g,
    T)`` the triangles, ``tris (g, T, 3, 3)`` their corners, ``normal (g, T, 3)`` and
    ``height (g, T, V)`` as turned outward, ``alignment (g, T, T)``: ``n_t . n_s``,
    ``verts (g, V, 3)`` the hull's world vertices."""
    g, t, v = np.nonzero(passed)
    crossed = np.zeros(passed.shape, dtype=bool)
    if len(g) == 0:
        return crossed
    h = height[g, t, v]  # (k,)
    d0 = height[g, :, v]  # the vertex above every triangle s, (k, T)
    d1 = d0 - h[:, None] * alignment[g, t]  # its foot on t above s
    tolerance = settings.STAGE_CROSSING_TOLERANCE
    strict = (d0 * d1 < 0) & (np.abs(d0) > tolerance) & (np.abs(d1) > tolerance)
    strict &= ids[g] != ids[g, t][:, None]  # not its own triangle
    step = (d0 / np.where(strict, d0 - d1, 1.0)) * h[:, None]  # x - step n_t crosses s
    point = verts[g, v][:, None] - step[..., None] * normal[g, t][:, None]  # (k, T, 3)
    crossed[g, t, v] = (strict & _inside(table, ids[g], tris[g, :, 0], point)).any(axis=1)
    return crossed


def _inside(table: dict, ids: np.ndarray, corner: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Bool, ``point (..., 3)`` projects inside triangle ``ids (...)`` whose corner 0 is
    ``corner (..., 3)`` (barycentric, within ``BARYCENTRIC_TOLERANCE``)."""
    relative = point - corner
    d20, d21 = dot(relative, table["e0"][ids]), dot(relative, table["e1"][ids])
    d00, d01, d11, denom = (table[key][ids] for key in ("d00", "d01", "d11", "denom"))
    v = (d11 * d20 - d01 * d21) / denom
    w = (d00 * d21 - d01 * d20) / denom
    tolerance = settings.BARYCENTRIC_TOLERANCE
    return (v >= -tolerance) & (w >= -tolerance) & (v + w <= 1 + tolerance)


def crossed_faces(candidate, best, corner, second, alignment, height) -> np.ndarray:
    """(g, T) bool: the triangles each hull crosses where no vertex rests on them, in jobs
    with vertex contacts (``candidate (g, T, V)``, resting triangles ``best (g, V)``,
    corner contacts ``corner (g, T, V)`` on ``second (g, V)``; ``alignment (g, T, T)`` the
    outward normals' products ``n_t . n_s`` and heights ``height (g, T, V)``, see
    :func:`batched_stage._stage_group`).

    A vertex behind triangle t's plane is *loose* for t when it holds no contact on a
    triangle facing t's way (``|n_s . n_t| >= STAGE_CORNER_COSINE``). Triangle t is
    crossed when a vertex lies in front of its plane and a loose one behind it, deeper
    than every vertex behind it that is held: a thin slab's side cutting a cone that rests
    on the floor, its rim vertices above and below the slab behind the side's plane and
    held by the floor or by nothing. Vertices resting on a floor are behind the floor's
    plane and its neighbours' but held by them; a box resting on a slab's top and
    overhanging its edge has its vertices in the air as deep behind the top's plane as
    those held on it: neither is crossed.
    Reference: :func:`reference_crossings.crossed_faces_reference`."""
    holds = np.zeros(height.shape, dtype=bool)  # triangle s holds a contact of vertex v
    g, v = np.nonzero(candidate.any(axis=1))
    holds[g, best[g, v], v] = True
    g, v = np.nonzero(corner.any(axis=1))
    holds[g, second[g, v], v] = True
    # triangles s facing t's way, |n_t . n_s| >= cos 45, (g, T, T); then the vertices held
    # by one of them: a boolean matrix product, (g, T, V)
    facing = np.abs(alignment) >= settings.STAGE_CORNER_COSINE
    held = facing @ holds
    behind = height < 0
    loose = np.where(behind & ~held, -height, 0.0).max(axis=2)  # the deepest loose, (g, T)
    kept = np.where(behind & held, -height, 0.0).max(axis=2)  # the deepest held
    contacted = np.asarray(holds.any(axis=(1, 2)))  # jobs with a vertex contact, (g,)
    return (loose > kept) & (height.max(axis=2) > 0) & contacted[:, None]


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
