"""Continuous collision for fast and thin bodies: a swept test against non-dynamic geometry.

A body that moved more than ``CCD_MOTION_FRACTION`` of its smallest half extent in one step
(after the solver and the position update) is swept along its step's travel ``d = L u``:

1. rays start at its hull vertices and its center, put back to the start of the step
   (``p - d``, the orientation of the end of the step), and run along ``u`` for ``L``
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
whose speculative contact (gap about 0) stops the approach next step. Rotation during the
step is ignored (the body is swept with its final orientation).

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

from . import settings
from .bodies import DYNAMIC, Bodies
from .quaternions import quat_to_matrix

#: hull vertices swept per body at most (evenly spread over the hull's list).
MAX_SWEPT_VERTICES = 64


def sweep_fast_bodies(bodies: Bodies, moving: np.ndarray, old_position: np.ndarray) -> None:
    """Push back bodies in ``moving (k,)`` that passed into static geometry this step;
    ``old_position (k, 3)`` are their centers before the step."""
    b = bodies
    if len(moving) == 0:
        return
    travel = b.body_position[moving] - old_position
    length = np.linalg.norm(travel, axis=1)
    radius = b.body_min_half_extent[moving]
    fast = length > settings.CCD_MOTION_FRACTION * np.maximum(radius, settings.CCD_MIN_RADIUS)
    if not np.any(fast):
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
    starts = np.vstack([position[None], world_vertices]) - travel  # the step's start
    pad = settings.SWEEP_BOX_PADDING
    lo = np.minimum(starts.min(0), starts.min(0) + travel) - pad
    hi = np.maximum(starts.max(0), starts.max(0) + travel) + pad
    triangles = _obstacle_triangles(bodies, obstacle, lo, hi)
    if len(triangles) == 0:
        return np.zeros(3)
    s, normal = first_hits(starts, u, triangles)
    hit = s < length
    if not np.any(hit):
        return np.zeros(3)
    cos = np.abs(normal @ u)
    # how far each ray's end is behind its surface (0 for the rays that hit nothing)
    depth = (length - np.where(hit, s, length)) * cos
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


def first_hits(origins: np.ndarray, direction: np.ndarray, triangles: np.ndarray):
    """First hit ``s (k,)`` (inf: none) of rays ``origins (k, 3) + s direction`` with the
    triangles ``(t, 3, 3)``, and the hit triangle's unit normal ``(k, 3)`` facing the ray's
    start (Moller-Trumbore, as in :func:`queries.ray_triangles`, for all rays at once)."""
    a = triangles[:, 0]
    e1, e2 = triangles[:, 1] - a, triangles[:, 2] - a
    p = np.cross(direction, e2)  # (t, 3), the same for every ray
    det = np.sum(e1 * p, axis=1)
    ok = np.abs(det) > settings.RAY_PARALLEL_DETERMINANT
    inv_det = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    rel = origins[:, None, :] - a[None]  # o - a, (k, t, 3)
    u = np.einsum("kti,ti->kt", rel, p) * inv_det  # barycentric u = (o - a) . p / det
    q = np.cross(rel, e1[None])  # (k, t, 3)
    v = (q @ direction) * inv_det  # v = d . q / det
    s = np.einsum("kti,ti->kt", q, e2) * inv_det
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (s >= 0)
    s = np.where(hit, s, np.inf)
    best = s.argmin(axis=1)
    normal = np.cross(e1, e2)[best]
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), settings.TINY)
    normal *= np.where(normal @ direction > 0, -1.0, 1.0)[:, None]  # n . u < 0: faces the start
    return s[np.arange(len(s)), best], normal
