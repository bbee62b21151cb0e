"""Solve stage of ``World.step``: gather manifolds, color them, run the contact solver.

Inputs => outputs: manifolds with points, body poses and velocities => new body velocities,
manifold impulses (for warm starting next step), split-impulse pseudo velocities ``(n, 6)``.
Sleeping and non-dynamic bodies enter with zero inverse mass (they are not moved);
KINEMATIC bodies enter with the velocity their velocity control gives them, so they push.
"""

from __future__ import annotations

import numpy as np

from . import settings as constants
from .bodies import DYNAMIC, KINEMATIC
from .coloring import color_manifolds
from .integrate import world_inverse_inertia
from .quaternions import live_rotations
from .rolling_friction import apply_rolling_friction, combined_coefficients
from .solver import SLOTS, build_batch, solve_contacts


def solve_stage(world, moving: np.ndarray, h: float):
    """Solve all contacts that touch an awake dynamic body; returns pseudo velocities or None."""
    b, n, store = world.bodies, world.bodies.count, world.manifolds
    solvable = np.zeros(n, dtype=bool)
    solvable[moving] = True
    rows = store.rows_with_points()
    rows = rows[solvable[store.bodies[rows, 0]] | solvable[store.bodies[rows, 1]]]
    world.last_batch = None
    if len(rows) == 0:
        return None
    colors = color_manifolds(store.bodies[rows, 0], store.bodies[rows, 1], solvable)
    # stage rows (a body the solver does not move) end each color: the solver's last word
    stage_row = ~(solvable[store.bodies[rows, 0]] & solvable[store.bodies[rows, 1]])
    colors = [color[np.argsort(stage_row[color], kind="stable")] for color in colors]
    sizes = np.cumsum([0] + [len(color) for color in colors])
    color_slices = list(zip(sizes[:-1].tolist(), sizes[1:].tolist(), strict=True))
    priority_starts = [int(stop - stage_row[color].sum())
                       for color, (_, stop) in zip(colors, color_slices, strict=True)]
    rows = rows[np.concatenate(colors)]
    body_a, body_b = store.bodies[rows, 0], store.bodies[rows, 1]
    counts = store.count[rows]
    rotation = live_rotations(b)
    points_a, points_b, normals = store.world_points(rows, rotation, b.body_position[:n])
    empty = (np.arange(SLOTS) >= counts[:, None])[..., None]
    normals = np.where(empty, [0.0, 1.0, 0.0], normals)  # a harmless unit normal when empty
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
    lower = _lower_bodies(body_a, body_b, solvable)
    friction = b.body_friction[body_a] * b.body_friction[body_b]  # pair value = product
    restitution = b.body_restitution[body_a] * b.body_restitution[body_b]
    batch = build_batch(points_a, points_b, normals, counts, body_a, body_b,
                        b.body_position[:n], inv_mass, inv_inertia, friction, restitution,
                        store.impulse[rows], approach_velocity, color_slices,
                        split_mass=world.settings.block_jacobi,
                        priority_starts=priority_starts, lower=lower,
                        slop=np.minimum(constants.PENETRATION_SLOP, store.feature[rows]))
    pseudo = solve_contacts(batch, velocity, h, world.settings)
    # rolling and spinning resistance (rolling_friction.py), a no-op when all are zero
    apply_rolling_friction(batch, velocity, inv_inertia, *combined_coefficients(b, body_a, body_b),
                           world.settings.use_vectorized)
    b.body_linear_velocity[moving] = velocity[moving, :3]
    b.body_angular_velocity[moving] = velocity[moving, 3:]
    # warm start next step from resting loads only: an impact's impulse (a point that
    # approached faster than IMPACT_SPEED) would relaunch the body it just stopped
    impact = batch.approach_speed < -constants.IMPACT_SPEED
    store.impulse[rows] = np.where(impact[..., None], 0.0, batch.impulse)  # 0 in empty slots
    world.last_batch = batch
    world.last_h = h
    return pseudo


def _lower_bodies(body_a: np.ndarray, body_b: np.ndarray, solvable: np.ndarray) -> np.ndarray:
    """(m, 2) bool: in each pair of moving bodies, the one fewer contacts away from the
    stage (or any body the solver does not move); neither when equal or unreached.

    The levels are breadth-first distances in the contact graph: level 0 for the unmoved
    bodies, then every unreached body touching a reached one gets the next level.
    """
    level = np.where(solvable, np.inf, 0.0)
    for next_level in range(1, len(body_a) + 1):
        reached_a, reached_b = level[body_a] < np.inf, level[body_b] < np.inf
        grow_b, grow_a = reached_a & ~reached_b, reached_b & ~reached_a
        if not (grow_a.any() or grow_b.any()):
            break
        level[body_b[grow_b]] = next_level
        level[body_a[grow_a]] = next_level
    both_moving = solvable[body_a] & solvable[body_b]
    la, lb = level[body_a], level[body_b]
    return np.stack([both_moving & (la < lb), both_moving & (lb < la)], axis=1)


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
