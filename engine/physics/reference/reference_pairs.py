"""Reference twins of the pair table's rules: contacts of one shape pair, in plain loops.

The plain version of :mod:`batched_stage` and :mod:`batched_pairs` (box pairs in
:mod:`reference_box_box`), the size of box2d-lite's ``Collide``: loops over vertices and
triangles a student can step through in a debugger. Each ``*_pair`` function is the
``reference`` column of one rule of :mod:`pair_table` and takes one :class:`PairJob`;
it returns the job's contacts, or None to decline it to the rule's fallback. Tests prove
that both paths produce the same contact points (to rounding); each function names the
batched code it mirrors.

Vectors are ``(3,)`` float arrays in the world frame unless named ``_local`` (body frame).
Matrix-vector products are written out as three dot products (:func:`rotate`,
:func:`unrotate`) so they round exactly like the batched ``einsum`` calls.
"""

from __future__ import annotations

import numpy as np

from ..collision.collide import round_stage_contacts
from ..collision.contact_helpers import (
    coincident,
    coincident_spheres,
    contact_arrays,
    deepest_record,
    fcl_raw_contacts,
    generic_contacts,
    spread_direction,
    triangle_table,
)
from ..collision.contacts import ManifoldStore, tie_key
from ..collision.pair_rules import FCL_FEATURE, PairContext, PairJob
from ..collision.stage_crossings import crossed_face_points
from ..collision.stage_grid import candidate_triangles_reference
from ..core import settings
from ..core.reference_geometry import Contact, dot, rotate, unrotate
from .reference_box_box import box_box_contacts_reference
from .reference_crossings import (
    crossed_faces_reference,
    inside_triangle_prism,
    way_out_crossed_reference,
)


def as_contacts(result) -> list[Contact]:
    """``(point_a, point_b, normal)`` arrays ``(k, 3)`` (or None) as a list of contacts."""
    if result is None:
        return []
    point_a, point_b, normal = result
    return [Contact(point_a[k], point_b[k], normal[k], k) for k in range(len(point_a))]


# ------------------------------------------------------------------------------------------
# the rules' reference functions (one job each)
# ------------------------------------------------------------------------------------------
def stage_hull_pair(job: PairJob, context: PairContext) -> list[Contact] | None:
    """Rule ``stage-hull``: hull vertices resting on the stage triangles near the hull,
    fcl's points on the triangles the hull crosses without a vertex on them, or, without
    any vertex contact, fcl's points of an edge crossing a face (mirrors
    :func:`batched_stage.stage_hull_batch`)."""
    bodies, b = context.bodies, job.body_b
    # the triangles whose box overlaps B's AABB grown by the probe's reach
    near = candidate_triangles_reference(
        job.shape_a.ray_triangles,
        bodies.body_aabb_min[b : b + 1] - settings.STAGE_NEAR_DISTANCE,
        bodies.body_aabb_max[b : b + 1] + settings.STAGE_NEAR_DISTANCE,
    )[0].tolist()
    if not near:
        return []
    cached = cached_stage_normals(context.store, b)
    pose = context.pose(b)
    crossed: dict = {}  # triangles the hull crosses without a vertex on them
    contacts = stage_polyhedron_contacts(job.shape_a, job.shape_b, pose, near, cached, crossed)
    if contacts and not crossed:
        return contacts
    context.objects.move(bodies, np.array([b]), context.rotation[[b]])  # and its probe
    if contacts:  # a thin slab's side across a resting body: fcl's points on that side
        point_a, point_b, normal = crossed_face_points(
            fcl_raw_contacts(job.object_a, job.probe_b), crossed
        )
        extra = [
            Contact(point_a[i], point_b[i], normal[i], FCL_FEATURE + i) for i in range(len(normal))
        ]
        return contacts + extra
    # no vertex in contact (an edge crossing a face): fcl's triangles and points
    found = fcl_raw_contacts(job.object_a, job.probe_b)
    if not found:
        return []
    touched = sorted({int(record.b1) for record in found if record.b1 >= 0})
    # every triangle fcl names was tested above (the batched path's known edge): no vertex
    # rests on any, fcl's points only; else (never seen) fcl's triangles from the start
    known = all(record.b1 >= 0 for record in found) and set(touched) <= set(near)
    return stage_polyhedron_contacts(
        job.shape_a, job.shape_b, pose, touched, cached, None, found, vertex_contacts=not known
    )


def box_pair(job: PairJob, context: PairContext) -> list[Contact] | None:
    """Rule ``box-box``: separating axes + clipping, no fcl (mirrors
    :func:`batched_pairs.box_pair_batch`); None (declined to ``hull-hull``, fcl objects
    moved) when the boxes share a center or overlap deeper than ``BOX_DEEP_OVERLAP``."""
    a, c = job.body_a, job.body_b
    if not coincident(context.bodies, a, c):
        boxed = box_box_contacts_reference(
            box_frame(job.shape_a, context.pose(a)), box_frame(job.shape_b, context.pose(c))
        )
        if boxed is not None:
            return boxed
    context.objects.move_shapes(context.bodies, [a, c], context.rotation)
    return None


def hull_pair(job: PairJob, context: PairContext) -> list[Contact] | None:
    """Rule ``hull-hull``: fcl's normal, then vertices inside the other hull (mirrors
    :func:`batched_pairs.hull_pair_batch`)."""
    found = fcl_raw_contacts(job.object_a, job.object_b)
    if not found:
        return []
    a, c = job.body_a, job.body_b
    # bodies created at one point: fcl's normal is arbitrary, use the pair's spread direction
    spread = spread_direction(a, c) if coincident(context.bodies, a, c) else None
    return polyhedron_contacts(
        job.shape_a, context.pose(a), job.shape_b, context.pose(c), found, spread
    )


def sphere_pair(job: PairJob, context: PairContext) -> list[Contact] | None:
    """Rule ``sphere-sphere`` (mirrors :func:`batched_pairs.sphere_pair_batch`)."""
    a, c = job.body_a, job.body_b
    if coincident(context.bodies, a, c):
        return as_contacts(
            coincident_spheres(context.bodies, a, job.shape_a, c, job.shape_b, context.rotation)
        )
    return as_contacts(generic_contacts(job.object_a, job.object_b))


def stage_round_pair(job: PairJob, context: PairContext) -> list[Contact] | None:
    """Rule ``stage-round`` (mirrors :func:`batched_pairs.stage_round_batch`)."""
    pose_b = context.pose(job.body_b)
    return as_contacts(
        round_stage_contacts(job.shape_a, job.object_a, job.shape_b, pose_b, job.probe_b)
    )


def fcl_pair(job: PairJob, context: PairContext) -> list[Contact] | None:
    """Rule ``fcl``: fcl's own points (mirrors :func:`batched_pairs.fcl_pair_batch`)."""
    return as_contacts(generic_contacts(job.object_a, job.object_b))


# ------------------------------------------------------------------------------------------
# the per-pair geometry behind them
# ------------------------------------------------------------------------------------------
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
    center: np.ndarray,
    cached: list[tuple[np.ndarray, np.ndarray]],
    level: bool = True,
) -> float:
    """+1 or -1 turning a triangle's normal to the stage's outward side.

    The cached normal most (anti-)parallel to it decides when it is within 60 degrees
    (``|n . c| > 0.5``) and its point lies on the triangle's plane (within
    ``OUTWARD_SIDE_PLANE_DISTANCE`` of the plane through ``corner``): the body stays on the
    side where the contact began. A new contact, or one cached on another surface, follows
    :func:`new_contact_side_reference` with the hull vertices' ``heights``, the body's
    ``center`` and whether it is ``level`` with the triangle (between its lowest and highest
    corner), see :func:`center_decides_reference`.
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
    center_height = dot(normal, center) - dot(normal, corner)
    decides = center_decides_reference(level, center_height, max(heights), min(heights))
    return new_contact_side_reference(float(normal[1]), center_height, max(heights), decides)


def center_decides_reference(
    level: bool, center_height: float, max_height: float, min_height: float
) -> bool:
    """Plain twin of :func:`contact_helpers.center_decides`: the center is level with the
    triangle, or its plane passes clear of the center (farther than
    ``STAGE_CENTER_SIDE_FRACTION`` of the body's extent along the normal)."""
    extent = max_height - min_height
    return level or abs(center_height) > settings.STAGE_CENTER_SIDE_FRACTION * extent


def new_contact_side_reference(
    normal_y: float, center_height: float, max_height: float, decides: bool = True
) -> float:
    """Plain twin of :func:`contact_helpers.new_contact_side` (one triangle): the back when
    the whole body is behind the plane; on a floor-like triangle up when the body's center
    is on or above its plane, else the front; on a wall-like one the center's side where
    it ``decides`` (:func:`center_decides_reference`), else the front."""
    if max_height <= 0:
        return -1.0  # wholly behind: a body behind a one-sided wall stays there
    if abs(normal_y) >= settings.FLOOR_NORMAL_Y:  # a floor or a ceiling
        if center_height * normal_y >= 0:  # the center on the up side of the plane
            return 1.0 if normal_y > 0 else -1.0  # up, whichever way the floor is wound
        return 1.0
    if not decides:  # a low face cutting the body near its middle: its front
        return 1.0
    return 1.0 if center_height >= 0 else -1.0  # a wall: where most of the body is


def stage_polyhedron_contacts(
    stage,
    hull,
    pose,
    triangle_ids: list[int],
    cached: list[tuple[np.ndarray, np.ndarray]],
    crossed: dict | None = None,
    found: list | None = None,
    vertex_contacts: bool = True,
) -> list[Contact]:
    """Vertices of ``hull`` (at ``pose = (R, x)``) resting on the stage triangles
    ``triangle_ids`` (ascending); when none touches and fcl's records ``found`` are given,
    fcl's points with the normal of the triangle the hull is least deep behind (an edge
    crossing a face), no deeper than the hull's deepest vertex below that triangle's
    plane. A vertex passed a triangle rests on it only if the segment to its foot crosses
    no other of its triangles
    (:func:`reference_crossings.way_out_crossed_reference`).

    Mirrors ``batched_stage._stage_group``. For every touched triangle t (normal n_t turned to
    the stage's outward side, :func:`outward_side` with the ``cached`` manifold normals)
    and hull vertex v, the signed height
    ``h = n_t . (x_v - p0_t)``; v is in contact with t when ``h < STAGE_SPECULATIVE_DISTANCE``,
    it is not more than half the hull's extent below the plane, and its projection falls
    inside the triangle. Each vertex keeps its resting triangle (:func:`_resting_triangle`:
    the shallowest it has passed, else the nearest) and, in a corner, the shallowest of
    those turned 45 to 135 degrees from it that hold it up beside it
    (:func:`_behind_the_corner`; listed after all the first contacts, as the batched path
    orders them). ``crossed`` (a dict, when given) receives the triangles the hull
    crosses without a vertex on them, in a job with vertex contacts
    (:func:`reference_crossings.crossed_faces_reference`): ``{id: (normal, least height)}``.
    Without ``vertex_contacts`` only fcl's points are made (every triangle fcl named was
    already tested with the body's whole near set, which holds the vertices' ways out).
    """
    table = triangle_table(stage)
    rotation, position = pose
    vertices = [rotate(rotation, v) + position for v in hull.hull_vertices]
    extent = max(
        max(v[axis] for v in vertices) - min(v[axis] for v in vertices) for axis in range(3)
    )
    normals, heights = [], []
    for t in triangle_ids:
        normal, corner = table["normal"][t], stage.ray_triangles[t][0]
        height = [dot(normal, v) - dot(normal, corner) for v in vertices]
        level = bool(table["y_low"][t] <= position[1] <= table["y_high"][t])
        level = level or bool(table["backed"][t])  # a board's back against a wall
        side = outward_side(normal, corner, height, position, cached, level)
        normal, height = normal * side, [value * side for value in height]
        normals.append(normal)
        heights.append(height)  # (T, V) signed heights, m
    contacts, corner_contacts = [], []
    holding: list[list[int]] = [[] for _ in vertices]  # positions holding vertex k
    for k, vertex in enumerate(vertices if vertex_contacts else []):
        # positions i of the triangles this vertex touches
        touching = [
            i
            for i, t in enumerate(triangle_ids)
            if settings.STAGE_SPECULATIVE_DISTANCE > heights[i][k]
            and heights[i][k] > -settings.STAGE_BELOW_FRACTION * extent
            and inside_triangle_prism(table, t, stage.ray_triangles[t][0], vertex)
            and not way_out_crossed_reference(
                stage, table, triangle_ids, normals, heights, i, k, vertex
            )
        ]
        if not touching:
            continue
        best = _resting_triangle(touching, heights, k)
        holding[k].append(best)
        contacts.append(_vertex_contact(vertex, normals[best], heights[best][k], k))
        # in a corner: also the shallowest triangle turned 45 to 135 degrees from that one
        # which holds the vertex up beside it (see _behind_the_corner)
        turned = [
            i
            for i in _behind_the_corner(
                stage, table, triangle_ids, (k, vertex, extent), touching, best, normals, heights
            )
            if abs(dot(normals[i], normals[best])) < settings.STAGE_CORNER_COSINE
        ]
        if turned:
            second = _shallowest(turned, heights, k)
            holding[k].append(second)
            corner = _vertex_contact(vertex, normals[second], heights[second][k], len(vertices) + k)
            corner_contacts.append(corner)
    contacts += corner_contacts  # the batched path orders them after every first contact
    if crossed is not None:  # a thin slab's side across a body resting on the floor
        for i in crossed_faces_reference(holding, normals, heights):
            crossed.setdefault(triangle_ids[i], (normals[i], min(heights[i])))
    if not contacts and triangle_ids and found:  # an edge crossing a face: fcl's points
        mid, _, depths, _ = contact_arrays(found)
        depths = depths - settings.STAGE_SPECULATIVE_DISTANCE  # probe depth -> shape depth
        # the face entered through: the triangle the hull is least deep behind (the first
        # of equals; mirrors batched_stage._entry_face); no deeper than its deepest vertex
        entry = max(range(len(heights)), key=lambda i: min(heights[i]))
        depths = np.minimum(depths, -min(heights[entry]))
        contacts = midpoint_contact_list(mid, [normals[entry]] * len(mid), depths)
    return contacts


def _behind_the_corner(
    stage, table, triangle_ids, vertex_of, touching: list[int], best: int, normals, heights
) -> list[int]:
    """Positions of the triangles holding vertex ``k`` up in a corner beside its resting
    triangle ``best``, when it has passed that one: it lies behind them (``-STAGE_BELOW_FRACTION
    * extent < h < 0``) and, pushed out of ``best`` to ``STAGE_CORNER_PUSH`` in front of it,
    inside their prisms; either ``touching`` them already or at most ``STAGE_CORNER_REACH``
    below them (``vertex_of = (k, vertex, extent)``; mirrors
    ``batched_stage._behind_the_corner``)."""
    k, vertex, extent = vertex_of
    if heights[best][k] >= 0:
        return []
    pushed = vertex + (settings.STAGE_CORNER_PUSH - heights[best][k]) * normals[best]
    return [
        i
        for i, t in enumerate(triangle_ids)
        if -settings.STAGE_BELOW_FRACTION * extent < heights[i][k] < 0
        and (i in touching or heights[i][k] > -settings.STAGE_CORNER_REACH)
        and inside_triangle_prism(table, t, stage.ray_triangles[t][0], pushed)
    ]


def _resting_triangle(positions: list[int], heights: list, k: int) -> int:
    """The position in ``positions`` of vertex ``k``'s resting triangle: the shallowest of
    those it has passed (``h < 0``), else the nearest (all speculative: the surface it
    meets first); the first of equal heights (mirrors ``batched_stage._resting_triangle``)."""
    passed = [i for i in positions if heights[i][k] < 0]
    if passed:
        return _shallowest(passed, heights, k)
    best = positions[0]
    for i in positions[1:]:
        if heights[i][k] < heights[best][k]:
            best = i
    return best


def _shallowest(positions: list[int], heights: list, k: int) -> int:
    """The position in ``positions`` whose triangle vertex ``k`` is highest above (the
    first of equal heights)."""
    best = positions[0]
    for i in positions[1:]:
        if heights[i][k] > heights[best][k]:
            best = i
    return best


def _vertex_contact(vertex: np.ndarray, normal: np.ndarray, height: float, feature: int) -> Contact:
    """Vertex ``vertex`` at ``height`` above a plane of outward ``normal``: depth ``-height``,
    A's point on the plane; ``feature``: its feature number (the vertex's, ``V + v`` for
    a corner's second contact)."""
    return Contact(vertex - normal * height, vertex, normal, feature)


def polyhedron_contacts(
    shape_a, pose_a, shape_b, pose_b, found: list, spread: np.ndarray | None = None
) -> list[Contact]:
    """Vertex contacts of two polyhedra (method 1 of :mod:`collide`).

    Mirrors ``batched_pairs._polyhedron_group``. fcl's deepest normal ``n`` (A -> B) picks a
    reference face on A (the face most aligned with ``n``) and one on B (most aligned with
    ``-n``); a face counts only if ``n_face . (+-n) >= REFERENCE_FACE_ALIGNMENT``. Every
    vertex of the other body inside the reference hull (its planes inflated by
    ``SPECULATIVE_DISTANCE``) and at most that far above the face becomes a contact,
    A's face first. Without any, fcl's own points are used. ``spread``: the direction that
    replaces fcl's normal for bodies created at one point (:func:`contact_helpers.coincident`).
    """
    deepest = deepest_record(found)  # the first of near-equal depths
    n = np.asarray(deepest.normal, dtype=np.float64) if spread is None else spread
    contacts: list[Contact] = []
    # feature numbers: B's vertices against A's face, then A's after them
    for first, (reference, pose_ref, incident, pose_inc, sign) in zip(
        (0, len(shape_b.hull_vertices)),
        ((shape_a, pose_a, shape_b, pose_b, 1.0), (shape_b, pose_b, shape_a, pose_a, -1.0)),
        strict=True,
    ):
        rotation_inc, position_inc = pose_inc
        vertices = [rotate(rotation_inc, v) + position_inc for v in incident.hull_vertices]
        for v, vertex, on_face, face_normal in _reference_face_contacts(
            reference, pose_ref, vertices, sign * n
        ):
            if sign > 0:
                contacts.append(Contact(on_face, vertex, face_normal, first + v))
            else:
                contacts.append(Contact(vertex, on_face, -face_normal, first + v))
    if not contacts:  # no face faces the other body: fcl's points
        mid, normals, depths, _ = contact_arrays(found)
        contacts = midpoint_contact_list(mid, list(normals), depths)
    return contacts


def _reference_face_contacts(reference, pose, vertices: list, towards: np.ndarray) -> list:
    """``[(index, vertex, point on the face, face normal)]`` of ``vertices`` inside
    ``reference``."""
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
    for index, vertex in enumerate(vertices):
        local = unrotate(rotation, vertex - position)
        inside = all(
            dot(local, plane) - offset <= tolerance
            for plane, offset in zip(reference.plane_normals, reference.plane_offsets, strict=True)
        )
        depth = plane_offset - dot(vertex, normal)
        if inside and depth > -tolerance:
            contacts.append((index, vertex, vertex + depth * normal, normal))
    return contacts


def midpoint_contact_list(mid, normals, depths) -> list[Contact]:
    """fcl midpoints -> contacts: A's point half a depth along +n, B's half a depth back
    (feature numbers ``FCL_FEATURE + i``)."""
    contacts = []
    for i, (point, normal, depth) in enumerate(zip(mid, normals, depths, strict=True)):
        half = 0.5 * depth * normal
        contacts.append(Contact(point + half, point - half, normal, FCL_FEATURE + i))
    return contacts
