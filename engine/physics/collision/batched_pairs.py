"""Batched contacts of body pairs away from the stage (rules of :mod:`pair_table`).

* ``box-box`` (:func:`box_pair_batch`): analytic, no fcl: separating axes and face clipping
  (:mod:`box_box`) for all box pairs at once; pairs of (nearly) coincident bodies and
  overlaps deeper than ``BOX_DEEP_OVERLAP`` are declined to ``hull-hull``;
* ``hull-hull`` (:func:`hull_pair_batch`): fcl's deepest normal ``n`` (A -> B) picks the
  reference face most aligned with it on A (with ``-n`` on B); every vertex of the other
  body inside the reference hull (planes ``n_f . p <= c_f`` inflated by
  ``SPECULATIVE_DISTANCE``) becomes a contact at depth ``d = c_f + n_f . x_ref - n_f . x``
  below the face (method 1 of :mod:`collide`), A's face first. Jobs are grouped by
  ``(V_a, F_a, V_b, F_b)`` vertex and face counts, a group is a few ``(g, ...)`` arrays;
* ``sphere-sphere``, ``stage-round``, ``fcl``: one small call per job (fcl's points, the
  exact sphere-triangle point, the spread direction of coincident spheres).

Reference twins: :mod:`reference_pairs`, one job at a time.
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np

from ..core import settings
from ..core.shapes import Shape
from ..core.vectors import vecdot
from .box_box import box_box_parts, box_shape_frames
from .collide import round_stage_contacts
from .contact_helpers import (
    body_poses,
    coincident,
    coincident_mask,
    coincident_spheres,
    contact_arrays,
    deepest_record,
    fcl_raw_contacts,
    generic_contacts,
    midpoint_contacts,
    spread_direction,
    to_world,
)
from .contacts import tie_key
from .pair_rules import (
    FCL_FEATURE,
    ContactBatch,
    JobColumns,
    PairContext,
    PairJob,
    job_columns,
)


def box_pair_batch(jobs: list[PairJob], context: PairContext, out: ContactBatch) -> list[PairJob]:
    """Analytic contacts of box pairs (:mod:`box_box`); returns the jobs declined to the
    general polyhedron path: bodies with (nearly) the same center (:func:`coincident`) and
    overlaps deeper than ``BOX_DEEP_OVERLAP``, their fcl objects moved (the analytic path
    does not move them)."""
    bodies, objects = context.bodies, context.objects
    column = job_columns(jobs)
    a = np.array(column.body_a, dtype=np.int64)
    c = np.array(column.body_b, dtype=np.int64)
    general = coincident_mask(bodies, a, c)
    analytic = np.flatnonzero(~general)
    if len(analytic):
        general[analytic] = _analytic_boxes(column, analytic, a, c, context, out)
    declined = [jobs[k] for k in np.flatnonzero(general).tolist()]
    if declined:
        ends = [job.body_a for job in declined] + [job.body_b for job in declined]
        objects.move_shapes(bodies, ends, context.rotation)
    return declined


def _analytic_boxes(column: JobColumns, analytic, a, c, context, out: ContactBatch) -> np.ndarray:
    """Contacts of the box jobs ``analytic`` (indices into the job ``column``s, bodies
    ``a``, ``c``); returns ``deep (g,)`` bool, the pairs overlapping deeper than
    ``BOX_DEEP_OVERLAP``."""
    bodies, objects, rotation = context.bodies, context.objects, context.rotation
    g = len(analytic)
    body = np.concatenate([a[analytic], c[analytic]])  # A's bodies, then B's, (2 g,)
    if objects.single_box[body].all():  # each body's only box, kept by CollisionObjects
        offset, half = objects.box_offset[body], objects.box_half[body]
    else:
        jobs = analytic.tolist()
        boxes = [column.shape_a[k] for k in jobs] + [column.shape_b[k] for k in jobs]
        offset = np.array([box.body_from_shape for box in boxes])  # (2 g, 4, 4)
        half = np.array([box.geometry.side for box in boxes], dtype=np.float64) / 2.0
    center, world = box_shape_frames(rotation[body], bodies.body_position[body], offset)
    # the face and the edge contacts as two chunks: the batch sorts by (job, candidate)
    parts, deep = box_box_parts(center[:g], world[:g], half[:g], center[g:], world[g:], half[g:])
    seq = np.array(column.seq, dtype=np.int64)[analytic]
    for pair, local, point_a, point_b, normal, feature in parts:
        out.add(seq[pair], local, point_a, point_b, normal, feature)
    return deep


def hull_pair_batch(jobs: list[PairJob], context: PairContext, out: ContactBatch) -> list[PairJob]:
    """Vertex contacts of polyhedron pairs (boxes, hulls, cylinders, cones): fcl's normal,
    then the vertices inside the other hull, grouped by vertex and face counts."""
    groups: defaultdict[tuple[int, int, int, int], list[PairJob]] = defaultdict(list)
    for job in jobs:
        found = fcl_raw_contacts(job.object_a, job.object_b)
        if found:
            sizes = (*_hull_sizes(job.shape_a), *_hull_sizes(job.shape_b))
            groups[sizes].append(job._replace(records=found))
    for group in groups.values():
        _polyhedron_group(
            group, context.rotation, context.bodies.body_position, out, context.bodies
        )
    return []


def _hull_sizes(shape: Shape) -> tuple[int, int]:
    """``(vertex count, face count)`` of a hull shape."""
    faces = 0 if shape.plane_normals is None else len(shape.plane_normals)
    return len(shape.hull_vertices), faces


def sphere_pair_batch(
    jobs: list[PairJob], context: PairContext, out: ContactBatch
) -> list[PairJob]:
    """Two spheres: fcl's point, or the spread direction when their centers coincide."""
    bodies = context.bodies
    for job in jobs:
        if coincident(bodies, job.body_a, job.body_b):
            result = coincident_spheres(
                bodies, job.body_a, job.shape_a, job.body_b, job.shape_b, context.rotation
            )
        else:
            result = generic_contacts(job.object_a, job.object_b)
        out.add_one(job.seq, result)
    return []


def stage_round_batch(
    jobs: list[PairJob], context: PairContext, out: ContactBatch
) -> list[PairJob]:
    """Spheres and capsules on the stage (:func:`collide.round_stage_contacts`)."""
    for job in jobs:
        pose_b = context.pose(job.body_b)
        out.add_one(
            job.seq,
            round_stage_contacts(job.shape_a, job.object_a, job.shape_b, pose_b, job.probe_b),
        )
    return []


def fcl_pair_batch(jobs: list[PairJob], context: PairContext, out: ContactBatch) -> list[PairJob]:
    """fcl's own points (method 3 of :mod:`collide`), one query per job."""
    for job in jobs:
        out.add_one(job.seq, generic_contacts(job.object_a, job.object_b))
    return []


def _polyhedron_group(jobs, rotation, position, contacts: ContactBatch, bodies) -> None:
    """Vertex contacts of ``g`` polyhedron pairs of equal vertex and face counts.

    Reference: :func:`reference_pairs.polyhedron_contacts` (one shape pair)."""
    seq = np.array([job.seq for job in jobs], dtype=np.int64)
    # fcl's deepest normal (A -> B) picks the touching faces; coincident bodies (whose fcl
    # normal is an arbitrary axis) get their pair's spread direction instead
    n = np.array([deepest_record(job.records).normal for job in jobs])
    a = np.array([job.body_a for job in jobs])
    c = np.array([job.body_b for job in jobs])
    together = coincident_mask(bodies, a, c)
    if together.any():
        n[together] = spread_direction(a[together], c[together])
    frame_a = body_poses([job.body_a for job in jobs], rotation, position)
    frame_b = body_poses([job.body_b for job in jobs], rotation, position)
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
            ref, ref_frame, to_world(inc_rotation, inc_position, inc_vertices), sign * n
        )
        found[g] = True
        local = direction * n_first + v  # A's reference points first, then B's
        contact_normal = sign * face_normal[g]  # always A -> B
        if sign > 0:
            contacts.add(seq[g], local, on_face, verts[g, v], contact_normal)
        else:
            contacts.add(seq[g], local, verts[g, v], on_face, contact_normal)
    for k in np.flatnonzero(~found).tolist():  # no face faces the other body: fcl's points
        mid, normals, depths, _ = contact_arrays(jobs[k].records)
        contacts.add_one(seq[k], midpoint_contacts(mid, normals, depths), FCL_FEATURE)


def _reference_face_contacts(ref_shapes, ref_frame, verts, towards):
    """Vertices ``verts (g, V, 3)`` inside the reference hulls, on their face facing ``towards``.

    Returns the job and vertex indices of the contacts, their points on the reference face,
    all vertices and the reference face normals ``(g, 3)`` (world, outward).
    """
    rotation, position = ref_frame
    planes = np.stack([s.plane_normals for s in ref_shapes])  # (g, F, 3) body frame
    offsets = np.stack([s.plane_offsets for s in ref_shapes])  # (g, F)
    face_normals = np.einsum("gij,gfj->gfi", rotation, planes)  # outward, world frame
    alignment = vecdot(face_normals, towards[:, None])  # n_f . towards
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
    depth = (offsets[jobs, face] + vecdot(normal, position))[:, None] - np.einsum(
        "gvi,gi->gv", verts, normal
    )
    g, v = np.nonzero(inside & (depth > -tolerance) & facing[:, None])
    on_face = verts[g, v] + depth[g, v, None] * normal[g]  # x + d n_f
    return g, v, on_face, verts, normal
