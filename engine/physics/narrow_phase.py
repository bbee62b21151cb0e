"""Batched narrow phase: one fcl query per shape pair, then NumPy batches make the contacts.

:mod:`collide` explains the contact rules; this module applies them to all pairs of a step
at once. A Python loop asks python-fcl about every shape pair (that call is the only
per-pair work) and sorts the pairs into *jobs* of equal array sizes:

* stage vs polyhedron, grouped by the polyhedron's hull vertex count ``V``: the body's hull
  vertices lying in the prism of a touched triangle, just below its plane (method 2). The
  triangle's normal is turned to the stage's *outward side*: the side the body was on
  when the contact began, remembered by the pair's manifold (its cached normals point
  from the stage to the body). Only a new contact falls back to the side holding the
  middle of the body's extent; the body's center is never used, so a thin plate pushed
  past the surface's plane is still pushed back out, never through;
* polyhedron vs polyhedron, grouped by ``(V_a, F_a, V_b, F_b)`` vertex and face counts: the
  vertices of one body inside the other, measured against the reference face picked by
  fcl's normal (method 1);
* anything else (spheres, capsules) goes through the scalar :func:`collide.round_contacts`.

Each group is a handful of ``(g, ...)`` array operations, whatever its size ``g``. The
result is flat: ``pair_position (q,)`` (index into the pair list, ascending) and world
``point_a, point_b, normal (q, 3)``, normals from A to B, in the order the per-pair
reference path (:func:`reference_contacts.pair_contacts`) produces them: shape pairs in body
order; within a pair, vertex order, A's reference face's points before B's.
"""

from __future__ import annotations

from collections import defaultdict
from itertools import chain
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from . import settings
from .box_box import box_box_contacts, box_shape_frames
from .collide import (
    _POLYHEDRA,
    _midpoint_contacts,
    _triangle_table,
    contact_arrays,
    fcl_raw_contacts,
    round_contacts,
)
from .contacts import tie_key

if TYPE_CHECKING:
    from .bodies import Bodies
    from .collision_stage import CollisionObjects
    from .contacts import ManifoldStore

_EMPTY = (np.zeros(0, dtype=np.int64), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)))


class Job(NamedTuple):
    """One shape pair for a batch: its sequence number, the two shapes and their bodies
    (A is the stage for stage jobs) and fcl's contact records of the pair."""

    seq: int
    shape_a: Any
    body_a: int
    shape_b: Any
    body_b: int
    contacts: list


class _Contacts:
    """Collects contact chunks tagged with (shape-pair sequence number, order in the pair)."""

    def __init__(self) -> None:
        self.chunks: list[tuple] = []

    def add(self, seq, local, point_a, point_b, normal) -> None:
        if len(seq):
            self.chunks.append((seq, local, point_a, point_b, normal))

    def add_one(self, seq: int, result) -> None:
        if result is not None and len(result[0]):
            k = len(result[0])
            self.add(np.full(k, seq), np.arange(k), *result)

    def sorted(self, pair_of_seq: np.ndarray):
        """Flat ``(pair_position, point_a, point_b, normal)`` in sequence order."""
        if not self.chunks:
            return _EMPTY
        seq, local, point_a, point_b, normal = (
            np.concatenate(part) for part in zip(*self.chunks, strict=True)
        )
        order = np.lexsort((local, seq))  # by shape pair, then by order inside the pair
        return pair_of_seq[seq[order]], point_a[order], point_b[order], normal[order]


def narrow_phase(
    bodies: Bodies,
    objects: CollisionObjects,
    store: ManifoldStore,
    pairs: list,
    rotation: np.ndarray,
):
    """Contacts of body ``pairs`` ``[(a, c), ...]`` (see the module docstring).

    ``rotation (n, 3, 3)``: every body's world_from_body matrix; ``store``: the manifolds
    before this step's update (their normals keep a stage contact on its side). Must agree with
    :func:`reference_contacts.pair_contacts` called on each pair in turn (tested).
    """
    b = bodies
    # jobs grouped by array sizes: stage jobs by V, polyhedron jobs by (V_a, F_a, V_b, F_b)
    jobs: dict[str, defaultdict[Any, list[Job]]] = {
        "stage": defaultdict(list),
        "polyhedra": defaultdict(list),
    }
    contacts, pair_of_seq = _Contacts(), list[int]()
    # polyhedron pairs wait for fcl with their fcl objects; box pairs go to box_box first
    pending: list[tuple[Job, Any, Any]] = []
    boxes = BoxPairs()
    box_only, shapes, shape_objects = objects.box_only, b.shapes, objects.shape_objects
    for position, (a, c) in enumerate(pairs):
        if box_only[a] and box_only[c] and len(shapes[a]) == 1 == len(shapes[c]):
            # two one-box bodies (the common case): straight to the box batch
            boxes.add(len(pair_of_seq), shapes[a][0], a, shapes[c][0], c)
            pair_of_seq.append(position)
            continue
        for shape_a, obj_a in zip(b.shapes[a], objects.shape_objects[a], strict=True):
            for shape_c, obj_c, probe_c in zip(
                b.shapes[c], objects.shape_objects[c], objects.probe_objects[c], strict=True
            ):
                seq = len(pair_of_seq)
                pair_of_seq.append(position)
                if shape_a.kind == "mesh" and shape_c.kind in _POLYHEDRA:
                    found = fcl_raw_contacts(obj_a, probe_c)  # the triangles near C's hull
                    if found:
                        job = Job(seq, shape_a, a, shape_c, c, found)
                        jobs["stage"][len(shape_c.hull_vertices)].append(job)
                elif shape_a.kind == shape_c.kind == "box":
                    boxes.add(seq, shape_a, a, shape_c, c, obj_a, obj_c)
                elif shape_a.kind in _POLYHEDRA and shape_c.kind in _POLYHEDRA:
                    pending.append((Job(seq, shape_a, a, shape_c, c, []), obj_a, obj_c))
                elif shape_a.kind == shape_c.kind == "sphere" and coincident(b, a, c):
                    contacts.add_one(seq, coincident_spheres(b, a, shape_a, c, shape_c, rotation))
                else:
                    pose_c = (rotation[c], b.body_position[c])
                    contacts.add_one(
                        seq, round_contacts(shape_a, obj_a, shape_c, pose_c, obj_c, probe_c)
                    )
    if boxes.seq:  # analytic; coincident boxes and deep overlaps go to fcl as polyhedra
        general = _box_group(boxes, rotation, b, contacts, objects)
        to_fcl = [boxes.job(k, shape_objects) for k in np.flatnonzero(general).tolist()]
        if to_fcl:  # their fcl objects were not moved for the analytic path
            ends = [job.body_a for job, _, _ in to_fcl] + [job.body_b for job, _, _ in to_fcl]
            objects.move_shapes(b, ends, rotation)
        pending += to_fcl
    for job, obj_a, obj_c in pending:
        found = fcl_raw_contacts(obj_a, obj_c)
        if found:
            shape_a, shape_c = job.shape_a, job.shape_b
            sizes = (
                len(shape_a.hull_vertices),
                len(shape_a.plane_normals),
                len(shape_c.hull_vertices),
                len(shape_c.plane_normals),
            )
            jobs["polyhedra"][sizes].append(job._replace(contacts=found))
    for group in jobs["stage"].values():
        _stage_group(
            group,
            rotation,
            b.body_position,
            contacts,
            _cached_normals(store, [job.body_b for job in group]),
        )
    for group in jobs["polyhedra"].values():
        _polyhedron_group(group, rotation, b.body_position, contacts, b)
    return contacts.sorted(np.array(pair_of_seq, dtype=np.int64))


class BoxPairs:
    """The box shape pairs of a step, as columns (one list per field, in pair order): their
    sequence numbers, shapes and bodies, and the fcl objects of the pairs whose bodies hold
    several shapes (None for one-box bodies: their only object)."""

    def __init__(self) -> None:
        self.seq: list[int] = []
        self.shape_a: list[Any] = []
        self.body_a: list[int] = []
        self.shape_b: list[Any] = []
        self.body_b: list[int] = []
        self.objects: list[Any] = []
        self.one_box_bodies = True  # every pair joins two bodies of a single box shape

    def add(self, seq, shape_a, body_a, shape_b, body_b, obj_a=None, obj_b=None) -> None:
        self.one_box_bodies &= obj_a is None
        self.seq.append(seq)
        self.shape_a.append(shape_a)
        self.body_a.append(body_a)
        self.shape_b.append(shape_b)
        self.body_b.append(body_b)
        self.objects.append(None if obj_a is None else (obj_a, obj_b))

    def job(self, k: int, shape_objects: dict) -> tuple[Job, Any, Any]:
        """Pair ``k`` as a polyhedron job with its two fcl objects (for the fcl path)."""
        a, c = self.body_a[k], self.body_b[k]
        obj_a, obj_c = self.objects[k] or (shape_objects[a][0], shape_objects[c][0])
        return Job(self.seq[k], self.shape_a[k], a, self.shape_b[k], c, []), obj_a, obj_c


def _box_group(
    jobs: BoxPairs, rotation, bodies, contacts: _Contacts, objects: CollisionObjects
) -> np.ndarray:
    """Analytic contacts of box pairs (:mod:`box_box`: separating axes + clipping); returns
    ``general (g,)`` bool, the pairs left to the general polyhedron path: bodies with
    (nearly) the same center (:func:`coincident`) and overlaps deeper than
    ``BOX_DEEP_OVERLAP``.

    Reference: :func:`reference_contacts.pair_contacts` ->
    :func:`reference_box_box.box_box_contacts_reference` (one pair)."""
    a = np.array(jobs.body_a, dtype=np.int64)
    c = np.array(jobs.body_b, dtype=np.int64)
    general = coincident_mask(bodies, a, c)
    analytic = np.flatnonzero(~general)
    if len(analytic) == 0:
        return general
    frames = []
    chosen = analytic.tolist()
    for shapes, index in ((jobs.shape_a, a), (jobs.shape_b, c)):
        body = index[analytic]
        r, x = rotation[body], bodies.body_position[body]
        if jobs.one_box_bodies:  # each body's only box, kept by CollisionObjects
            offset, half = objects.box_offset[body], objects.box_half[body]
        else:
            offset = np.array([shapes[k].body_from_shape for k in chosen])  # (g, 4, 4)
            half = np.array([shapes[k].geometry.side for k in chosen], dtype=np.float64) / 2.0
        center, world = box_shape_frames(r, x, offset)
        frames += [center, world, half]
    pair, local, point_a, point_b, normal, deep = box_box_contacts(*frames)
    seq = np.array(jobs.seq, dtype=np.int64)[analytic]
    contacts.add(seq[pair], local, point_a, point_b, normal)
    general[analytic] = deep
    return general


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


def _pose(
    bodies: list, rotation: np.ndarray, position: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Rotations ``(g, 3, 3)`` and positions ``(g, 3)`` of ``bodies``."""
    index = np.array(bodies, dtype=np.int64)
    return rotation[index], position[index]


def _to_world(rotation, position, points):
    """World points ``(g, k, 3)``: ``R p + x`` for body-frame points ``(g, k, 3)``."""
    return np.einsum("gij,gkj->gki", rotation, points) + position[:, None]


def _cached_normals(store, bodies: list) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """World normals ``(g, S, 3)`` (stage -> body), stage points ``(g, S, 3)`` and ``valid
    (g, S)`` of the manifolds of the stage with ``bodies`` (the stage frame is the world
    frame)."""
    rows = store.rows_of([(0, body) for body in bodies])
    known = np.array([row is not None for row in rows])
    index = np.array([row if row is not None else 0 for row in rows], dtype=np.int64)
    slots = np.arange(store.normal_local.shape[1])
    valid = known[:, None] & (slots < store.count[index][:, None])
    return store.normal_local[index], store.local_a[index], valid


def _outward_side(normal: np.ndarray, corner: np.ndarray, height: np.ndarray, cached) -> np.ndarray:
    """(g, T) +-1 turning each touched triangle's normal to the stage's outward side.

    The cached normal most (anti-)parallel to the triangle's decides when it is within 60
    degrees of it and its point lies on the triangle's plane (``corner (g, T, 3)``: a
    vertex of each triangle); otherwise (a new contact) the side holding the middle of the
    hull's extent along the normal.
    """
    cached_normal, cached_point, valid = cached
    # distance of cached point k from triangle t's plane, |n_t . (p_k - p0_t)|, (g, T, S)
    offset = np.abs(
        np.einsum("gti,gki->gtk", normal, cached_point) - (normal * corner).sum(axis=2)[..., None]
    )
    on_plane = valid[:, None, :] & (offset < settings.OUTWARD_SIDE_PLANE_DISTANCE)
    # n_t . c_k for every triangle t and cached normal k, (g, T, S)
    alignment = np.einsum("gti,gki->gtk", normal, cached_normal) * on_plane
    strongest = np.take_along_axis(alignment, np.abs(alignment).argmax(axis=2)[..., None], axis=2)[
        ..., 0
    ]
    middle = np.where(height.max(axis=2) + height.min(axis=2) < 0, -1.0, 1.0)
    return np.where(np.abs(strongest) > settings.OUTWARD_SIDE_ALIGNMENT, np.sign(strongest), middle)


def _stage_group(jobs, rotation, position, contacts: _Contacts, cached) -> None:
    """Vertex-triangle contacts of ``g`` hulls with ``V`` vertices against the stage
    (``cached``: the pairs' cached manifold normals, see :func:`_cached_normals`).

    Reference: :func:`reference_contacts.stage_polyhedron_contacts` (one shape pair)."""
    stage = jobs[0].shape_a
    table = _triangle_table(stage)
    seq = np.array([job.seq for job in jobs], dtype=np.int64)
    ids = _touched_triangles(
        [[c.b1 for c in job.contacts] for job in jobs], len(stage.ray_triangles)
    )
    tris = stage.ray_triangles[ids]  # (g, T, 3, 3) world (the stage frame is world)
    r, x = _pose([job.body_b for job in jobs], rotation, position)
    hull = np.stack([job.shape_b.hull_vertices for job in jobs])
    verts = _to_world(r, x, hull)  # (g, V, 3)
    normal = table["normal"][ids]
    # signed height of vertex v above triangle t's plane: n_t . (x_v - p0_t), (g, T, V)
    height = (
        np.einsum("gti,gvi->gtv", normal, verts) - (normal * tris[:, :, 0]).sum(axis=2)[..., None]
    )
    side = _outward_side(normal, tris[:, :, 0], height, cached)  # (g, T)
    normal, height = normal * side[..., None], height * side[..., None]
    extent = (verts.max(axis=1) - verts.min(axis=1)).max(axis=1)
    # a vertex far below a thin triangle is on the other side of it, not in contact
    candidate = (
        (height < settings.STAGE_SPECULATIVE_DISTANCE)
        & (height > -settings.STAGE_BELOW_FRACTION * extent[:, None, None])
        & _in_prisms(table, ids, tris, verts)
    )
    # each vertex keeps its shallowest triangle (the surface it is really resting on)
    best = np.where(candidate, height, -np.inf).argmax(axis=1)  # (g, V)
    g, v = np.nonzero(candidate.any(axis=1))
    t = best[g, v]
    n, depth, point_b = normal[g, t], -height[g, t, v], verts[g, v]
    contacts.add(seq[g], v, point_b + n * depth[:, None], point_b, n)
    for k in np.flatnonzero(~candidate.any(axis=(1, 2))).tolist():
        # an edge crossing a face: fcl's points with the first triangle's normal
        mid, _, depths, _ = contact_arrays(jobs[k].contacts)
        depths = depths - settings.STAGE_SPECULATIVE_DISTANCE  # probe depth -> shape depth
        contacts.add_one(
            seq[k], _midpoint_contacts(mid, np.tile(normal[k, 0], (len(mid), 1)), depths)
        )


def _touched_triangles(triangle_ids: list, n_triangles: int) -> np.ndarray:
    """(g, T) ids of the distinct triangles each job touches, ascending.

    Rows are padded by repeating their last id (a duplicate triangle changes no result).
    """
    lengths = [len(ids) for ids in triangle_ids]
    job = np.repeat(np.arange(len(triangle_ids)), lengths)
    tri = np.fromiter(chain.from_iterable(triangle_ids), dtype=np.int64, count=sum(lengths))
    # one key per (job, triangle): unique keys are sorted by job, then by triangle
    key = np.unique((job * n_triangles + tri)[tri >= 0])
    job, tri = np.divmod(key, n_triangles)
    counts = np.bincount(job, minlength=len(triangle_ids))
    starts = np.cumsum(counts) - counts
    slot = np.minimum(np.arange(counts.max()), counts[:, None] - 1)
    return tri[starts[:, None] + slot]


def _in_prisms(table: dict, ids: np.ndarray, tris: np.ndarray, verts: np.ndarray) -> np.ndarray:
    """(g, T, V) bool: vertex v projected on triangle t's plane falls inside the triangle."""
    e0, e1, denom = table["e0"][ids], table["e1"][ids], table["denom"][ids]
    d00, d01, d11 = table["d00"][ids], table["d01"][ids], table["d11"][ids]
    rel = verts[:, None, :, :] - tris[:, :, None, 0]  # x_v - p0_t, (g, T, V, 3)
    d20 = (rel * e0[:, :, None]).sum(axis=3)
    d21 = (rel * e1[:, :, None]).sum(axis=3)
    # barycentric (v, w) of the projection: [d00 d01; d01 d11] [v; w] = [d20; d21]
    bary_v = (d11[..., None] * d20 - d01[..., None] * d21) / denom[..., None]
    bary_w = (d00[..., None] * d21 - d01[..., None] * d20) / denom[..., None]
    tolerance = settings.BARYCENTRIC_TOLERANCE
    return (bary_v >= -tolerance) & (bary_w >= -tolerance) & (bary_v + bary_w <= 1 + tolerance)


def _polyhedron_group(jobs, rotation, position, contacts: _Contacts, bodies) -> None:
    """Vertex contacts of ``g`` polyhedron pairs of equal vertex and face counts.

    Reference: :func:`reference_contacts.polyhedron_contacts` (one shape pair)."""
    seq = np.array([job.seq for job in jobs], dtype=np.int64)
    # fcl's deepest normal (A -> B) picks the touching faces; coincident bodies (whose fcl
    # normal is an arbitrary axis) get their pair's spread direction instead
    n = np.array([deepest_record(job.contacts).normal for job in jobs])
    a = np.array([job.body_a for job in jobs])
    c = np.array([job.body_b for job in jobs])
    coincident = coincident_mask(bodies, a, c)
    if coincident.any():
        n[coincident] = spread_direction(a[coincident], c[coincident])
    frame_a = _pose([job.body_a for job in jobs], rotation, position)
    frame_b = _pose([job.body_b for job in jobs], rotation, position)
    shapes_a, shapes_b = [job.shape_a for job in jobs], [job.shape_b for job in jobs]
    found = np.zeros(len(jobs), dtype=bool)
    n_first = len(shapes_b[0].hull_vertices)  # B's vertices: the sort keys of A's face
    # A's face against B's vertices (sign +1), then B's face against A's vertices (sign -1)
    for direction, (ref, ref_frame, inc, inc_frame, sign) in enumerate(
        ((shapes_a, frame_a, shapes_b, frame_b, 1.0), (shapes_b, frame_b, shapes_a, frame_a, -1.0))
    ):
        inc_rotation, inc_position = inc_frame
        inc_vertices = np.stack([s.hull_vertices for s in inc])
        g, v, on_face, verts, face_normal = _reference_face_contacts(
            ref, ref_frame, _to_world(inc_rotation, inc_position, inc_vertices), sign * n
        )
        found[g] = True
        local = direction * n_first + v  # A's reference points first, then B's
        contact_normal = sign * face_normal[g]  # always A -> B
        if sign > 0:
            contacts.add(seq[g], local, on_face, verts[g, v], contact_normal)
        else:
            contacts.add(seq[g], local, verts[g, v], on_face, contact_normal)
    for k in np.flatnonzero(~found).tolist():  # no face faces the other body: fcl's points
        mid, normals, depths, _ = contact_arrays(jobs[k].contacts)
        contacts.add_one(seq[k], _midpoint_contacts(mid, normals, depths))


def deepest_record(records: list):
    """fcl's deepest contact record; near-equal depths (``TIE_QUANTUM``) go to the first,
    so the choice does not hang on the rounding of the poses (plain Python: a job has only
    a few records, and NumPy calls would cost more than they save)."""
    # tie_key of |depth|: Python's round, like np.round, rounds halves to even
    keys = [round(abs(record.penetration_depth) / settings.TIE_QUANTUM) for record in records]
    return records[keys.index(max(keys))]


def _reference_face_contacts(ref_shapes, ref_frame, verts, towards):
    """Vertices ``verts (g, V, 3)`` inside the reference hulls, on their face facing ``towards``.

    Returns the job and vertex indices of the contacts, their points on the reference face,
    all vertices and the reference face normals ``(g, 3)`` (world, outward).
    """
    rotation, position = ref_frame
    planes = np.stack([s.plane_normals for s in ref_shapes])  # (g, F, 3) body frame
    offsets = np.stack([s.plane_offsets for s in ref_shapes])  # (g, F)
    face_normals = np.einsum("gij,gfj->gfi", rotation, planes)  # outward, world frame
    alignment = (face_normals * towards[:, None]).sum(axis=2)
    face = tie_key(alignment).argmax(axis=1)  # the first of (nearly) equally aligned faces
    jobs = np.arange(len(face))
    # else no face of this body faces the other
    facing = alignment[jobs, face] >= settings.REFERENCE_FACE_ALIGNMENT
    normal = face_normals[jobs, face]
    tolerance = settings.SPECULATIVE_DISTANCE
    # inside the hull planes n_f . p <= c_f + tol, p in the reference body frame R^T (x - x_r)
    local = np.einsum("gji,gvj->gvi", rotation, verts - position[:, None])
    inside = (np.einsum("gvj,gfj->gvf", local, planes) - offsets[:, None] <= tolerance).all(axis=2)
    # depth below the reference face plane n_f . x = c_f + n_f . x_ref
    depth = (offsets[jobs, face] + (normal * position).sum(axis=1))[:, None] - np.einsum(
        "gvi,gi->gv", verts, normal
    )
    g, v = np.nonzero(inside & (depth > -tolerance) & facing[:, None])
    on_face = verts[g, v] + depth[g, v][:, None] * normal[g]  # x + d n_f
    return g, v, on_face, verts, normal
