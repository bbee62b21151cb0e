"""Solve stage of ``World.step``: gather manifolds, color them, run the contact solver.

Inputs => outputs: manifolds with points, body poses and velocities => new body velocities,
manifold impulses (for warm starting next step), split-impulse pseudo velocities ``(n, 6)``.
Sleeping and non-dynamic bodies enter with zero inverse mass (they are not moved);
KINEMATIC bodies enter with the velocity their velocity control gives them, so they push.
"""

from __future__ import annotations

import numpy as np

from .bodies import DYNAMIC, KINEMATIC
from .coloring import color_manifolds
from .integrate import world_inverse_inertia
from .quaternions import quat_to_matrix
from .solver import SLOTS, build_batch, solve_contacts


def solve_stage(world, moving: np.ndarray, h: float):
    """Solve all contacts that touch an awake dynamic body; returns pseudo velocities or None."""
    b, n = world.bodies, world.bodies.count
    solvable = np.zeros(n, dtype=bool)
    solvable[moving] = True
    manifolds = [m for m in world.manifolds.values()
                 if len(m) and (solvable[m.body_a] or solvable[m.body_b])]
    world.last_batch = None
    if not manifolds:
        return None
    body_a = np.array([m.body_a for m in manifolds], dtype=np.int64)
    body_b = np.array([m.body_b for m in manifolds], dtype=np.int64)
    colors = color_manifolds(body_a, body_b, solvable)
    order = np.concatenate(colors)
    sizes = np.cumsum([0] + [len(c) for c in colors])
    color_slices = list(zip(sizes[:-1].tolist(), sizes[1:].tolist(), strict=True))
    manifolds = [manifolds[i] for i in order]
    body_a, body_b = body_a[order], body_b[order]
    arrays = _padded_points(b, manifolds)
    inv_mass = np.where(solvable, 1.0 / np.maximum(b.body_mass[:n], 1e-300), 0.0)
    inv_inertia = np.zeros((n, 3, 3))
    inv_inertia[moving] = world_inverse_inertia(b.body_rotation[moving], b.body_inertia[moving])
    velocity = _velocity_array(b, n)
    # restitution uses the approach speed at the start of the step (before this step's
    # gravity): the impact happened during the previous step, not after one more h g
    approach_velocity = velocity.copy()
    start = getattr(world, "step_start_velocity", None)
    if start is not None and len(start) == n:
        dynamic = b.body_motion_type[:n] == DYNAMIC
        approach_velocity[dynamic] = start[dynamic]
    friction = b.body_friction[body_a] * b.body_friction[body_b]  # pair value = product
    restitution = b.body_restitution[body_a] * b.body_restitution[body_b]
    batch = build_batch(*arrays, body_a, body_b, b.body_position[:n], inv_mass, inv_inertia,
                        friction, restitution, arrays_impulse(manifolds), approach_velocity,
                        color_slices, split_mass=world.settings.block_jacobi)
    pseudo = solve_contacts(batch, velocity, h, world.settings)
    b.body_linear_velocity[moving] = velocity[moving, :3]
    b.body_angular_velocity[moving] = velocity[moving, 3:]
    for i, manifold in enumerate(manifolds):
        manifold.impulse = batch.impulse[i, : len(manifold)].copy()
    world.last_batch = batch
    world.last_h = h
    return pseudo


def _padded_points(b, manifolds):
    """World anchors and normals ``(m, S, 3)`` and point counts ``(m,)``."""
    m = len(manifolds)
    points_a, points_b = np.zeros((m, SLOTS, 3)), np.zeros((m, SLOTS, 3))
    normals = np.zeros((m, SLOTS, 3))
    normals[..., 1] = 1.0  # harmless unit normal in empty slots
    counts = np.zeros(m, dtype=np.int64)
    poses: dict[int, tuple] = {}  # body -> (R, x), built once per body
    for i, manifold in enumerate(manifolds):
        a, c = manifold.body_a, manifold.body_b
        for index in (a, c):
            if index not in poses:
                poses[index] = _pose(b, index)
        pa, pc, nrm = manifold.world_points(poses[a], poses[c])
        k = len(manifold)
        points_a[i, :k], points_b[i, :k], normals[i, :k] = pa, pc, nrm
        counts[i] = k
    return points_a, points_b, normals, counts


def _pose(b, index: int) -> tuple[np.ndarray, np.ndarray]:
    """``(R (3, 3), x (3,))`` of body ``index``."""
    return quat_to_matrix(b.body_rotation[index]), b.body_position[index]


def arrays_impulse(manifolds) -> np.ndarray:
    """Cached impulses ``(m, S, 3)`` of the manifolds (zero-padded)."""
    impulse = np.zeros((len(manifolds), SLOTS, 3))
    for i, manifold in enumerate(manifolds):
        impulse[i, : len(manifold)] = manifold.impulse
    return impulse


def _velocity_array(b, n: int) -> np.ndarray:
    """``(n, 6)`` [v, w]: dynamic bodies their velocity, kinematic their controlled one."""
    velocity = np.zeros((n, 6))
    dynamic = b.body_motion_type[:n] == DYNAMIC
    kinematic = b.body_motion_type[:n] == KINEMATIC
    velocity[dynamic, :3] = b.body_linear_velocity[:n][dynamic]
    velocity[dynamic, 3:] = b.body_angular_velocity[:n][dynamic]
    velocity[kinematic, :3] = b.body_solver_velocity[:n][kinematic]
    velocity[kinematic, 3:] = b.body_solver_angular_velocity[:n][kinematic]
    return velocity
