"""Continuous collision for fast and thin bodies: a swept test against non-dynamic geometry.

A body that moved more than ``CCD_MOTION_FRACTION`` of its smallest half extent in one step
(after the solver and the position update) is swept along its step's travel ``d = L u``:

1. rays start at its hull vertices and its center, put back to the start of the step
   (``p - d``, the orientation of the end of the step), and run along ``u`` for ``L``; the
   vertex rays start ``STAGE_SPECULATIVE_DISTANCE`` earlier still, so a vertex that began
   the step a hair inside a surface still crosses it (a crossing in that extra length
   counts when the surface faces the body's center)
   (Moller-Trumbore against the stage's triangles near the swept box, and against the
   triangles of static and kinematic bodies);
2. a ray that hits at ``s < L`` ends ``(L - s) |u . n|`` behind the surface (``n``, the
   hit triangle's normal, faces the ray's start: the side the body came from). The center
   ray adds the body's support along ``-n`` (its half thickness there), so a body whose
   vertices start a hair inside the surface is still caught;
3. the body is pushed back along each hit normal, deepest first, until no ray end is more
   than ``min(CCD_PENETRATION, 10 % of the body's thickness)`` behind a surface;
4. each ray only reports its first surface, so at a corner the push out of one wall can
   leave the body behind the other: the sweep is repeated from the start to the corrected
   end, up to ``CCD_SWEEPS`` times.

Only the motion into the surface is undone (the body keeps sliding along it), which is a
time-of-impact clamp for the normal component; velocities are left to the contact solver,
whose speculative contact (gap about 0) stops the approach next step. The translation is
swept with the final orientation. The path sweep (:func:`sweep_path`) follows each hull
vertex from its place at the start of the step to its place at the end, along the turn's
arc in chords of at most ``CCD_ARC_ANGLE``, and the center along its line; it takes

* a body whose translation plus turn (``|d| + theta r``: :func:`turn_angle`,
  :func:`body_reach`) passes the threshold (Box2D v3's test, ``b2FinalizeBodies``:
  ``|v| h + |w| h r_max`` against half the body's smallest extent): a 1 mm slab thrown
  flat at the floor at 29 m/s spun up by the impact and dug a corner 7.9 cm into it the
  next frame; a 25 cm cone at 5.4 m/s and 14 rad/s (4.3 cm and 2.1 cm a step, each under
  the 5 cm threshold) struck 7 cm into a bed's side;
* a body, at any speed, whose center went through the front of a stage triangle this step
  (:func:`centers_through_stage`, all bodies at once): a 25 cm cone spun at 35-38 rad/s
  against a 10 cm wall crept in tip first, 1-1.5 cm a step (its tip held by a floor contact
  only), until the center followed and it left through the wall's far side. The center's
  crossing pushes the whole body back out (the center's depth plus its support), and no
  vertex's push may undo it.

What the reference engines do (checked in their sources and manuals):

* Bullet: ``btRigidBody::setCcdMotionThreshold`` (sweep a body that moves more than this per
  step) and ``setCcdSweptSphereRadius`` (a sphere inside the body is swept, and the body
  is put back to the time of impact) in ``btDiscreteDynamicsWorld::integrateTransforms``;
  we sweep the hull's vertices instead of one sphere, and only against static geometry.
* Box2D v3: every body gets speculative contacts within ``B2_SPECULATIVE_DISTANCE``
  (4 x linear slop = 2 cm); fast bodies get continuous collision against static bodies
  (``b2SolveContinuous``: time of impact ``b2TimeOfImpact`` by conservative advancement,
  then the body is moved back to that time), dynamic "bullet" bodies also against other
  dynamic bodies. Our speculative distance is Box2D's 2 cm (``STAGE_SPECULATIVE_DISTANCE``).
* Jolt: an ``EMotionQuality::LinearCast`` body that moves more than
  ``PhysicsSettings::mLinearCastThreshold`` (0.75) of its inner radius in a step is cast
  along its motion (a shape cast) and stopped at the first hit; every body has speculative
  contacts within ``mSpeculativeContactDistance`` (2 cm by default).
"""

from __future__ import annotations

import numpy as np

from ..core import settings
from ..core.bodies import DYNAMIC, Bodies
from ..core.quaternions import quat_multiply, quat_to_matrix, rotation_quat, rotation_vector

#: hull vertices swept per body at most (evenly spread over the hull's list).
MAX_SWEPT_VERTICES = 64


def sweep_fast_bodies(
    bodies: Bodies, moving: np.ndarray, old_position: np.ndarray, old_rotation: np.ndarray
) -> None:
    """Push back bodies in ``moving (k,)`` that passed into static geometry this step;
    ``old_position (k, 3)`` and ``old_rotation (k, 4)`` are their poses before the step."""
    b = bodies
    if len(moving) == 0:
        return
    travel = b.body_position[moving] - old_position
    length = np.linalg.norm(travel, axis=1)
    threshold = settings.CCD_MOTION_FRACTION * np.maximum(
        b.body_min_half_extent[moving], settings.CCD_MIN_RADIUS
    )
    fast = length > threshold
    angle, reach = turn_angle(b, moving, old_rotation), body_reach(b, moving)
    turn = angle * reach
    # Box2D v3's test: the translation and the turn together (|v| h + |w| h r) past the
    # threshold; the path sweep also takes the bodies whose turn alone passes it
    on_path = ((length + turn > threshold) & ~fast) | (turn > threshold)
    moved = np.flatnonzero(length > settings.CCD_CENTER_TRAVEL)  # (resting bodies: none)
    if len(moved):
        on_path[moved] |= centers_through_stage(b, moving[moved], old_position[moved])
    if not (np.any(fast) or np.any(on_path)):
        return
    n = b.count
    # the obstacles' indices, once: each fast body tests only them (not all n bodies)
    obstacle = np.flatnonzero(
        b.body_alive[:n] & b.body_collidable[:n] & (b.body_motion_type[:n] != DYNAMIC)
    )
    for k in np.nonzero(fast)[0].tolist():
        index = int(moving[k])
        step = travel[k].copy()
        for _ in range(settings.CCD_SWEEPS):  # a corner: each sweep finds one more wall
            correction = sweep_body(bodies, index, step, obstacle)
            if not np.any(correction):
                break
            b.body_position[index] += correction
            step += correction  # sweep again from the start to the corrected end
    for k in np.nonzero(on_path)[0].tolist():
        pose = (old_position[k], old_rotation[k])
        turned = (float(angle[k]), float(reach[k]))
        for _ in range(settings.CCD_SWEEPS):
            correction = sweep_path(bodies, int(moving[k]), pose, obstacle, turned)
            if not np.any(correction):
                break
            b.body_position[int(moving[k])] += correction


def centers_through_stage(
    bodies: Bodies, moving: np.ndarray, old_position: np.ndarray
) -> np.ndarray:
    """``(k,)`` whether the center of each body in ``moving`` went this step from the
    start ``old_position (k, 3)`` through the front of a stage triangle (the side its
    winding faces): a fall-through whatever the body's speed, so :func:`sweep_path` holds
    it. All bodies at once: the stage grid's triangles near each center's segment
    (``collision.stage_grid.StageGrid``), one Moller-Trumbore test per (segment, triangle) pair."""
    crossed = np.zeros(len(moving), dtype=bool)
    stage = [s for s in bodies.shapes[0] if s.kind == "mesh"] if bodies.count else []
    if len(moving) == 0 or not stage or not bodies.body_alive[0]:
        return crossed
    start, end = old_position, bodies.body_position[moving]
    pad = settings.SWEEP_BOX_PADDING
    lo, hi = np.minimum(start, end) - pad, np.maximum(start, end) + pad
    for shape in stage:
        # the grid the batched collision stage builds on its first stage pair and keeps on
        # the shape (collision.stage_grid; the solver does not import collision)
        grid = getattr(shape, "_stage_grid", None)
        if grid is not None:
            segment, triangle = grid.candidates(lo, hi)
        else:  # the same pairs from every triangle's box (the plain path builds no grid)
            tri_lo, tri_hi = _triangle_boxes(shape)
            overlap = (tri_lo[None] <= hi[:, None]) & (tri_hi[None] >= lo[:, None])
            segment, triangle = np.nonzero(overlap.all(axis=2))
        if len(segment) == 0:
            continue
        corners = shape.ray_triangles[triangle]
        d = end[segment] - start[segment]
        e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        p = np.cross(d, e2)
        det = (p * e1).sum(axis=1)  # = -d . (e1 x e2): > 0 when d meets the front
        ok = det > settings.RAY_PARALLEL_DETERMINANT
        inv = 1.0 / np.where(ok, det, 1.0)
        rel = start[segment] - corners[:, 0]
        u = (rel * p).sum(axis=1) * inv
        q = np.cross(rel, e1)
        v = (q * d).sum(axis=1) * inv
        t = (q * e2).sum(axis=1) * inv  # the crossing's fraction of the segment
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (t <= 1)
        crossed[segment[hit]] = True
    return crossed


def turn_angle(bodies: Bodies, moving: np.ndarray, old_rotation: np.ndarray) -> np.ndarray:
    """``(k,)`` rad, the angle between each body's old and new orientation."""
    q = bodies.body_rotation[moving]
    # |<q_old, q_new>| = cos(theta / 2)
    cosine = np.minimum(np.abs((q * old_rotation).sum(axis=1)), 1.0)
    return 2.0 * np.arccos(cosine)


def body_reach(bodies: Bodies, moving: np.ndarray) -> np.ndarray:
    """``(k,)`` m, the distance of each body's farthest AABB corner from its center of mass
    (no hull vertex is farther)."""
    center, half = bodies.body_shape_center[moving], bodies.body_shape_half[moving]
    return np.linalg.norm(np.abs(center) + half, axis=1)


def path_points(
    vertices: np.ndarray,
    old_pose: tuple[np.ndarray, np.ndarray],
    new_pose,
    angle: float | None = None,
) -> np.ndarray:
    """``(m + 1, v, 3)`` world places of the body-frame points ``vertices (v, 3)`` at the
    ``m + 1`` poses of the step's motion from ``old_pose`` to ``new_pose`` (position (3,),
    rotation (4,)): the center moves on the straight line, the orientation turns at a
    constant rate about the step's fixed axis (``q(t) = exp(t theta u / 2) q_0``, Box2D's
    ``b2GetSweepTransform``), cut where the turn passes ``CCD_ARC_ANGLE`` so each vertex's
    arc is followed by chords (sagitta ``r (1 - cos(a / 2))``: 1.5 mm at 0.25 rad and 20 cm).
    ``angle`` (rad), the turn's angle when known: within one chord only the two poses are
    needed."""
    if angle is not None and angle <= settings.CCD_ARC_ANGLE:
        rotation = quat_to_matrix(np.stack([old_pose[1], new_pose[1]]))
        center = np.stack([old_pose[0], new_pose[0]])
        return np.einsum("mij,vj->mvi", rotation, vertices) + center[:, None]
    turn = rotation_vector(new_pose[1][None], old_pose[1][None])[0]
    pieces = max(1, int(np.ceil(np.linalg.norm(turn) / settings.CCD_ARC_ANGLE)))
    t = np.linspace(0.0, 1.0, pieces + 1)[:, None]
    rotation = quat_multiply(rotation_quat(t * turn), old_pose[1][None])
    rotation[-1] = new_pose[1]  # the end pose exactly (no rounding of the exp map)
    center = old_pose[0] + t * (new_pose[0] - old_pose[0])
    return np.einsum("mij,vj->mvi", quat_to_matrix(rotation), vertices) + center[:, None]


def sweep_path(
    bodies: Bodies,
    index: int,
    old_pose: tuple[np.ndarray, np.ndarray],
    obstacle: np.ndarray,
    turned: tuple[float, float],
) -> np.ndarray:
    """(3,) displacement taking body ``index`` out of the surfaces crossed this step by its
    hull vertices and by its center (``old_pose``: position (3,), rotation (4,) at the
    step's start).

    Each vertex follows its path from the old pose to the new one (:func:`path_points`:
    the translation and the turn's arc, in chords); a vertex's crossing counts when the
    surface faces the body's center (a vertex that started a hair behind a floor and turns
    up through it must not push the body down). The center follows its straight line: its
    crossing of a triangle's front (the side its winding faces; a center leaving a solid
    is not pushed back in, nor one that starts on the plane) is a fall-through whatever the
    vertices did (Box2D v3's fallback to a core circle around the centroid in
    ``b2SolveContinuous``, Bullet's swept sphere at the center): it ends its depth plus the
    body's support behind the surface. The pushes are as in :func:`sweep_body` (step 3).
    ``turned``: the step's turn angle (rad) and the body's reach (m, :func:`body_reach`)."""
    b = bodies
    position = b.body_position[index]
    # no vertex leaves the center's line by more than the reach: no obstacle triangle in
    # that box, nothing to sweep (most steps of a tumbling body in the air)
    grow = turned[1] + settings.SWEEP_BOX_PADDING
    triangles = _obstacle_triangles(
        bodies,
        obstacle,
        np.minimum(old_pose[0], position) - grow,
        np.maximum(old_pose[0], position) + grow,
    )
    if len(triangles) == 0:
        return np.zeros(3)
    vertices = np.concatenate([s.hull_vertices for s in b.shapes[index]])
    vertices = vertices[:: max(1, len(vertices) // MAX_SWEPT_VERTICES)]
    new_pose = (position, b.body_rotation[index])
    points = path_points(np.vstack([np.zeros((1, 3)), vertices]), old_pose, new_pose, turned[0])
    chord = points[1:] - points[:-1]  # (m, v + 1, 3), point 0 the center
    length = np.linalg.norm(chord, axis=2)
    u = chord / np.maximum(length, settings.TINY)[:, :, None]
    starts = points[:-1]
    m, count = length.shape
    s, normal, front = first_hits_each(starts.reshape(-1, 3), u.reshape(-1, 3), triangles, True)
    s, normal, front = s.reshape(m, count), normal.reshape(m, count, 3), front.reshape(m, count)
    crossed = (s < length) & (length > settings.TINY)
    point = starts + np.where(crossed, s, 0.0)[:, :, None] * u
    facing = ((position - point) * normal).sum(axis=2) > 0.0
    # a vertex's crossing counts when the surface faces the body's center; the center's
    # only into a triangle's front (a center leaving a solid is not pushed back into it)
    crossed[:, 1:] &= facing[:, 1:]
    crossed[:, 0] &= front[:, 0] & (s[:, 0] > 0.0)  # (a center spawned on a plane: no)
    # each point's first crossing along its path, and how far its end is behind it
    piece = np.argmax(crossed, axis=0)  # (v + 1,): the first chord that crossed
    every = np.arange(count)
    hit = crossed[piece, every]
    normal, point = normal[piece, every], point[piece, every]
    depth = np.where(hit, ((point - points[-1]) * normal).sum(axis=1), 0.0)
    # the center stands for the whole body: add its support along -n (half thickness)
    depth[0] += max(np.max(-(points[-1, 1:] - position) @ normal[0]), 0.0)
    hit &= depth > 0.0
    if hit[0]:  # the center crossed: no vertex may push the body back against its push
        hit &= normal @ normal[0] >= 0.0
    if not np.any(hit):
        return np.zeros(3)
    allowed = min(
        settings.CCD_PENETRATION, settings.CCD_PENETRATION_FRACTION * b.body_min_half_extent[index]
    )
    correction = np.zeros(3)
    for ray in np.argsort(-depth, kind="stable").tolist():
        remaining = depth[ray] - correction @ normal[ray]
        if hit[ray] and remaining > allowed:
            correction += (remaining - allowed) * normal[ray]
    return correction


def sweep_body(bodies: Bodies, index: int, travel: np.ndarray, obstacle: np.ndarray) -> np.ndarray:
    """(3,) displacement taking body ``index`` out of the surfaces its step crossed;
    ``obstacle (o,)``: indices of the non-dynamic bodies it may hit."""
    b = bodies
    position = b.body_position[index]
    rotation = quat_to_matrix(b.body_rotation[index][None])[0]
    vertices = np.concatenate([s.hull_vertices for s in b.shapes[index]])
    step = max(1, len(vertices) // MAX_SWEPT_VERTICES)
    world_vertices = vertices[::step] @ rotation.T + position  # p = R v + x
    length = float(np.linalg.norm(travel))
    if length == 0.0:
        return np.zeros(3)
    u = travel / length
    # the vertex rays start the stage's speculative distance before the step's start, so a
    # vertex that began the step a hair inside a surface still crosses it
    back = settings.STAGE_SPECULATIVE_DISTANCE
    starts = np.vstack([position[None], world_vertices - back * u]) - travel
    ray_length = np.full(len(starts), length)
    ray_length[1:] += back
    pad = settings.SWEEP_BOX_PADDING
    lo = np.minimum(starts.min(0), starts.min(0) + travel) - pad
    hi = np.maximum(starts.max(0), starts.max(0) + travel) + pad
    triangles = _obstacle_triangles(bodies, obstacle, lo, hi)
    if len(triangles) == 0:
        return np.zeros(3)
    s, normal = first_hits(starts, u, triangles)
    # a crossing before the step's start counts when the surface faces the body's center
    point = starts + np.where(np.isfinite(s), s, 0.0)[:, None] * u
    facing = ((position - point) * normal).sum(axis=1) > 0.0
    hit = (s < ray_length) & (facing | (s >= ray_length - length))
    if not np.any(hit):
        return np.zeros(3)
    cos = np.abs(normal @ u)
    # how far each ray's end is behind its surface (0 for the rays that hit nothing)
    depth = (ray_length - np.where(hit, s, ray_length)) * cos
    # the center ray stands for the whole body: add its support along -n (half thickness)
    support = np.max(-(world_vertices - position) @ normal[0])
    depth[0] += max(support, 0.0)
    allowed = min(
        settings.CCD_PENETRATION, settings.CCD_PENETRATION_FRACTION * b.body_min_half_extent[index]
    )
    correction = np.zeros(3)
    for ray in np.argsort(-depth, kind="stable").tolist():
        if not hit[ray]:
            continue
        remaining = depth[ray] - correction @ normal[ray]
        if remaining > allowed:
            correction += (remaining - allowed) * normal[ray]
    return correction


def _obstacle_triangles(
    bodies: Bodies, obstacle: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> np.ndarray:
    """World triangles ``(t, 3, 3)`` of the bodies ``obstacle (o,)`` whose boxes meet the
    box lo..hi."""
    b = bodies
    near = obstacle[
        np.all((b.body_aabb_min[obstacle] <= hi) & (b.body_aabb_max[obstacle] >= lo), axis=1)
    ]
    parts = []
    for index in near.tolist():
        rotation = quat_to_matrix(b.body_rotation[index][None])[0]
        for shape in b.shapes[index]:
            if shape.kind == "mesh":  # the stage: world frame, keep the triangles in the box
                tri_lo, tri_hi = _triangle_boxes(shape)
                inside = np.all((tri_lo <= hi) & (tri_hi >= lo), axis=1)
                parts.append(shape.ray_triangles[inside])
            elif shape.kind != "sphere":
                parts.append(shape.ray_triangles @ rotation.T + b.body_position[index])
    return np.concatenate(parts) if parts else np.zeros((0, 3, 3))


def _triangle_boxes(shape) -> tuple[np.ndarray, np.ndarray]:
    """Per-triangle AABBs ``(t, 3)`` of a static mesh, computed once and kept on the shape."""
    boxes = getattr(shape, "_triangle_boxes", None)
    if boxes is None:
        boxes = (shape.ray_triangles.min(axis=1), shape.ray_triangles.max(axis=1))
        shape._triangle_boxes = boxes
    return boxes


def first_hits_each(
    origins: np.ndarray, directions: np.ndarray, triangles: np.ndarray, with_front: bool = False
):
    """First hit ``s (k,)`` (inf: none) of rays ``origins (k, 3) + s directions (k, 3)``
    (unit directions) with the triangles ``(t, 3, 3)``, and the hit triangle's unit normal
    ``(k, 3)`` facing the ray's start (Moller-Trumbore, as in :func:`queries.ray_triangles`,
    for all rays at once); ``with_front``: also ``(k,)`` whether the ray met the triangle's
    front (the side its winding ``(b - a) x (c - a)`` faces)."""
    a = triangles[:, 0]
    e1, e2 = triangles[:, 1] - a, triangles[:, 2] - a
    p = np.cross(directions[:, None, :], e2[None])  # (k, t, 3)
    det = np.einsum("kti,ti->kt", p, e1)
    ok = np.abs(det) > settings.RAY_PARALLEL_DETERMINANT
    inv_det = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    rel = origins[:, None, :] - a[None]  # o - a, (k, t, 3)
    u = (rel * p).sum(axis=2) * inv_det  # barycentric u = (o - a) . p / det
    q = np.cross(rel, e1[None])  # (k, t, 3)
    v = np.einsum("kti,ki->kt", q, directions) * inv_det  # v = d . q / det
    s = np.einsum("kti,ti->kt", q, e2) * inv_det
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (s >= 0)
    s = np.where(hit, s, np.inf)
    best = s.argmin(axis=1)
    normal = np.cross(e1, e2)[best]
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), settings.TINY)
    facing = (normal * directions).sum(axis=1) > 0
    normal *= np.where(facing, -1.0, 1.0)[:, None]  # n . u < 0: faces the start
    if with_front:
        return s[np.arange(len(s)), best], normal, ~facing
    return s[np.arange(len(s)), best], normal


def first_hits(origins: np.ndarray, direction: np.ndarray, triangles: np.ndarray):
    """:func:`first_hits_each` with the same unit ``direction (3,)`` for every ray."""
    return first_hits_each(origins, np.broadcast_to(direction, origins.shape), triangles)
