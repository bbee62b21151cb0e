"""Reference path of the collision stage: contacts and manifolds one body pair at a time.

This is the plain version of :mod:`narrow_phase` (batched contact generation; box pairs
in :mod:`reference_box_box`) and, with :mod:`reference_manifolds`, of
:meth:`contacts.ManifoldStore.update` (batched manifold refresh, merge and reduction), the
size of box2d-lite's ``Collide`` + ``Arbiter::Update``: loops over shapes, vertices and
triangles a student can step through in a debugger. ``SolverSettings.use_vectorized =
False`` routes the world through it, and tests prove that both paths produce the same
contact points, manifolds and trajectories (to rounding). The rules are those of
:mod:`collide` and :mod:`contacts`; each function names the batched code it mirrors.

Vectors are ``(3,)`` float arrays in the world frame unless named ``_local`` (body frame).
Matrix-vector products are written out as three dot products (:func:`rotate`,
:func:`unrotate`) so they round exactly like the batched ``einsum`` calls.
"""

from __future__ import annotations

import numpy as np

from . import settings
from .bodies import Bodies
from .collide import (
    _POLYHEDRA,
    _triangle_table,
    contact_arrays,
    fcl_raw_contacts,
    round_contacts,
)
from .contacts import SLOTS, ManifoldStore, tie_key
from .narrow_phase import coincident, coincident_spheres, deepest_record, spread_direction
from .reference_box_box import box_box_contacts_reference
from .reference_geometry import Contact, dot, rotate, unrotate
from .reference_manifolds import ManifoldPoint, select_support, update_manifold


# ------------------------------------------------------------------------------------------
# contact generation (mirrors narrow_phase.narrow_phase)
# ------------------------------------------------------------------------------------------
def pair_contacts(
    bodies: Bodies, objects, store: ManifoldStore, a: int, c: int, rotation: np.ndarray
) -> list[Contact]:
    """Contacts of body pair ``(a, c)``, ``a < c``, in the narrow phase's order: shape pairs
    in body order, then the order of each rule below (``rotation (n, 3, 3)``: all bodies;
    ``store``: the manifolds before this step's update, whose normals keep a stage contact
    on the side it began on)."""
    contacts: list[Contact] = []
    pose_a = (rotation[a], bodies.body_position[a])
    pose_c = (rotation[c], bodies.body_position[c])
    for shape_a, obj_a in zip(bodies.shapes[a], objects.shape_objects[a], strict=True):
        for shape_c, obj_c, probe_c in zip(
            bodies.shapes[c], objects.shape_objects[c], objects.probe_objects[c], strict=True
        ):
            if shape_a.kind == "mesh" and shape_c.kind in _POLYHEDRA:
                found = fcl_raw_contacts(obj_a, probe_c)  # the triangles near C's hull
                if found:
                    contacts += stage_polyhedron_contacts(
                        shape_a, shape_c, pose_c, found, cached_stage_normals(store, c)
                    )
            elif (
                boxed := _analytic_boxes(bodies, a, shape_a, pose_a, c, shape_c, pose_c)
            ) is not None:
                contacts += boxed  # separating axes + clipping, no fcl (narrow_phase._box_group)
            elif shape_a.kind in _POLYHEDRA and shape_c.kind in _POLYHEDRA:
                if shape_a.kind == shape_c.kind == "box":  # analytic path's fcl objects stay put
                    objects.move_shapes(bodies, [a, c], rotation)
                found = fcl_raw_contacts(obj_a, obj_c)
                if found:
                    # bodies created at one point: fcl's normal is arbitrary, use the
                    # pair's spread direction (narrow_phase.spread_direction)
                    spread = spread_direction(a, c) if coincident(bodies, a, c) else None
                    contacts += polyhedron_contacts(shape_a, pose_a, shape_c, pose_c, found, spread)
            elif shape_a.kind == shape_c.kind == "sphere" and coincident(bodies, a, c):
                result = coincident_spheres(bodies, a, shape_a, c, shape_c, rotation)
                contacts += [Contact(*point) for point in zip(*result, strict=True)]
            else:  # spheres and capsules: the per-pair code is shared by both paths
                result = round_contacts(shape_a, obj_a, shape_c, pose_c, obj_c, probe_c)
                if result is not None:
                    contacts += [Contact(*point) for point in zip(*result, strict=True)]
    return contacts


def _analytic_boxes(bodies, a, shape_a, pose_a, c, shape_c, pose_c) -> list[Contact] | None:
    """The analytic contacts of two boxes; None when the pair is not two boxes, or the
    boxes share a center or overlap deeper than ``BOX_DEEP_OVERLAP`` (polyhedron path)."""
    if shape_a.kind != "box" or shape_c.kind != "box" or coincident(bodies, a, c):
        return None
    return box_box_contacts_reference(box_frame(shape_a, pose_a), box_frame(shape_c, pose_c))


def box_frame(shape, pose) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A box shape in the world: center ``R t + x``, axes (rows: the columns of
    ``R R_shape``) and half extents (mirrors ``box_box.box_shape_frames``)."""
    rotation, position = pose
    offset = shape.body_from_shape
    center = rotate(rotation, offset[:3, 3]) + position
    world = rotation @ offset[:3, :3]
    half = np.asarray(shape.geometry.side, dtype=np.float64) / 2.0
    return center, world.T.copy(), half


def cached_stage_normals(store: ManifoldStore, body: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(world normal (stage -> body), stage point)`` of the points of the stage's manifold
    with ``body`` (the stage frame is the world frame); empty for a new contact."""
    row = store.row((0, body))
    if row is None:
        return []
    return [(store.normal_local[row, s], store.local_a[row, s]) for s in range(store.count[row])]


def outward_side(
    normal: np.ndarray,
    corner: np.ndarray,
    heights: list[float],
    cached: list[tuple[np.ndarray, np.ndarray]],
) -> float:
    """+1 or -1 turning a triangle's normal to the stage's outward side.

    The cached normal most (anti-)parallel to it decides when it is within 60 degrees
    (``|n . c| > 0.5``) and its point lies on the triangle's plane (within
    ``OUTWARD_SIDE_PLANE_DISTANCE`` of the plane through ``corner``): the body stays on the
    side where the contact began. A new contact, or one cached on another surface, takes
    the side holding the middle of the hull's extent along the normal.
    """
    alignments = [
        dot(normal, c)
        if abs(dot(normal, p) - dot(normal, corner)) < settings.OUTWARD_SIDE_PLANE_DISTANCE
        else 0.0
        for c, p in cached
    ]
    if alignments:
        strongest = alignments[int(np.argmax(np.abs(alignments)))]
        if abs(strongest) > settings.OUTWARD_SIDE_ALIGNMENT:
            return float(np.sign(strongest))
    return -1.0 if max(heights) + min(heights) < 0 else 1.0


def stage_polyhedron_contacts(
    stage, hull, pose, found: list, cached: list[tuple[np.ndarray, np.ndarray]]
) -> list[Contact]:
    """Vertices of ``hull`` (at ``pose = (R, x)``) resting on the stage triangles fcl found.

    Mirrors ``narrow_phase._stage_group``. For every touched triangle t (normal n_t turned to
    the stage's outward side, :func:`outward_side` with the ``cached`` manifold normals)
    and hull vertex v, the signed height
    ``h = n_t . (x_v - p0_t)``; v is in contact with t when ``h < STAGE_SPECULATIVE_DISTANCE``,
    it is not more than half the hull's extent below the plane, and its projection falls
    inside the triangle. Each vertex keeps its shallowest triangle (the largest h).
    """
    table = _triangle_table(stage)
    triangle_ids = sorted({int(record.b1) for record in found if record.b1 >= 0})
    rotation, position = pose
    vertices = [rotate(rotation, v) + position for v in hull.hull_vertices]
    extent = max(
        max(v[axis] for v in vertices) - min(v[axis] for v in vertices) for axis in range(3)
    )
    normals, heights = [], []
    for t in triangle_ids:
        normal, corner = table["normal"][t], stage.ray_triangles[t][0]
        height = [dot(normal, v) - dot(normal, corner) for v in vertices]
        side = outward_side(normal, corner, height, cached)
        normal, height = normal * side, [value * side for value in height]
        normals.append(normal)
        heights.append(height)  # (T, V) signed heights, m
    contacts = []
    for k, vertex in enumerate(vertices):
        # (height, triangle position) of the shallowest candidate triangle
        best: tuple[float, int] | None = None
        for i, t in enumerate(triangle_ids):
            above = heights[i][k]  # m, height of this vertex above triangle t
            if (
                above < settings.STAGE_SPECULATIVE_DISTANCE
                and above > -settings.STAGE_BELOW_FRACTION * extent
                and inside_triangle_prism(table, t, stage.ray_triangles[t][0], vertex)
                and (best is None or above > best[0])
            ):
                best = (above, i)
        if best is not None:
            normal, depth = normals[best[1]], -best[0]
            contacts.append(Contact(vertex + normal * depth, vertex, normal))
    if not contacts and triangle_ids:  # an edge crossing a face: fcl's points
        mid, _, depths, _ = contact_arrays(found)
        depths = depths - settings.STAGE_SPECULATIVE_DISTANCE  # probe depth -> shape depth
        contacts = _midpoint_contacts(mid, [normals[0]] * len(mid), depths)
    return contacts


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


def polyhedron_contacts(
    shape_a, pose_a, shape_b, pose_b, found: list, spread: np.ndarray | None = None
) -> list[Contact]:
    """Vertex contacts of two polyhedra (method 1 of :mod:`collide`).

    Mirrors ``narrow_phase._polyhedron_group``. fcl's deepest normal ``n`` (A -> B) picks a
    reference face on A (the face most aligned with ``n``) and one on B (most aligned with
    ``-n``); a face counts only if ``n_face . (+-n) >= REFERENCE_FACE_ALIGNMENT``. Every
    vertex of the other body inside the reference hull (its planes inflated by
    ``SPECULATIVE_DISTANCE``) and at most that far above the face becomes a contact,
    A's face first. Without any, fcl's own points are used. ``spread``: the direction that
    replaces fcl's normal for bodies created at one point (``narrow_phase.coincident``).
    """
    deepest = deepest_record(found)  # the first of near-equal depths
    n = np.asarray(deepest.normal, dtype=np.float64) if spread is None else spread
    contacts: list[Contact] = []
    for reference, pose_ref, incident, pose_inc, sign in (
        (shape_a, pose_a, shape_b, pose_b, 1.0),
        (shape_b, pose_b, shape_a, pose_a, -1.0),
    ):
        rotation_inc, position_inc = pose_inc
        vertices = [rotate(rotation_inc, v) + position_inc for v in incident.hull_vertices]
        for vertex, on_face, face_normal in _reference_face_contacts(
            reference, pose_ref, vertices, sign * n
        ):
            if sign > 0:
                contacts.append(Contact(on_face, vertex, face_normal))
            else:
                contacts.append(Contact(vertex, on_face, -face_normal))
    if not contacts:  # no face faces the other body: fcl's points
        mid, normals, depths, _ = contact_arrays(found)
        contacts = _midpoint_contacts(mid, list(normals), depths)
    return contacts


def _reference_face_contacts(reference, pose, vertices: list, towards: np.ndarray) -> list:
    """``[(vertex, point on the face, face normal)]`` of ``vertices`` inside ``reference``."""
    rotation, position = pose
    face_normals = [rotate(rotation, plane) for plane in reference.plane_normals]
    alignment = [dot(normal, towards) for normal in face_normals]
    face = int(np.argmax(tie_key(np.array(alignment))))  # the first of equally aligned faces
    if alignment[face] < settings.REFERENCE_FACE_ALIGNMENT:
        return []
    normal = face_normals[face]
    tolerance = settings.SPECULATIVE_DISTANCE
    # the face plane n . x = c_f + n . x_ref in the world
    plane_offset = reference.plane_offsets[face] + dot(normal, position)
    contacts = []
    for vertex in vertices:
        local = unrotate(rotation, vertex - position)
        inside = all(
            dot(local, plane) - offset <= tolerance
            for plane, offset in zip(reference.plane_normals, reference.plane_offsets, strict=True)
        )
        depth = plane_offset - dot(vertex, normal)
        if inside and depth > -tolerance:
            contacts.append((vertex, vertex + depth * normal, normal))
    return contacts


def _midpoint_contacts(mid, normals, depths) -> list[Contact]:
    """fcl midpoints -> contacts: A's point half a depth along +n, B's half a depth back."""
    contacts = []
    for point, normal, depth in zip(mid, normals, depths, strict=True):
        half = 0.5 * depth * normal
        contacts.append(Contact(point + half, point - half, normal))
    return contacts


# ------------------------------------------------------------------------------------------
# manifold update (mirrors ManifoldStore.update)
# ------------------------------------------------------------------------------------------
def update_manifolds_reference(
    bodies: Bodies,
    objects,
    store: ManifoldStore,
    pairs: list[tuple[int, int]],
    rotation: np.ndarray,
) -> None:
    """Reference for ``collision_stage.update_manifolds``: per pair, its contacts, then
    its manifold refreshed, merged and reduced (:func:`update_manifold`)."""
    from .collision_stage import add_manifold_row

    for key in pairs:
        contacts = pair_contacts(bodies, objects, store, key[0], key[1], rotation)
        row = store.row(key)
        if row is None:
            if not contacts:
                continue
            row = add_manifold_row(bodies, store, key)
        frame_a = (rotation[key[0]], bodies.body_position[key[0]])
        frame_b = (rotation[key[1]], bodies.body_position[key[1]])
        cached = [
            ManifoldPoint(
                store.local_a[row, s].copy(),
                store.local_b[row, s].copy(),
                store.normal_local[row, s].copy(),
                store.impulse[row, s].copy(),
            )
            for s in range(store.count[row])
        ]
        points = update_manifold(
            cached,
            contacts,
            frame_a,
            frame_b,
            int(store.max_points[row]),
            float(store.feature[row]),
        )
        store.count[row] = len(points)
        for array in (store.local_a, store.local_b, store.normal_local, store.impulse):
            array[row] = 0.0
        for slot, point in enumerate(points):
            store.local_a[row, slot], store.local_b[row, slot] = point.local_a, point.local_b
            store.normal_local[row, slot], store.impulse[row, slot] = (
                point.normal_local,
                point.impulse,
            )


__all__ = [
    "SLOTS",
    "Contact",
    "ManifoldPoint",
    "pair_contacts",
    "select_support",
    "update_manifold",
    "update_manifolds_reference",
]
