r"""Batched contacts of hulls resting on the stage mesh (rule ``stage-hull`` of :mod:`pair_table`).

The stage's triangle grid (:mod:`stage_grid`, built once) names the triangles near every
body at once: those whose box overlaps the body's AABB grown by
``STAGE_NEAR_DISTANCE`` (a superset of what fcl's BVH reports for the body's *probe*, the
shape grown by ``STAGE_SPECULATIVE_DISTANCE``, which reaches at most that far). The contacts
are the body's hull vertices lying in the prism of a nearby triangle, just below its plane
(method 2 of :mod:`collide`). For vertex ``v`` and triangle ``t`` (unit normal ``n_t``,
corner ``p0_t``) the signed height is

.. math::

    h_{tv} = n_t \cdot (x_v - p_{0t}),

and ``v`` touches ``t`` when ``h < STAGE_SPECULATIVE_DISTANCE``, ``h > -STAGE_BELOW_FRACTION
* extent`` and its projection is inside the triangle (barycentric test, Ericson 3.4). Each
vertex keeps its *resting* triangle: the shallowest it has passed (the largest ``h < 0``,
its way out of the stage's solid), else the nearest (the smallest ``h >= 0``: the surface
it meets first); the contact depth is ``-h``. In a corner it also keeps the shallowest of
the triangles turned 45 to 135 degrees from that one (``|n_t . n_best| <
STAGE_CORNER_COSINE``) that it has passed and that still lies under it once it is pushed
out of its resting triangle (to ``STAGE_CORNER_PUSH`` in front of it): a vertex pressed
into a floor beside a wall is pushed out of both, also when it has left the floor's prism
at the wall's foot (at most ``STAGE_CORNER_REACH`` below the floor), while a vertex at a
convex edge (a skirting board's top and front) is pushed out of one face only (the
opposite face of a thin slab is never a second surface: it would push the vertex through
the slab). The triangle's normal is
turned to the stage's *outward side*: the side the body was on when the contact began,
remembered by the pair's manifold (its cached normals point from the stage to the body).
Only a new contact falls back to :func:`contact_helpers.new_contact_side`: the back when
the whole hull is behind the plane (a body behind a one-sided wall), up on a floor-like
triangle when the body's center is on or above its plane (a stage may wind its floor
either way), the side of the body's center on a wall-like triangle level with it or
whose plane passes clear of it (:func:`contact_helpers.center_decides`; a thin slab's
side cutting the body near its middle says nothing of where the body is), else the
triangle's front (its winding normal): a body spawned or teleported
with its center below a floor is pushed up, never down through it, and a thin plate
pushed past the surface's plane is still pushed back out.

A vertex that has passed a triangle rests on it only when the segment to its foot on it
stays inside the stage's solid, crossing no other stage triangle
(:mod:`stage_crossings`): a vertex just below a thin table top is in the prism of the
top face but outside the slab, and the top would pull the body through the slab.

A triangle only near the body (in the grid's answer, not fcl's) never holds a contact: a
vertex inside its prism within ``STAGE_SPECULATIVE_DISTANCE`` of its plane puts the probe on
it. A job whose hull has no vertex in contact (an edge crossing a face) asks fcl after all
and takes fcl's points, as before the grid, with the outward normal of the triangle fcl
names that the hull is least deep behind, the face it entered through (kept from the
first pass, :func:`_known_edge`). A job with vertex contacts whose hull crosses a triangle
no vertex rests on (:func:`stage_crossings.crossed_faces`: a thin slab's side cutting a
body that rests on the floor) asks fcl too and takes its points on that triangle with
the triangle's normal. Jobs are grouped by
the hull's vertex count ``V``; each group is a handful of ``(g, T, V)`` array operations,
whatever its size ``g``.
Reference: :func:`reference_pairs.stage_hull_pair`.
"""

from __future__ import annotations

from collections import defaultdict
from itertools import chain

import numpy as np

from ..core import settings
from ..core.vectors import dot
from .contact_helpers import (
    body_poses,
    center_decides,
    contact_arrays,
    fcl_raw_contacts,
    level_with,
    midpoint_contacts,
    new_contact_side,
    to_world,
    triangle_table,
)
from .pair_rules import FCL_FEATURE, ContactBatch, PairContext, PairJob
from .stage_crossings import crossed_face_points, crossed_faces, ways_out_crossed
from .stage_grid import stage_grid

#: a job with stage triangles but no vertex in contact, its triangle ids ``(T,)``, their
#: outward normals ``(T, 3)`` (stage -> body) and the signed heights ``(T, V)`` of the hull's
#: vertices above their planes, from :func:`_stage_group`
EdgeJob = tuple[PairJob, np.ndarray, np.ndarray, np.ndarray]
#: a job with vertex contacts whose hull crosses stage triangles without a vertex on them
#: (:func:`stage_crossings.crossed_faces`): ``{triangle id: (outward normal (3,), the
#: hull's least vertex height above it)}``, and the job's vertex count
CrossedJob = tuple[PairJob, dict, int]


def stage_hull_batch(jobs: list[PairJob], context: PairContext, out: ContactBatch) -> list[PairJob]:
    """Contacts of hull shapes (box, convex, cylinder, cone) with the stage mesh (A)."""
    nearby, count = nearby_triangles(jobs, context)
    crossed: list[CrossedJob] = []
    edge_jobs = _vertex_contacts(jobs, nearby, count, context, out, crossed)
    if edge_jobs or crossed:  # fcl's triangles and points for these few
        asking = chain((edge[0] for edge in edge_jobs), (job for job, _, _ in crossed))
        bodies = np.array(sorted({job.body_b for job in asking}), dtype=np.int64)
        context.objects.move(context.bodies, bodies, context.rotation[bodies])  # and probes
    for job, faces, n_vertices in crossed:  # a thin slab's side across a resting body
        point_a, point_b, normal = crossed_face_points(
            fcl_raw_contacts(job.object_a, job.probe_b), faces
        )
        local = np.arange(len(normal))  # after the vertex and corner contacts, as the twin
        seq = np.full(len(normal), job.seq)
        out.add(seq, 2 * n_vertices + local, point_a, point_b, normal, FCL_FEATURE + local)
    if edge_jobs:  # no vertex in contact
        asked = []
        for job, ids, normals, heights in edge_jobs:
            records = fcl_raw_contacts(job.object_a, job.probe_b)
            if records and not _known_edge(job.seq, records, (ids, normals, heights), out):
                asked.append(job._replace(records=records))
        if asked:  # fcl named a triangle the grid did not (never seen): the full pass
            named = [np.array([c.b1 for c in job.records], dtype=np.int64) for job in asked]
            touched, count = _touched_triangles(named, len(jobs[0].shape_a.ray_triangles))
            _vertex_contacts(asked, touched, count, context, out, None)
    return []


def _known_edge(seq: int, records: list, triangles, out) -> bool:
    """Add fcl's points of an edge job (no vertex in contact) when every triangle fcl
    names was among its grid triangles; returns whether it did. ``triangles``: the job's
    grid triangle ids ``(T,)``, their outward normals ``(T, 3)`` and the hull's vertex
    heights ``(T, V)`` above them (:data:`EdgeJob`).

    Those triangles were tested in the first pass with all the body's near triangles (no
    vertex rests on any of them, their ways out tested against the whole set), and their
    normals and heights are known: the
    job's contacts are fcl's points with the normal of the named triangle the hull is least
    deep behind (:func:`_entry_face`),
    exactly what :func:`_stage_group` gives in fcl's second pass, without that pass
    over the arrays."""
    ids, normals, heights = triangles
    touched = sorted({c.b1 for c in records})
    grid = ids.tolist()
    if touched[0] < 0 or not set(touched) <= set(grid):
        return False
    named = [grid.index(t) for t in touched]
    entry = named[_entry_face(heights[named])]
    _add_fcl_points(out, seq, records, normals[entry], heights[entry])
    return True


def _entry_face(heights: np.ndarray) -> int:
    """The row of ``heights (T, V)`` (the hull's vertex heights above triangles fcl named)
    whose triangle the hull is least deep behind (the largest least height; the first of
    equals): the face the body entered through, whose normal an edge crossing takes.

    The lowest-id triangle (the rule before) gave a cube whose edge crossed a 4 cm table
    top's front-bottom edge by 3 mm the slab's bottom face (-Y, the cube 10 cm deep behind
    its plane) instead of the front face (+Z, a few cm): pushed along the slab, it went
    6.9 cm into it."""
    return int(heights.min(axis=1).argmax())


def _add_fcl_points(
    out: ContactBatch, seq: int, records: list, normal: np.ndarray, heights: np.ndarray
) -> None:
    """fcl's midpoints of a stage job's probe records, all with ``normal (3,)`` (stage ->
    body) of one triangle, their depths turned from the probe's into the shape's and at
    most how far the hull's deepest vertex is below that triangle's plane (``heights
    (V,)``: the vertices' signed heights above it):
    no point of a convex hull is deeper below a plane than its deepest vertex, while fcl's
    depth of a probe against a single triangle can be the way out through the triangle
    (measured: up to 0.5 m for 0.2 m cubes on a floor, popping them up)."""
    mid, _, depths, _ = contact_arrays(records)
    depths = depths - settings.STAGE_SPECULATIVE_DISTANCE  # probe depth -> shape depth
    depths = np.minimum(depths, -heights.min())
    out.add_one(seq, midpoint_contacts(mid, np.tile(normal, (len(mid), 1)), depths), FCL_FEATURE)


def nearby_triangles(jobs: list[PairJob], context: PairContext) -> tuple[np.ndarray, np.ndarray]:
    """Ids of the stage triangles near each job's body B: their box overlaps B's world AABB
    grown by ``STAGE_NEAR_DISTANCE`` (all jobs in one grid query, :mod:`stage_grid`), as
    padded rows (:func:`_padded_rows`): ``ids (g, T)`` and ``count (g,)``."""
    bodies = context.bodies
    body = np.array([job.body_b for job in jobs], dtype=np.int64)
    lo = bodies.body_aabb_min[body] - settings.STAGE_NEAR_DISTANCE
    hi = bodies.body_aabb_max[body] + settings.STAGE_NEAR_DISTANCE
    owner, triangle = stage_grid(jobs[0].shape_a).candidates(lo, hi)  # sorted, distinct
    return _padded_rows(owner, triangle, len(jobs))


def _vertex_contacts(
    jobs, ids: np.ndarray, count: np.ndarray, context, out, crossed: list | None
) -> list[EdgeJob]:
    """Contacts of ``jobs`` with their triangles (padded rows ``ids (g, T)`` holding
    ``count (g,)`` ids each), grouped by hull size; returns the jobs with triangles but no
    vertex in contact, as :data:`EdgeJob`, and appends to ``crossed`` the jobs crossing
    a face without a vertex on it (:data:`CrossedJob`); with ``crossed`` None (fcl's
    second pass) the jobs without a vertex in contact take fcl's points instead, see
    :func:`_stage_group`."""
    groups: defaultdict[int, list[int]] = defaultdict(list)
    for k, (job, n_ids) in enumerate(zip(jobs, count.tolist(), strict=True)):
        if n_ids:
            groups[len(job.shape_b.hull_vertices)].append(k)
    edge_jobs: list[EdgeJob] = []
    for group in groups.values():
        members = [jobs[k] for k in group]
        rows = np.array(group, dtype=np.int64)
        # the group's rows, padded to its own longest (the same ids, fewer repeats)
        group_ids = ids[rows, : count[rows].max()]
        cached = _cached_normals(context.store, [job.body_b for job in members])
        edge_jobs += _stage_group(
            members,
            group_ids,
            (context.rotation, context.bodies.body_position),
            out,
            cached,
            crossed,
        )
    return edge_jobs


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


def _outward_side(
    normal: np.ndarray,
    corner: np.ndarray,
    height: np.ndarray,
    center: np.ndarray,
    cached,
    level: np.ndarray,
) -> np.ndarray:
    """(g, T) +-1 turning each touched triangle's normal to the stage's outward side.

    The cached normal most (anti-)parallel to the triangle's decides when it is within 60
    degrees of it and its point lies on the triangle's plane (``corner (g, T, 3)``: a
    vertex of each triangle); otherwise (a new contact) :func:`new_contact_side` from the
    vertices' heights ``height (g, T, V)``, the body's center ``center (g, 3)`` and whether
    that center is ``level (g, T)`` with each triangle.
    """
    cached_normal, cached_point, valid = cached
    # distance of cached point k from triangle t's plane, |n_t . (p_k - p0_t)|, (g, T, S)
    offset = np.abs(
        np.einsum("gti,gki->gtk", normal, cached_point) - dot(normal, corner)[..., None]
    )
    on_plane = valid[:, None, :] & (offset < settings.OUTWARD_SIDE_PLANE_DISTANCE)
    # n_t . c_k for every triangle t and cached normal k, (g, T, S)
    alignment = np.einsum("gti,gki->gtk", normal, cached_normal) * on_plane
    strongest = np.take_along_axis(alignment, np.abs(alignment).argmax(axis=2)[..., None], axis=2)[
        ..., 0
    ]
    # a new contact: the body's heights decide (floor-like triangles push up)
    center_height = np.einsum("gti,gi->gt", normal, center) - dot(normal, corner)
    highest = height.max(axis=2)
    decides = center_decides(level, center_height, highest, height.min(axis=2))
    new = new_contact_side(normal[..., 1], center_height, highest, decides)
    return np.where(np.abs(strongest) > settings.OUTWARD_SIDE_ALIGNMENT, np.sign(strongest), new)


def _stage_group(
    jobs, ids: np.ndarray, poses, contacts: ContactBatch, cached, crossed: list | None
) -> list[EdgeJob]:
    """Vertex-triangle contacts of ``g`` hulls with ``V`` vertices against the stage
    triangles ``ids (g, T)`` (ascending per row, padded by repeats; ``poses``: every body's rotation
    ``(n, 3, 3)`` and position ``(n, 3)``; ``cached``: the pairs' cached manifold normals,
    see :func:`_cached_normals`). Returns the jobs without a vertex in contact with their
    triangles and outward normals (:data:`EdgeJob`) and appends the jobs crossing a face
    without a vertex on it to ``crossed`` (:data:`CrossedJob`), or with ``crossed`` None
    (fcl's second pass) gives the first fcl's points (their ``records``) and returns none.

    Reference: :func:`reference_pairs.stage_polyhedron_contacts` (one shape pair)."""
    rotation, position = poses
    stage = jobs[0].shape_a
    table = triangle_table(stage)
    seq = np.array([job.seq for job in jobs], dtype=np.int64)
    tris = stage.ray_triangles[ids]  # (g, T, 3, 3) world (the stage frame is world)
    r, x = body_poses([job.body_b for job in jobs], rotation, position)
    # (g, V, 3) body-frame hulls: one concatenate (np.stack pays a Python call per array)
    hull = np.concatenate([job.shape_b.hull_vertices for job in jobs]).reshape(len(jobs), -1, 3)
    verts = to_world(r, x, hull)  # (g, V, 3)
    normal = table["normal"][ids]
    # signed height of vertex v above triangle t's plane: n_t . (x_v - p0_t), (g, T, V)
    height = np.einsum("gti,gvi->gtv", normal, verts) - dot(normal, tris[:, :, 0])[..., None]
    level = level_with(table, ids, x[:, None, 1])  # the center level with each triangle
    side = _outward_side(normal, tris[:, :, 0], height, x, cached, level)  # (g, T)
    normal, height = normal * side[..., None], height * side[..., None]
    extent = (verts.max(axis=1) - verts.min(axis=1)).max(axis=1)
    # a vertex far below a thin triangle is on the other side of it, not in contact
    below = height > -settings.STAGE_BELOW_FRACTION * extent[:, None, None]
    candidate = (
        (height < settings.STAGE_SPECULATIVE_DISTANCE) & below & _in_prisms(table, ids, tris, verts)
    )
    grid = stage_grid(stage)
    # n_t . n_s of the job's triangles, (g, T, T) (a stage in one plane needs none)
    alignment = None if grid.one_plane else np.einsum("gti,gsi->gts", normal, normal)
    if alignment is not None:  # a passed triangle holds a vertex whose way out stays inside
        passed = candidate & (height < 0)
        candidate &= ~ways_out_crossed(table, ids, tris, passed, normal, height, alignment, verts)
    # each vertex keeps its resting triangle (the shallowest it has passed, else the
    # nearest) ...
    best = _resting_triangle(candidate, height)  # (g, V)
    _add_vertex_contacts(contacts, seq, candidate, best, normal, height, verts, 0)
    # ... and, in a corner, the shallowest of those facing another way (floor and wall;
    # a stage whose triangles are all nearly parallel has no corner: skipped, exactly)
    if not grid.corner_free and alignment is not None:
        behind = _behind_the_corner(
            table, ids, tris, (candidate, below), best, normal, height, verts
        )
        corner, second = _corner_contacts(contacts, seq, behind, best, normal, height, verts)
        if crossed is not None:  # a thin slab's side across a body resting on the floor
            faces = crossed_faces(candidate, best, corner, second, alignment, height)
            crossed += _crossed_jobs(jobs, ids, faces, normal, height)
    untouched = np.flatnonzero(~candidate.any(axis=(1, 2))).tolist()
    if crossed is not None:  # with their triangles, normals and heights, for _known_edge
        return [(jobs[k], ids[k], normal[k], height[k]) for k in untouched]
    for k in untouched:  # an edge crossing a face: fcl's points with the entry face's normal
        entry = _entry_face(height[k])
        _add_fcl_points(contacts, seq[k], jobs[k].records, normal[k, entry], height[k, entry])
    return []


def _crossed_jobs(jobs, ids, faces, normal, height) -> list[CrossedJob]:
    """The jobs with crossed triangles ``faces (g, T)`` as :data:`CrossedJob` (the first
    of a padded row's repeats)."""
    least = height.min(axis=2)  # (g, T)
    out = []
    for k in np.flatnonzero(faces.any(axis=1)).tolist():
        found: dict = {}
        for t in np.flatnonzero(faces[k]).tolist():
            found.setdefault(int(ids[k, t]), (normal[k, t], float(least[k, t])))
        out.append((jobs[k], found, height.shape[2]))
    return out


def _resting_triangle(candidate: np.ndarray, height: np.ndarray) -> np.ndarray:
    """(g, V) the position of each vertex's resting triangle among its ``candidate (g, T,
    V)`` ones: the shallowest it has passed (the largest ``h < 0``: the way out of the
    stage's solid), else the nearest (the smallest ``h >= 0``, all speculative: the surface
    it meets first); the first of equal heights.

    The farthest speculative one (the rule before) let a cone's tip 1.6 mm above a bed's
    top and 1.1 cm before the mattress's side keep the side, and it went 4.5 cm into the
    top in the next step; a vertex 1 mm behind a skirting board's front kept the wall 1.4
    cm ahead and the board's top 2.3 cm above it lifted the cone (its other end then sank
    3 cm into the floor)."""
    behind = height < 0
    passed = np.any(candidate & behind, axis=1)  # (g, V)
    # h where the vertex has passed a triangle, -h where all are speculative: the largest
    key = np.where(passed[:, None, :], np.where(behind, height, -np.inf), -height)
    return np.where(candidate, key, -np.inf).argmax(axis=1)


def _behind_the_corner(table, ids, tris, masks, best, normal, height, verts) -> np.ndarray:
    """(g, T, V) bool, the triangles that hold vertex v up in a corner beside its resting
    triangle ``best (g, V)`` when it has passed that one (``h_best < 0``): it lies behind
    triangle t (``h < 0``, not too far below it: ``masks = (candidate, below)``, both
    ``(g, T, V)``, see :func:`_stage_group`) and, pushed out of its resting triangle to
    ``STAGE_CORNER_PUSH`` in front of it, inside t's prism; either a candidate of t already
    (a floor beside a wall) or at most ``STAGE_CORNER_REACH`` below it (the floor ending at
    the wall's face, which the vertex pressed into the wall has left).

    At a concave corner (a floor meeting a wall) the vertex pushed out of the wall is still
    over the floor: the floor holds it too; without it a cone's tip sank down the wall to
    the wall's underside, 5 cm below the floor, and then under the wall. At a convex edge
    (a skirting board's top and front, a table's top and side) the vertex pushed out of one
    face is beyond the other's edge: nothing is added (a vertex 1 mm behind a board's front
    was lifted onto its top, 2.3 cm above). The reach keeps a vertex pressed into a wall
    behind a board (inside the board once pushed out of the wall) off the board's top."""
    candidate, below = masks
    best_height = np.take_along_axis(height, best[:, None, :], axis=1)[:, 0]  # (g, V)
    g, v = np.nonzero(candidate.any(axis=1) & (best_height < 0))
    behind = np.zeros(candidate.shape, dtype=bool)
    if len(g) == 0:
        return behind
    # x_v pushed along its best triangle's normal to STAGE_CORNER_PUSH in front of it, (k, 3)
    push = settings.STAGE_CORNER_PUSH - best_height[g, v]
    pushed = verts[g, v] + push[:, None] * normal[g, best[g, v]]
    inside = _in_prisms(table, ids[g], tris[g], pushed[:, None])[..., 0]  # (k, T)
    h = height[g, :, v]  # (k, T)
    reach = candidate[g, :, v] | (h > -settings.STAGE_CORNER_REACH)
    behind[g, :, v] = inside & (h < 0) & below[g, :, v] & reach
    return behind


def _corner_contacts(contacts, seq, behind, best, normal, height, verts):
    """Second contacts of vertices in a corner: of the ``behind (g, T, V)`` triangles (see
    :func:`_behind_the_corner`) turned 45 to 135 degrees from the vertex's resting one
    ``best (g, V)``, the shallowest, ordered after the first contacts (``V + v``); returns
    the corner mask ``(g, T, V)`` and each vertex's second triangle ``(g, V)``."""
    best_normal = np.take_along_axis(normal, best[..., None], axis=1)  # (g, V, 3)
    alignment = np.einsum("gti,gvi->gtv", normal, best_normal)  # n_t . n_best, (g, T, V)
    corner = behind & (np.abs(alignment) < settings.STAGE_CORNER_COSINE)
    second = np.where(corner, height, -np.inf).argmax(axis=1)
    _add_vertex_contacts(contacts, seq, corner, second, normal, height, verts, verts.shape[1])
    return corner, second


def _add_vertex_contacts(contacts, seq, candidate, chosen, normal, height, verts, first: int):
    """Add one contact per vertex ``v`` with a ``candidate (g, T, V)`` triangle: the one
    ``chosen (g, V)``, depth ``-h``, A's point ``x_v + n depth``; ordered ``first + v``."""
    g, v = np.nonzero(candidate.any(axis=1))
    t = chosen[g, v]
    n, depth, point_b = normal[g, t], -height[g, t, v], verts[g, v]
    contacts.add(seq[g], first + v, point_b + n * depth[:, None], point_b, n)


def _touched_triangles(triangle_ids: list, n_triangles: int) -> tuple[np.ndarray, np.ndarray]:
    """The distinct triangles (ids ``>= 0``) of each job's id array ``triangle_ids``, as
    padded rows (:func:`_padded_rows`)."""
    lengths = [len(ids) for ids in triangle_ids]
    job = np.repeat(np.arange(len(triangle_ids)), lengths)
    tri = np.fromiter(chain.from_iterable(triangle_ids), dtype=np.int64, count=sum(lengths))
    # one key per (job, triangle): unique keys are sorted by job, then by triangle
    key = np.unique((job * n_triangles + tri)[tri >= 0])
    job, tri = np.divmod(key, n_triangles)
    return _padded_rows(job, tri, len(triangle_ids))


def _padded_rows(job: np.ndarray, tri: np.ndarray, n_jobs: int) -> tuple[np.ndarray, np.ndarray]:
    """Flat ``(job, triangle)`` pairs, sorted by job then triangle, distinct, as ``ids
    (n_jobs, T)`` (row k: job k's triangles, ascending, padded by repeating its last id; a
    duplicate triangle changes no result) and ``count (n_jobs,)`` (a row without
    triangles, ``count == 0``, holds no meaning)."""
    count = np.bincount(job, minlength=n_jobs)
    starts = np.cumsum(count) - count
    slot = np.minimum(np.arange(count.max()), count[:, None] - 1)
    return tri[starts[:, None] + slot], count


def _in_prisms(table: dict, ids: np.ndarray, tris: np.ndarray, verts: np.ndarray) -> np.ndarray:
    """(g, T, V) bool: vertex v projected on triangle t's plane falls inside the triangle."""
    e0, e1, denom = table["e0"][ids], table["e1"][ids], table["denom"][ids]
    d00, d01, d11 = table["d00"][ids], table["d01"][ids], table["d11"][ids]
    rel = verts[:, None, :, :] - tris[:, :, None, 0]  # x_v - p0_t, (g, T, V, 3)
    d20, d21 = dot(rel, e0[:, :, None]), dot(rel, e1[:, :, None])  # (g, T, V)
    # barycentric (v, w) of the projection: [d00 d01; d01 d11] [v; w] = [d20; d21]
    bary_v = (d11[..., None] * d20 - d01[..., None] * d21) / denom[..., None]
    bary_w = (d00[..., None] * d21 - d01[..., None] * d20) / denom[..., None]
    tolerance = settings.BARYCENTRIC_TOLERANCE
    return (bary_v >= -tolerance) & (bary_w >= -tolerance) & (bary_v + bary_w <= 1 + tolerance)
