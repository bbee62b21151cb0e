"""Plain twins of :mod:`collision.stage_crossings`, one vertex or one triangle at a time.

A vertex's way out (:func:`way_out_crossed_reference`, batched
``stage_crossings.ways_out_crossed``) and the faces a hull crosses where no vertex rests
(:func:`crossed_faces_reference`, batched ``stage_crossings.crossed_faces``), with the
barycentric prism test both they and :mod:`reference_pairs` use
(:func:`inside_triangle_prism`). The rules and their derivation are in
:mod:`collision.stage_crossings`.
"""

from __future__ import annotations

import numpy as np

from ..core import settings
from ..core.reference_geometry import dot


def inside_triangle_prism(table: dict, t: int, corner: np.ndarray, point: np.ndarray) -> bool:
    """True when ``point`` projected on triangle t's plane lies inside the triangle.

    Barycentric ``(v, w)`` solve ``[d00 d01; d01 d11] [v; w] = [d20; d21]`` with the Gram
    entries of the edges e0, e1 from ``corner`` (Ericson 3.4); inside when ``v, w >= 0`` and
    ``v + w <= 1`` (within ``BARYCENTRIC_TOLERANCE``).
    """
    relative = point - corner
    d20, d21 = dot(relative, table["e0"][t]), dot(relative, table["e1"][t])
    d00, d01, d11, denom = (table[key][t] for key in ("d00", "d01", "d11", "denom"))
    v = (d11 * d20 - d01 * d21) / denom
    w = (d00 * d21 - d01 * d20) / denom
    tolerance = settings.BARYCENTRIC_TOLERANCE
    return bool(v >= -tolerance and w >= -tolerance and v + w <= 1 + tolerance)


def way_out_crossed_reference(stage, table, triangle_ids, normals, heights, i, k, vertex) -> bool:
    """Plain version of :func:`stage_crossings.ways_out_crossed` for vertex ``k`` (world
    ``vertex``) and the triangle at position ``i`` of the job's ``triangle_ids``, given
    every triangle's outward normal and vertex heights: whether its way out crosses another
    of them."""
    h = heights[i][k]
    if h >= 0:
        return False
    tolerance = settings.STAGE_CROSSING_TOLERANCE
    for j, s in enumerate(triangle_ids):
        if s == triangle_ids[i]:
            continue
        d0 = heights[j][k]
        d1 = d0 - h * dot(normals[i], normals[j])
        if not (d0 * d1 < 0 and abs(d0) > tolerance and abs(d1) > tolerance):
            continue
        point = vertex - ((d0 / (d0 - d1)) * h) * normals[i]
        if inside_triangle_prism(table, s, stage.ray_triangles[s][0], point):
            return True
    return False


def crossed_faces_reference(holding: list[list[int]], normals: list, heights: list) -> list[int]:
    """Plain version of :func:`stage_crossings.crossed_faces` for one job: the positions of
    its crossed triangles, given ``holding[k]``, the positions of the triangles holding
    vertex k's contacts, and every triangle's outward normal and vertex heights."""
    if not any(holding):
        return []
    crossed = []
    for i, (normal, height) in enumerate(zip(normals, heights, strict=True)):
        loose, kept = 0.0, 0.0  # the deepest loose and held vertices behind the plane
        for k, positions in enumerate(holding):
            if height[k] >= 0:
                continue
            facing = any(
                abs(dot(normal, normals[j])) >= settings.STAGE_CORNER_COSINE for j in positions
            )
            if facing:
                kept = max(kept, -height[k])
            else:
                loose = max(loose, -height[k])
        if loose > kept and max(height) > 0:
            crossed.append(i)
    return crossed
