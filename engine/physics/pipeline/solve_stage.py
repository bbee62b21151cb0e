"""Solve stage of ``World.step``: gather manifolds, color them, run the contact solver.

Inputs => outputs (``n`` bodies, ``m`` manifolds with points, ``S = 4`` slots each)::

    Bodies (poses, velocities (n, 3), masses, inertias), ManifoldStore (m rows),
    moving (k,) awake dynamic body indices, start_velocity (n, 6), h s, SolverSettings
        => Bodies.body_linear/angular_velocity of ``moving`` updated,
           ManifoldStore.impulse (m, S, 3) (warm start of the next step),
           SolveResult: pseudo_velocity (n, 6) split-impulse velocities (None: no contact),
           overlapping_bodies (j,) bodies of contacts deeper than SLEEP_MAX_PENETRATION

Sleeping and non-dynamic bodies enter with zero inverse mass (they are not moved);
KINEMATIC bodies enter with the velocity their velocity control gives them, so they push.
``settings.use_vectorized`` picks the batched solver (:mod:`solver`) or the scalar reference
(:mod:`reference_solver`), which builds its own Jacobians and effective masses;
``settings.soft_step`` Box2D v3's soft schedule (:mod:`soft_step`, its twin
:mod:`reference_soft`) instead of the rigid sweeps and the split-impulse position solve.
Its forces' share per substep is the step's ``velocity - approach_velocity`` (the forces
stage ran before this one).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..collision.contacts import ManifoldStore
from ..core.bodies import DYNAMIC, KINEMATIC, Bodies
from ..core.quaternions import live_rotations
from ..core.settings import (
    IMPACT_SPEED,
    PENETRATION_SLOP,
    SLEEP_MAX_PENETRATION,
    TINY,
    SolverSettings,
)
from ..solver.coloring import color_manifolds
from ..solver.contact_batch import (
    ColorOrder,
    ManifoldPoints,
    PairCoefficients,
    SolverBodies,
    build_batch,
)
from ..solver.integrate import body_velocities, world_inverse_inertia
from ..solver.rolling_friction import (
    ContactLoads,
    apply_rolling_friction,
    combined_coefficients,
    needs_rolling_friction,
)
from ..solver.sequential_impulses import solve_contacts
from ..solver.soft_step import solve_soft


@dataclass
class SolveResult:
    """What the solve stage hands to the integrate and sleep stages.

    ``pseudo_velocity (n, 6)``: split-impulse [v, w] moving bodies this step only (None when
    no contact was solved); ``overlapping_bodies (j,)``: bodies of a contact deeper than
    ``SLEEP_MAX_PENETRATION`` (not resting while the position solve separates them).
    """

    pseudo_velocity: np.ndarray | None
    overlapping_bodies: np.ndarray


@dataclass
class SolverInput:
    """The manifolds to solve, in color order, and the body quantities the solver reads.

    ``rows (m,)`` store rows sorted by color, ``color_slices`` ``(start, stop)`` into them;
    ``priority_starts`` per color, the first of its *stage rows* (manifolds with a body the
    solver does not move; they end each color and get the last word, see :mod:`solver`);
    ``lower (m, 2)`` bool, which body of a pair of moving bodies is fewer contacts from the
    stage (shock propagation); ``slop (m,)`` m, the penetration each manifold's position
    solve leaves (``PENETRATION_SLOP``, capped at the feature length for small bodies);
    ``inv_mass (n,)`` 1/kg, ``inv_inertia (n, 3, 3)`` world frame, 1/(kg m^2) (zero for
    bodies that do not move); ``velocity (n, 6)`` [v, w] that the solver updates;
    ``approach_velocity (n, 6)`` the start-of-step velocities restitution measures;
    ``pairs (m, 2)`` the bodies of each row, ``store.bodies[rows]``.
    """

    rows: np.ndarray
    color_slices: list[tuple[int, int]]
    priority_starts: list[int]
    lower: np.ndarray
    slop: np.ndarray
    inv_mass: np.ndarray
    inv_inertia: np.ndarray
    velocity: np.ndarray
    approach_velocity: np.ndarray
    pairs: np.ndarray


def solve_stage(
    bodies: Bodies,
    store: ManifoldStore,
    moving: np.ndarray,
    start_velocity: np.ndarray,
    h: float,
    settings: SolverSettings,
) -> SolveResult:
    """Solve all contacts that touch an awake dynamic body (see the module docstring)."""
    problem = gather_solver_input(bodies, store, moving, start_velocity)
    if problem is None:
        return SolveResult(None, np.zeros(0, dtype=np.int64))
    # rolling and spinning resistance (rolling_friction.py) only if some body of the
    # solved pairs has it: then the solve also returns the manifolds' normal loads
    rolling = needs_rolling_friction(bodies, problem.pairs)
    if settings.use_vectorized:
        pseudo, depth, loads = _solve_batched(bodies, store, problem, h, settings, rolling)
    elif settings.soft_step:
        from ..reference.reference_soft import solve_soft_reference

        pseudo, depth, loads = solve_soft_reference(bodies, store, problem, h, settings, rolling)
    else:
        from ..reference.reference_solver import solve_reference

        pseudo, depth, loads = solve_reference(bodies, store, problem, h, settings, rolling)
    if loads is not None:
        apply_rolling_friction(
            loads,
            problem.velocity,
            problem.inv_inertia,
            *combined_coefficients(bodies, loads.body_a, loads.body_b),
            settings.use_vectorized,
        )
    bodies.body_linear_velocity[moving] = problem.velocity[moving, :3]
    bodies.body_angular_velocity[moving] = problem.velocity[moving, 3:]
    deep = depth.max(axis=1) > SLEEP_MAX_PENETRATION
    overlapping = problem.pairs[deep].ravel()
    return SolveResult(pseudo, overlapping)


def gather_solver_input(
    bodies: Bodies, store: ManifoldStore, moving: np.ndarray, start_velocity: np.ndarray
) -> SolverInput | None:
    """Manifolds with points touching a ``moving`` body, colored; None when there are none."""
    b, n = bodies, bodies.count
    solvable = np.zeros(n, dtype=bool)
    solvable[moving] = True
    rows = store.rows_with_points()
    pairs = store.bodies[rows]  # (m, 2) body indices
    touches = solvable[pairs].any(axis=1)  # a body of the pair is moving
    rows, pairs = rows[touches], pairs[touches]
    if len(rows) == 0:
        return None
    order, color_slices, priority_starts, lower = solver_order(store, pairs, solvable)
    rows, pairs = rows[order], pairs[order]
    inv_mass = np.where(solvable, 1.0 / np.maximum(b.body_mass[:n], TINY), 0.0)
    inv_inertia = np.zeros((n, 3, 3))
    inv_inertia[moving] = world_inverse_inertia(b.body_rotation[moving], b.body_inertia[moving])
    velocity = solver_velocities(b, n)
    # restitution uses the approach speed at the start of the step (before this step's
    # gravity): the impact happened during the previous step, not after one more h g
    dynamic = b.body_motion_type[:n] == DYNAMIC
    approach_velocity = np.where(dynamic[:, None], start_velocity, velocity)
    slop = np.minimum(PENETRATION_SLOP, store.feature[rows])
    return SolverInput(
        rows,
        color_slices,
        priority_starts,
        lower,
        slop,
        inv_mass,
        inv_inertia,
        velocity,
        approach_velocity,
        pairs,
    )


def solver_order(
    store: ManifoldStore, pairs: np.ndarray, solvable: np.ndarray
) -> tuple[np.ndarray, list[tuple[int, int]], list[int], np.ndarray]:
    """``(order, color_slices, priority_starts, lower)`` of the manifolds of the bodies
    ``pairs (m, 2)``: :func:`color_manifolds` and :func:`color_order`, then
    :func:`lower_bodies` of the pairs in that order.

    All four are functions of the contact graph only (the pairs and which of their bodies
    are ``solvable``), which often stays the same from one step to the next (a pile at
    rest, a tower): then the last step's answer is reused, exactly the same arrays, instead
    of the pure-Python greedy coloring and the level search (the memo lives on ``store``).
    """
    pair_solvable = solvable[pairs]  # (m, 2)
    key = pairs.tobytes() + pair_solvable.tobytes()
    memo = store.solver_order
    if memo.value is None or memo.key != key:
        body_a, body_b = pairs[:, 0], pairs[:, 1]
        order, color_slices, priority_starts = color_order(
            color_manifolds(body_a, body_b, solvable), ~pair_solvable.all(axis=1)
        )
        lower = lower_bodies(body_a[order], body_b[order], solvable)
        memo.key, memo.value = key, (order, color_slices, priority_starts, lower)
    order, color_slices, priority_starts, lower = memo.value
    return order, list(color_slices), list(priority_starts), lower.copy()


def color_order(
    colors: list[np.ndarray], stage_row: np.ndarray
) -> tuple[np.ndarray, list[tuple[int, int]], list[int]]:
    """The manifolds in solver order: color by color, and in each color the stage rows
    (``stage_row (m,)`` bool: a body the solver does not move) last, the solver's last word.

    Returns the manifold indices ``order (m,)``, each color's ``(start, stop)`` in it and
    the start of each color's stage rows. One stable sort by (color, stage row) for all
    colors: the order of :func:`color_manifolds` is kept otherwise.
    """
    sizes = np.array([len(color) for color in colors], dtype=np.int64)
    members = np.concatenate(colors)  # manifold indices, color by color
    color_of = np.repeat(np.arange(len(colors)), sizes)
    order = members[np.lexsort((stage_row[members], color_of))]  # lexsort is stable
    stops = np.cumsum(sizes)
    starts = stops - sizes
    stage_counts = np.add.reduceat(stage_row[order], starts)  # colors are never empty
    color_slices = list(zip(starts.tolist(), stops.tolist(), strict=True))
    return order, color_slices, (stops - stage_counts).tolist()


def _solve_batched(
    bodies: Bodies,
    store: ManifoldStore,
    problem: SolverInput,
    h: float,
    settings: SolverSettings,
    with_loads: bool = True,
) -> tuple[np.ndarray, np.ndarray, ContactLoads | None]:
    """Batched path: padded arrays, one NumPy batch per color. Returns the pseudo
    velocities ``(n, 6)``, the contact depths ``(m, S)`` (0 in empty slots) and the
    manifolds' normal loads (rolling friction's input; None unless ``with_loads``)."""
    b, n, rows = bodies, bodies.count, problem.rows
    body_a, body_b = problem.pairs[:, 0], problem.pairs[:, 1]
    counts = store.count[rows]
    rotation = live_rotations(b)
    position = b.body_position[:n]
    points_a, points_b, normals = world_points(store, rows, rotation, position, body_a, body_b)
    friction = b.body_friction[body_a] * b.body_friction[body_b]  # pair value = product
    restitution = b.body_restitution[body_a] * b.body_restitution[body_b]
    batch = build_batch(
        ManifoldPoints(points_a, points_b, normals, counts, body_a, body_b),
        SolverBodies(position, problem.inv_mass, problem.inv_inertia, problem.approach_velocity),
        PairCoefficients(friction, restitution, store.impulse[rows], problem.slop),
        ColorOrder(problem.color_slices, problem.priority_starts, problem.lower),
        split_mass=settings.block_jacobi,
        block_normal=settings.uses_block_normal,
    )
    if settings.soft_step:  # Box2D v3's schedule (soft_step.py)
        forces = problem.velocity - problem.approach_velocity
        pseudo = solve_soft(batch, problem.velocity, forces, h, settings)
    else:
        pseudo = solve_contacts(batch, problem.velocity, h, settings)
    loads = None
    if with_loads:  # every slot of a manifold shares its normal; lambda_n is the sum
        loads = ContactLoads(
            batch.body_a,
            batch.body_b,
            batch.color_slices,
            batch.normal_jac[:, 0, 6:9],
            batch.impulse[:, :, 0].sum(axis=1),
        )
    # warm start next step from resting loads only: an impact's impulse (a point that
    # approached faster than IMPACT_SPEED) would relaunch the body it just stopped
    impact = batch.approach_speed < -IMPACT_SPEED
    store.impulse[rows] = np.where(impact[..., None], 0.0, batch.impulse)  # 0 in empty slots
    return pseudo, batch.depth, loads


def world_points(store: ManifoldStore, rows: np.ndarray, rotation, position, a, b):
    """World anchors of A and B and world normals ``(m, S, 3)`` of the store's ``rows``
    (``ManifoldStore.world_points``) as stacked matmuls ``p = local R^T + x``, several
    times faster than its einsum on a thousand rows; ``rotation (n, 3, 3)``, ``position
    (n, 3)``, the rows' bodies ``a, b (m,)``."""
    turn_a, turn_b = rotation[a].swapaxes(1, 2), rotation[b].swapaxes(1, 2)
    point_a = store.local_a[rows] @ turn_a + position[a][:, None]
    point_b = store.local_b[rows] @ turn_b + position[b][:, None]
    return point_a, point_b, store.normal_local[rows] @ turn_a


def lower_bodies(body_a: np.ndarray, body_b: np.ndarray, solvable: np.ndarray) -> np.ndarray:
    """(m, 2) bool: in each pair of moving bodies, the one fewer contacts away from the
    stage (or any body the solver does not move); neither when equal or unreached.

    The levels are breadth-first distances in the contact graph from the unmoved bodies
    (level 0; all of them are one node, ``n``): a plain breadth-first search over Python
    lists (a few hundred edges; one NumPy call per level cost more than the whole search).
    """
    n = len(solvable)
    node_a = np.where(solvable[body_a], body_a, n)
    node_b = np.where(solvable[body_b], body_b, n)
    neighbours: list[list[int]] = [[] for _ in range(n + 1)]
    for a, b in zip(node_a.tolist(), node_b.tolist(), strict=True):
        neighbours[a].append(b)
        neighbours[b].append(a)
    level = [math.inf] * (n + 1)
    level[n] = 0
    frontier = [n]
    while frontier:
        reached = []
        for node in frontier:
            for other in neighbours[node]:
                if level[other] == math.inf:
                    level[other] = level[node] + 1
                    reached.append(other)
        frontier = reached
    levels = np.array(level)
    la, lb = levels[node_a], levels[node_b]
    both_moving = (node_a < n) & (node_b < n)
    return np.stack([both_moving & (la < lb), both_moving & (lb < la)], axis=1)


def solver_velocities(b: Bodies, n: int) -> np.ndarray:
    """``(n, 6)`` [v, w]: dynamic bodies their velocity, kinematic their controlled one."""
    velocity = np.zeros((n, 6))
    motion = b.body_motion_type[:n]
    dynamic = motion == DYNAMIC
    velocity[dynamic] = body_velocities(b)[dynamic]
    kinematic = motion == KINEMATIC
    if kinematic.any():  # (most scenes have none)
        velocity[kinematic, :3] = b.body_solver_velocity[:n][kinematic]
        velocity[kinematic, 3:] = b.body_solver_angular_velocity[:n][kinematic]
    return velocity
