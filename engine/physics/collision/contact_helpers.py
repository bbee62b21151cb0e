"""Contact helpers shared by the batched and the reference narrow phase.

Both paths call these same public functions, so they agree by construction where they
use them (and neither imports private names of the other):

* fcl's answers as arrays: :func:`fcl_raw_contacts`, :func:`contact_arrays`,
  :func:`midpoint_contacts` (A's point half a depth along ``+n`` from fcl's midpoint,
  B's half a depth back), :func:`deepest_record` (ties broken by ``TIE_QUANTUM``);
* bodies created at one point (:func:`coincident`: center distance below
  ``COINCIDENT_FRACTION`` of the thinner body's smallest dimension), whose fcl normal is
  arbitrary: :func:`spread_direction` turns by the golden angle with the pair's ids, and
  :func:`coincident_spheres` pushes two spheres apart along it;
* :func:`segment_in_body`: a capsule's axis segment and radius (a sphere's: one point);
* :func:`body_poses`, :func:`to_world`: body poses and world points of ``g`` jobs at once;
* :func:`triangle_table`: the per-triangle constants of the stage mesh (normals, edges and
  the Gram entries of the barycentric solve, Ericson 3.4), computed once;
* :func:`new_contact_side`: which side of a stage triangle is outward for a body touching
  it for the first time (the stage may wind its triangles either way).
"""

from __future__ import annotations

import fcl
import numpy as np

from ..core import settings
from ..core.quaternions import cross
from ..core.shapes import Shape, ShapeKind

_REQUEST = fcl.CollisionRequest(num_max_contacts=settings.MAX_FCL_CONTACTS, enable_contact=True)


def fcl_raw_contacts(object_a, object_b) -> list:
    """fcl's contact records of two collision objects (empty list when apart)."""
    result = fcl.CollisionResult()
    if fcl.collide(object_a, object_b, _REQUEST, result) == 0:
        return []
    return result.contacts


def contact_arrays(contacts: list) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """fcl contact records as arrays: midpoints, normals A->B, depths, b1 (triangle) ids."""
    if not contacts:
        empty = np.zeros((0, 3))
        return empty, empty, np.zeros(0), np.zeros(0, dtype=np.int64)
    pos = np.array([c.pos for c in contacts])
    normal = np.array([c.normal for c in contacts])
    depth = np.abs(np.array([c.penetration_depth for c in contacts]))
    ids = np.array([c.b1 for c in contacts], dtype=np.int64)
    return pos, normal, depth, ids


def midpoint_contacts(mid, normals, depths):
    """fcl midpoints ``(k, 3)`` -> ``(point_a, point_b, normal)``: A's point is half a depth
    along +n, B's half a depth back."""
    half = 0.5 * depths[:, None] * normals
    return mid + half, mid - half, normals


def generic_contacts(object_a, object_b):
    """fcl's own points of two shapes (``(point_a, point_b, normal)``; None when apart)."""
    mid, normals, depths, _ = contact_arrays(fcl_raw_contacts(object_a, object_b))
    if len(depths) == 0:
        return None
    return midpoint_contacts(mid, normals, depths)


def deepest_record(records: list):
    """fcl's deepest contact record; near-equal depths (``TIE_QUANTUM``) go to the first,
    so the choice does not hang on the rounding of the poses (plain Python: a job has only
    a few records, and NumPy calls would cost more than they save)."""
    # tie_key of |depth|: Python's round, like np.round, rounds halves to even
    keys = [round(abs(record.penetration_depth) / settings.TIE_QUANTUM) for record in records]
    return records[keys.index(max(keys))]


def coincident_mask(b, a: np.ndarray, c: np.ndarray) -> np.ndarray:
    """(g,) bool, :func:`coincident` for the body pairs ``(a[k], c[k])`` at once."""
    gap = b.body_position[c] - b.body_position[a]
    # coincident: |x_c - x_a| < fraction * the thinner body's smallest dimension
    limit = (
        settings.COINCIDENT_FRACTION
        * 2.0
        * np.minimum(b.body_min_half_extent[a], b.body_min_half_extent[c])
    )
    return (gap * gap).sum(axis=1) < limit * limit


def coincident(b, a: int, c: int) -> bool:
    """Bodies a and c have (nearly) the same center: closer than ``COINCIDENT_FRACTION`` of
    the thinner one's smallest dimension (created at one point, say)."""
    limit = (
        settings.COINCIDENT_FRACTION
        * 2.0
        * min(b.body_min_half_extent[a], b.body_min_half_extent[c])
    )
    gap = b.body_position[c] - b.body_position[a]
    return float(gap @ gap) < limit * limit


def spread_direction(a, c) -> np.ndarray:
    """Unit horizontal direction(s) ``(3,)`` (or ``(k, 3)`` for id arrays) to push
    coincident bodies a < c apart.

    Any fixed direction would line all bodies created at one point up along one axis; a
    direction turning by the golden angle with the pair ids spreads them over a disc.
    """
    a, c = np.asarray(a), np.asarray(c)
    turn = 2.0 * np.pi * ((a * 0.6180339887498949 + c * 0.7548776662466927) % 1.0)
    return np.stack([np.cos(turn), np.zeros_like(turn), np.sin(turn)], axis=-1)


def coincident_spheres(b, a, shape_a, c, shape_c, rotation):
    """Contact of two spheres with (nearly) coincident centers along
    :func:`spread_direction` (fcl's center-to-center normal is undefined there)."""
    n = spread_direction(a, c)
    center_a = rotation[a] @ shape_a.body_from_shape[:3, 3] + b.body_position[a]
    center_c = rotation[c] @ shape_c.body_from_shape[:3, 3] + b.body_position[c]
    # A's deepest point inside C and C's inside A: depth = r_a + r_c + (x_a - x_c) . n
    point_a = center_a + shape_a.radius * n
    point_b = center_c - shape_c.radius * n
    return point_a[None], point_b[None], n[None]


def body_poses(
    bodies: list, rotation: np.ndarray, position: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Rotations ``(g, 3, 3)`` and positions ``(g, 3)`` of ``bodies`` (batched paths)."""
    index = np.array(bodies, dtype=np.int64)
    return rotation[index], position[index]


def to_world(rotation, position, points):
    """World points ``(g, k, 3)``: ``R p + x`` for body-frame points ``(g, k, 3)``."""
    return np.einsum("gij,gkj->gki", rotation, points) + position[:, None]


def triangle_table(mesh_shape) -> dict:
    """Constants of all triangles of a static mesh, computed once and kept on the shape.

    ``normal (t, 3)`` unit face normals (winding order), ``e0, e1 (t, 3)`` edges from vertex
    0, the Gram entries ``d00, d01, d11, denom (t,)`` of the barycentric solve, and the
    heights ``y_low, y_high (t,)`` of each triangle's lowest and highest corner, and
    ``backed (t,)``: another triangle lies in the same plane facing the other way
    (:func:`backed_triangles`).
    """
    table = getattr(mesh_shape, "_triangle_table", None)
    if table is None:
        tris = mesh_shape.ray_triangles
        e0, e1 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
        normal = cross(e0, e1)
        normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), settings.TINY)
        # Gram matrix [d00 d01; d01 d11] of the two edges: d_ij = e_i . e_j
        d00, d01, d11 = (e0 * e0).sum(1), (e0 * e1).sum(1), (e1 * e1).sum(1)
        table = {
            "normal": normal,
            "e0": e0,
            "e1": e1,
            "d00": d00,
            "d01": d01,
            "d11": d11,
            "denom": d00 * d11 - d01 * d01,
            "y_low": tris[:, :, 1].min(axis=1),
            "y_high": tris[:, :, 1].max(axis=1),
            "backed": backed_triangles(normal, tris[:, 0]),
        }
        mesh_shape._triangle_table = table
    return table


def backed_triangles(normal: np.ndarray, corner: np.ndarray) -> np.ndarray:
    """(t,) bool: a triangle whose plane holds another triangle facing the other way (unit
    normals ``normal (t, 3)``, a corner of each ``corner (t, 3)``; planes compared to 1e-3
    in the normal and 0.1 mm in the offset): the back of a skirting board against the
    wall's face. Its front is not free space, so its side is the body's center's even
    where the center is above it (:func:`center_decides`)."""
    offset = (normal * corner).sum(axis=1)
    key = np.round(np.column_stack([normal * 1e3, offset * 1e4])).astype(np.int64)
    flipped = np.round(np.column_stack([-normal * 1e3, -offset * 1e4])).astype(np.int64)
    planes = {tuple(row) for row in key.tolist()}
    return np.array([tuple(row) in planes for row in flipped.tolist()], dtype=bool)


def level_with(table: dict, ids: np.ndarray, center_y) -> np.ndarray:
    """Bool, a body's center at height ``center_y`` is level with each triangle ``ids``
    (between its lowest and highest corner, ``triangle_table``'s ``y_low`` and ``y_high``)
    or the triangle is backed (a board's back against a wall: its front is the wall), as
    :func:`center_decides` reads it."""
    level = (table["y_low"][ids] <= center_y) & (center_y <= table["y_high"][ids])
    return level | table["backed"][ids]


def segment_in_body(shape: Shape) -> tuple[np.ndarray, np.ndarray, float]:
    """Body-frame axis segment ``(p, q)`` and radius of a capsule (``p = q``: a sphere)."""
    center = shape.body_from_shape[:3, 3]
    if shape.kind == ShapeKind.SPHERE:
        return center, center, float(shape.radius)
    half = 0.5 * float(shape.geometry.lz) * shape.body_from_shape[:3, 2]  # fcl's axis is Z
    return center - half, center + half, float(shape.geometry.radius)


def center_decides(
    level: np.ndarray, center_height: np.ndarray, max_height: np.ndarray, min_height: np.ndarray
) -> np.ndarray:
    """Whether the body's center says on which side of a wall-like stage triangle the body
    is (rule 4 of :func:`new_contact_side`): the center is ``level`` with the triangle
    (between its lowest and highest corner, or the triangle is backed by an opposite one,
    :func:`backed_triangles`), or the plane passes clear of it, farther than
    ``STAGE_CENTER_SIDE_FRACTION`` of the body's extent along the normal (``max_height -
    min_height``, the largest and least ``n . (x - p_0)`` over its points).

    A low face cutting the body near its middle says nothing: a cone sliding off a 3 cm
    slab (a bed's base) with its center just past the slab's side, above its top, had the
    rim vertices dipping beyond the side, in the air, taken as 2-11 cm behind it and
    pushed into the slab; it ended wedged under the slab, its tip 10 cm below the floor.
    A skirting board's back against a wall keeps the center's side (its front is inside
    the wall): cones pressed into the board with their centers above it went through.

    Reference: :func:`reference_pairs.center_decides_reference`.
    """
    extent = max_height - min_height
    return level | (np.abs(center_height) > settings.STAGE_CENTER_SIDE_FRACTION * extent)


def new_contact_side(
    normal_y: np.ndarray,
    center_height: np.ndarray,
    max_height: np.ndarray,
    center_decides: np.ndarray | bool = True,
) -> np.ndarray:
    """+1 or -1 (same shape as the inputs) turning a stage triangle's winding normal ``n``
    to its outward side for a body without a cached contact on it.

    ``normal_y``: ``n_y``; ``center_height``: ``n . (c - p_0)`` of the body's center ``c``;
    ``max_height``: the largest ``n . (x - p_0)`` over the body's points; ``center_decides``:
    the body's center says where the body is (:func:`center_decides`). The rule, in order:

    1. the whole body behind the plane (``max_height <= 0``): the back (a body behind a
       one-sided wall stays there);
    2. a floor-like triangle (``|n_y| >= FLOOR_NORMAL_Y``) with the body's center on or
       above its plane (``center_height n_y >= 0``): up, whatever the winding (a body
       spawned half buried in a floor wound either way is pushed up, never through it);
    3. a floor-like triangle with the center below its plane: the front (a body teleported
       with its center below a floor is pushed up through the floor's front; one pressed
       into a ceiling from below stays below);
    4. a wall-like triangle where the center decides: the side holding the body's center
       (its front when the center is on the plane): a body poking through the back of a
       thin wall or skirting board is pulled back to where most of it is, not pushed on
       through the next wall;
    5. any other wall-like triangle: the front.

    Reference: :func:`reference_pairs.new_contact_side_reference`.
    """
    floor_like = np.abs(normal_y) >= settings.FLOOR_NORMAL_Y
    up = np.where(normal_y > 0, 1.0, -1.0)  # the sign turning n to point up
    floor_side = np.where(center_height * normal_y >= 0, up, 1.0)
    wall_side = np.where(center_decides, np.where(center_height >= 0, 1.0, -1.0), 1.0)
    side = np.where(floor_like, floor_side, wall_side)
    return np.where(max_height <= 0, -1.0, side)
