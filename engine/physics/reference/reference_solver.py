"""Reference path of the solve stage: sequential impulses one contact point at a time.

The plain version of :mod:`solver` (the batched NumPy solver), written like box2d-lite's
``Arbiter::PreStep`` / ``Arbiter::ApplyImpulse`` (Catto, GDC 2005/2006). It builds its own
anchors, tangents and effective masses (nothing is shared with ``solver.build_batch``), so
tests that compare the two paths cross-check the Jacobians and effective masses too.

For a contact point with unit normal ``n`` (A -> B), anchors ``r_a = p - x_a``,
``r_b = p - x_b`` (p the midpoint of the two anchors) and a direction ``d`` (n, t1 or t2):

* relative velocity ``dv = (v_b + w_b x r_b) - (v_a + w_a x r_a)``, ``v_d = dv . d``;
* effective mass ``m_d = 1 / (n_split (1/m_a + 1/m_b + (r_a x d) . I_a^-1 (r_a x d)
  + (r_b x d) . I_b^-1 (r_b x d)))``, with ``n_split`` the manifold's touching points when
  ``block_jacobi`` mass splitting is on, else 1;
* an impulse ``P = lambda d`` changes ``v_a -= P / m_a``, ``w_a -= I_a^-1 (r_a x P)``,
  ``v_b += P / m_b``, ``w_b += I_b^-1 (r_b x P)``.

Per iteration, per graph color, per manifold: the normal rows (``dl = -m_n (v_n + b)``,
accumulated impulse clamped ``>= 0``; in the first ``block_normal_sweeps`` the block
solve ``dl = -B (v_n + b)`` of the touching points, ``B`` a smooth pseudo-inverse of their
``K_ij = J_i M^-1 J_j^T``, kept when every accumulated impulse stays ``>= 0``, see
:func:`normal_block`) then the friction rows
(2-D tangent impulse clamped to the circle ``|lambda_t| <= mu lambda_n``). With
``block_jacobi`` all points of a manifold read the velocities from before their common
update (a Jacobi block); otherwise one point after the other (Gauss-Seidel). Then the
restitution pass and the stage's last word (:func:`stage_rows_last`: lumped push-only rows
of the contacts with unmoved bodies, then shock propagation), and the split-impulse
position solve on pseudo velocities, which also ends with the stage's last word. The
batched :func:`solver.solve_contacts` must agree with :func:`solve_reference` to rounding
(tested).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..collision.contacts import SLOTS, ManifoldStore
from ..core.bodies import Bodies
from ..core.quaternions import quat_to_matrix
from ..core.reference_geometry import cross3, dot, dot12, rotate
from ..core.settings import (
    BLOCK_FEASIBILITY_TOLERANCE,
    BLOCK_REGULARIZATION,
    DEEP_OVERLAP,
    IMPACT_SPEED,
    MAX_CORRECTION_SPEED,
    OVERLAP_BAUMGARTE,
    POSITION_BAUMGARTE,
    RESTITUTION_VELOCITY_THRESHOLD,
    SPLIT_TOUCH_DISTANCE,
    TANGENT_AXIS_SWITCH,
    TINY,
    SolverSettings,
)
from ..solver.rolling_friction import ContactLoads


@dataclass
class ContactRow:
    """One contact point prepared for the solver (box2d-lite's ``Contact``)."""

    r_a: np.ndarray  # (3,) m, from A's center to the contact point, world frame
    r_b: np.ndarray  # (3,) m, from B's center
    directions: list  # [n, t1, t2], unit (3,) world vectors
    masses: list  # [m_n, m_t1, m_t2] effective masses, kg
    depth: float  # m, > 0 overlapping, < 0 a speculative gap
    approach_speed: float  # m/s, v_n at the start of the step (< 0 approaching)
    impulse: list  # [lambda_n, lambda_t1, lambda_t2] accumulated, N s


@dataclass
class NormalBlock:
    """The block normal solve of one manifold: the indices of its ``touching`` points and
    ``inverse``, the smooth pseudo-inverse of their ``K_ij = J_i M^-1 J_j^T``
    (:func:`normal_block`)."""

    touching: list
    inverse: np.ndarray


@dataclass
class ManifoldRows:
    """The contact rows of one manifold and its pair coefficients; ``block`` its normal
    block (None: Jacobi rows only)."""

    body_a: int
    body_b: int
    friction: float
    restitution: float
    points: list
    block: NormalBlock | None = None


class Bodies6:
    """Velocities ``[v, w]`` of all bodies as Python lists, with inverse masses and world
    inverse inertias: what the scalar solver reads and writes."""

    def __init__(self, velocity: np.ndarray, inv_mass: np.ndarray, inv_inertia: np.ndarray):
        self.v = [np.array(row[:3]) for row in velocity]
        self.w = [np.array(row[3:]) for row in velocity]
        self.inv_mass = inv_mass
        self.inv_inertia = inv_inertia

    def relative_velocity(self, a: int, b: int, row: ContactRow) -> np.ndarray:
        """``dv = (v_b + w_b x r_b) - (v_a + w_a x r_a)`` at the contact point."""
        return (self.v[b] + cross3(self.w[b], row.r_b)) - (self.v[a] + cross3(self.w[a], row.r_a))

    def apply(self, a: int, b: int, row: ContactRow, impulse: np.ndarray) -> None:
        """Apply ``+impulse`` to B and ``-impulse`` to A at the contact point."""
        self.v[a] = self.v[a] - self.inv_mass[a] * impulse
        self.w[a] = self.w[a] - rotate(self.inv_inertia[a], cross3(row.r_a, impulse))
        self.v[b] = self.v[b] + self.inv_mass[b] * impulse
        self.w[b] = self.w[b] + rotate(self.inv_inertia[b], cross3(row.r_b, impulse))

    def array(self) -> np.ndarray:
        return np.array([np.concatenate([v, w]) for v, w in zip(self.v, self.w, strict=True)])


def tangent_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents: ``t1 = normalize(n x axis)`` with ``axis`` X unless ``|n_x|``
    reaches ``TANGENT_AXIS_SWITCH`` (then Y), and ``t2 = n x t1``."""
    axis = (
        np.array([1.0, 0.0, 0.0])
        if abs(normal[0]) < TANGENT_AXIS_SWITCH
        else np.array([0.0, 1.0, 0.0])
    )
    t1 = cross3(normal, axis)
    t1 = t1 / max(np.sqrt(dot(t1, t1)), TINY)
    return t1, cross3(normal, t1)


def effective_mass(bodies: Bodies6, a: int, b: int, r_a, r_b, direction, n_split) -> float:
    """``1 / (n_split J M^-1 J^T)`` for the row along ``direction``."""
    ra_x_d, rb_x_d = cross3(r_a, direction), cross3(r_b, direction)
    k = (
        bodies.inv_mass[a]
        + bodies.inv_mass[b]
        + dot(ra_x_d, rotate(bodies.inv_inertia[a], ra_x_d))
        + dot(rb_x_d, rotate(bodies.inv_inertia[b], rb_x_d))
    )
    return 1.0 / (n_split * max(k, TINY))


def build_rows(
    bodies: Bodies,
    store: ManifoldStore,
    rows: np.ndarray,
    state: Bodies6,
    approach: Bodies6,
    settings: SolverSettings,
) -> list[ManifoldRows]:
    """Contact rows of the manifolds ``rows`` (box2d-lite's ``Arbiter::PreStep``)."""
    manifolds = []
    for row in rows.tolist():
        a, b = (int(i) for i in store.bodies[row])
        ra, xa = quat_to_matrix(bodies.body_rotation[a]), bodies.body_position[a]
        rb, xb = quat_to_matrix(bodies.body_rotation[b]), bodies.body_position[b]
        points = []
        for slot in range(store.count[row]):
            point_a = rotate(ra, store.local_a[row, slot]) + xa
            point_b = rotate(rb, store.local_b[row, slot]) + xb
            normal = rotate(ra, store.normal_local[row, slot])
            middle = 0.5 * (point_a + point_b)
            impulse = (
                store.impulse[row, slot].tolist() if settings.warm_starting else [0.0, 0.0, 0.0]
            )
            points.append(
                ContactRow(
                    middle - xa,
                    middle - xb,
                    [normal, *tangent_basis(normal)],
                    [],
                    dot(point_a - point_b, normal),
                    0.0,
                    impulse,
                )
            )
        touching = sum(p.depth > -SPLIT_TOUCH_DISTANCE for p in points)
        n_split = max(touching, 1) if settings.block_jacobi else 1
        for p in points:
            p.masses = [effective_mass(state, a, b, p.r_a, p.r_b, d, n_split) for d in p.directions]
            p.approach_speed = dot(approach.relative_velocity(a, b, p), p.directions[0])
        manifolds.append(
            ManifoldRows(
                a,
                b,
                bodies.body_friction[a] * bodies.body_friction[b],
                bodies.body_restitution[a] * bodies.body_restitution[b],
                points,
                normal_block(state, a, b, points) if settings.uses_block_normal else None,
            )
        )
    return manifolds


def normal_block(state: Bodies6, a: int, b: int, points: list) -> NormalBlock:
    """The touching points (gap below ``SPLIT_TOUCH_DISTANCE``) of a manifold and the smooth
    pseudo-inverse ``(K + d I)^-1 K (K + d I)^-1`` of their ``K_ij = J_i M^-1 J_j^T``, with
    ``d = eps s``, ``s`` the largest diagonal entry and ``eps`` ``BLOCK_REGULARIZATION``:
    ``1 / w`` on an eigenvalue ``w >> d`` of K, 0 on its null space (a box face's four
    coplanar points give a K of rank 3), at most ``1 / (4 d)`` in between."""
    touching = [i for i, p in enumerate(points) if p.depth > -SPLIT_TOUCH_DISTANCE]
    rows = [points[i] for i in touching]
    k = np.array(
        [[dot12(jacobian_row(p), mobility_row(state, a, b, q)) for q in rows] for p in rows]
    ).reshape(len(rows), len(rows))
    if not rows:
        return NormalBlock(touching, k)
    d = BLOCK_REGULARIZATION * max(max(k[i, i] for i in range(len(rows))), TINY)
    inverse = np.linalg.inv(k + d * np.eye(len(rows)))
    return NormalBlock(touching, inverse @ k @ inverse)


def solve_reference(
    bodies: Bodies,
    store: ManifoldStore,
    problem,
    h: float,
    settings: SolverSettings,
    with_loads: bool = True,
) -> tuple[np.ndarray, np.ndarray, ContactLoads | None]:
    """Reference for ``solve_stage._solve_batched``: updates ``problem.velocity`` and the
    store's impulses; returns pseudo velocities ``(n, 6)``, depths ``(m, S)`` and the
    manifolds' normal loads (rolling friction's input; None unless ``with_loads``)."""
    state = Bodies6(problem.velocity, problem.inv_mass, problem.inv_inertia)
    approach = Bodies6(problem.approach_velocity, problem.inv_mass, problem.inv_inertia)
    manifolds = build_rows(bodies, store, problem.rows, state, approach, settings)
    if settings.warm_starting:
        for m in manifolds:
            for p in m.points:  # P = lambda_n n + lambda_t1 t1 + lambda_t2 t2
                state.apply(
                    m.body_a,
                    m.body_b,
                    p,
                    sum(lam * d for lam, d in zip(p.impulse, p.directions, strict=True)),
                )
    groups = _slot_groups(settings.block_jacobi)
    for sweep in range(settings.velocity_iterations):
        block = sweep < settings.block_normal_sweeps
        for m in manifolds:
            for group in groups(m):
                _normal_impulses(state, m, group, h, settings.accumulate_impulses, block)
                _friction_impulses(state, m, group, settings.accumulate_impulses)
    for m in manifolds:
        for group in groups(m):
            _restitution_impulses(state, m, group)
    stage_rows_last(state, manifolds, problem, lambda p: max(-p.depth, 0.0) / h, settings)
    problem.velocity[...] = state.array()
    depth = np.zeros((len(manifolds), SLOTS))
    for k, (row, m) in enumerate(zip(problem.rows.tolist(), manifolds, strict=True)):
        for slot, p in enumerate(m.points):
            # warm start next step from resting loads only: an impact's impulse (a point
            # that approached faster than IMPACT_SPEED) would relaunch the body it stopped
            impact = p.approach_speed < -IMPACT_SPEED
            store.impulse[row, slot] = 0.0 if impact else p.impulse
            depth[k, slot] = p.depth
    pseudo = solve_positions_reference(manifolds, problem, h, settings)
    loads = contact_loads(manifolds, problem.color_slices) if with_loads else None
    return pseudo, depth, loads


def contact_loads(manifolds: list[ManifoldRows], color_slices) -> ContactLoads:
    """Each manifold's bodies, normal and total normal impulse (``sum lambda_n``)."""
    normal = np.array(
        [m.points[0].directions[0] if m.points else (0.0, 1.0, 0.0) for m in manifolds],
        dtype=np.float64,
    ).reshape(-1, 3)
    lambda_n = np.array([sum(p.impulse[0] for p in m.points) for m in manifolds], dtype=np.float64)
    return ContactLoads(
        np.array([m.body_a for m in manifolds], dtype=np.int64),
        np.array([m.body_b for m in manifolds], dtype=np.int64),
        color_slices,
        normal,
        lambda_n,
    )


def _slot_groups(block_jacobi: bool):
    """Points solved together: all of a manifold's (Jacobi block) or one at a time."""
    if block_jacobi:
        return lambda m: [m.points] if m.points else []
    return lambda m: [[p] for p in m.points]


def _normal_impulses(
    state: Bodies6, m: ManifoldRows, group: list, h: float, accumulate: bool, block: bool
) -> None:
    """Normal rows: ``dl = -m_n (v_n + b)`` with the speculative bias ``b = max(-d, 0) / h``
    (a gap d < 0 may close by |d| / h this step); with ``block`` (a block sweep) and a
    normal block the touching points take the block solve ``dl = -B (v_n + b)`` instead
    when no accumulated impulse falls below zero by more than round-off
    (:func:`_block_steps`); clamp, then apply together."""
    residual = [
        dot(state.relative_velocity(m.body_a, m.body_b, p), p.directions[0])
        + max(-p.depth, 0.0) / h
        for p in group
    ]
    steps = [-p.masses[0] * r for p, r in zip(group, residual, strict=True)]
    if block and m.block is not None:  # block_jacobi: the group is all of m.points
        steps = _block_steps(m, residual, steps)
    for k, p in enumerate(group):
        if accumulate:  # clamp the accumulated impulse: lambda + dl >= 0
            steps[k] = max(steps[k], -p.impulse[0])
        else:  # clamp each increment (box2d-lite's toggle)
            steps[k] = max(steps[k], 0.0)
        p.impulse[0] += steps[k]
    for p, step in zip(group, steps, strict=True):
        state.apply(m.body_a, m.body_b, p, step * p.directions[0])


def _block_steps(m: ManifoldRows, residual: list, steps: list) -> list:
    """The block solve ``dl_i = -sum_j B_ij (v_n + b)_j`` over the touching points, taken
    (for them; the others keep their Jacobi ``steps``) when every touching point keeps
    ``lambda + dl >= -BLOCK_FEASIBILITY_TOLERANCE lambda`` (the accumulated impulse stays
    non-negative but for round-off); else the Jacobi ``steps`` unchanged."""
    assert m.block is not None
    touching, inverse = m.block.touching, m.block.inverse
    exact = [
        -sum(inverse[row][col] * residual[j] for col, j in enumerate(touching))
        for row in range(len(touching))
    ]
    floor = 1.0 + BLOCK_FEASIBILITY_TOLERANCE
    if not all(
        step >= -floor * m.points[i].impulse[0] for i, step in zip(touching, exact, strict=True)
    ):
        return steps
    merged = list(steps)
    for i, step in zip(touching, exact, strict=True):
        merged[i] = step
    return merged


def _friction_impulses(state: Bodies6, m: ManifoldRows, group: list, accumulate: bool) -> None:
    """Friction rows of each point: a 2-D impulse clamped to ``|lambda_t| <= mu lambda_n``."""
    steps = []
    for p in group:
        dv = state.relative_velocity(m.body_a, m.body_b, p)
        old = p.impulse[1:]
        new = [
            (old[t] if accumulate else 0.0) - p.masses[1 + t] * dot(dv, p.directions[1 + t])
            for t in range(2)
        ]
        limit = m.friction * p.impulse[0]
        scale = min(1.0, limit / max(np.hypot(new[0], new[1]), TINY))
        new = [value * scale for value in new]
        step = [new[t] - old[t] for t in range(2)] if accumulate else new
        p.impulse[1:] = [old[t] + step[t] for t in range(2)]
        steps.append(step)
    for p, step in zip(group, steps, strict=True):
        state.apply(m.body_a, m.body_b, p, step[0] * p.directions[1] + step[1] * p.directions[2])


def _restitution_impulses(state: Bodies6, m: ManifoldRows, group: list) -> None:
    """Bounce the loaded points that approached faster than the threshold: ``v_n = -e v_n0``."""
    steps = []
    for p in group:
        fast = p.approach_speed < -RESTITUTION_VELOCITY_THRESHOLD
        if not (m.restitution > 0 and fast and p.impulse[0] > 0):
            steps.append(0.0)
            continue
        vn = dot(state.relative_velocity(m.body_a, m.body_b, p), p.directions[0])
        step = -p.masses[0] * (vn + m.restitution * p.approach_speed)
        step = max(p.impulse[0] + step, 0.0) - p.impulse[0]
        p.impulse[0] += step
        steps.append(step)
    for p, step in zip(group, steps, strict=True):
        state.apply(m.body_a, m.body_b, p, step * p.directions[0])


def solve_positions_reference(
    manifolds: list[ManifoldRows], problem, h: float, settings: SolverSettings
) -> np.ndarray:
    """Split impulses: pseudo velocities ``(n, 6)`` that push penetrations deeper than
    ``PENETRATION_SLOP`` apart at ``min(beta (d - slop) / h, MAX_CORRECTION_SPEED)``.

    The same normal rows as the velocity solve, on pseudo velocities starting at zero with
    their own accumulated impulses; they move the bodies this step and are then discarded,
    so they add no kinetic energy (Catto; Bullet's split impulse).
    """
    pseudo = Bodies6(np.zeros((len(problem.inv_mass), 6)), problem.inv_mass, problem.inv_inertia)
    if not settings.position_correction or settings.position_iterations == 0:
        return pseudo.array()
    slop = {id(p): problem.slop[k] for k, m in enumerate(manifolds) for p in m.points}
    # bodies created overlapping (contacts deeper than DEEP_OVERLAP beyond the slop): more
    # sweeps, and a firmer Baumgarte factor for those contacts; still capped at
    # MAX_CORRECTION_SPEED
    deep = {id(p): p.depth - slop[id(p)] > DEEP_OVERLAP for m in manifolds for p in m.points}
    iterations = settings.position_iterations
    if any(deep.values()):
        iterations = max(iterations, settings.overlap_position_iterations)

    def target_of(p: ContactRow) -> float:
        beta = OVERLAP_BAUMGARTE if deep[id(p)] else POSITION_BAUMGARTE
        return _position_target(p, h, slop[id(p)], beta)

    groups = _slot_groups(settings.block_jacobi)
    pushed = {id(p): 0.0 for m in manifolds for p in m.points}  # accumulated pseudo impulse
    for _ in range(iterations):
        for m in manifolds:
            for group in groups(m):
                steps = []
                for p in group:
                    target = target_of(p)
                    vn = dot(pseudo.relative_velocity(m.body_a, m.body_b, p), p.directions[0])
                    step = -p.masses[0] * (vn - target)
                    step = max(step, -pushed[id(p)])  # accumulated pseudo impulse >= 0
                    pushed[id(p)] += step
                    steps.append(step)
                for p, step in zip(group, steps, strict=True):
                    pseudo.apply(m.body_a, m.body_b, p, step * p.directions[0])
    stage_rows_last(pseudo, manifolds, problem, lambda p: -target_of(p), settings)
    return pseudo.array()


def _position_target(p: ContactRow, h: float, slop: float, beta: float) -> float:
    """m/s, the separation speed that removes ``beta (depth - slop)`` this step, at most
    ``MAX_CORRECTION_SPEED``."""
    return min(beta * max(p.depth - slop, 0.0) / h, MAX_CORRECTION_SPEED)


# ------------------------------------------------------------------------------------------
# the stage's last word (mirrors stage_priority.stage_rows_last)
# ------------------------------------------------------------------------------------------
def jacobian_row(p: ContactRow) -> np.ndarray:
    """``J = [-n, -(r_a x n), n, r_b x n]`` (12,) of a point's normal row."""
    n = p.directions[0]
    return np.concatenate([-n, -cross3(p.r_a, n), n, cross3(p.r_b, n)])


def mobility_row(
    state: Bodies6, a: int, b: int, p: ContactRow, frozen: int | None = None
) -> np.ndarray:
    """``W = M^-1 J^T`` (12,): the velocity change per unit normal impulse; the body
    ``frozen`` (0: A, 1: B) gets infinite mass (its 6 entries are zero)."""
    n = p.directions[0]
    w = np.concatenate(
        [
            -state.inv_mass[a] * n,
            -rotate(state.inv_inertia[a], cross3(p.r_a, n)),
            state.inv_mass[b] * n,
            rotate(state.inv_inertia[b], cross3(p.r_b, n)),
        ]
    )
    if frozen is not None:
        w[6 * frozen : 6 * frozen + 6] = 0.0
    return w


def stage_rows_last(
    state: Bodies6, manifolds: list[ManifoldRows], problem, bias_of, settings: SolverSettings
) -> None:
    """The stage wins: ``stage_iterations`` sweeps over the *stage rows* (manifolds with a
    body the solver does not move, the end of each color), then as many over the pairs of
    moving bodies with the body nearer the stage held fixed (shock propagation,
    Guendelman et al. 2003). Each manifold acts as one *lumped* normal row: ``J`` and ``W``
    the means over its points, ``m = 1 / (J . W)``, bias the mean of its points' biases
    (``bias_of(point)``); a push-only impulse ``max(-m (J V + b), 0)``."""
    stage_rows = [
        m
        for (_, stop), first in zip(problem.color_slices, problem.priority_starts, strict=True)
        for m in range(first, stop)
    ]
    for _ in range(settings.stage_iterations):
        for k in stage_rows:
            _lumped_push(state, manifolds[k], None, bias_of)
    frozen = [0 if lower[0] else 1 if lower[1] else None for lower in problem.lower.tolist()]
    if not any(f is not None for f in frozen):
        return
    for _ in range(settings.stage_iterations):
        for m, fixed in zip(manifolds, frozen, strict=True):
            if fixed is not None:
                _lumped_push(state, m, fixed, bias_of)


def _lumped_push(state: Bodies6, m: ManifoldRows, frozen: int | None, bias_of) -> None:
    """One push-only update of manifold ``m``'s lumped row (``frozen``: see
    :func:`mobility_row`); no impulse when the lumped row has no mobility (``J . W <= 0``)."""
    a, b = m.body_a, m.body_b
    active = [(jacobian_row(p), mobility_row(state, a, b, p, frozen), p) for p in m.points]
    if not active:
        return
    jac = np.sum([j for j, _, _ in active], axis=0) / len(active)  # mean J of the points
    w = np.sum([w for _, w, _ in active], axis=0) / len(active)  # mean W
    k = dot12(jac, w)
    if k <= 0:
        return
    bias = sum(bias_of(p) for _, _, p in active) / len(active)
    velocity = np.concatenate([state.v[a], state.w[a], state.v[b], state.w[b]])
    step = max(-(dot12(jac, velocity) + bias) / k, 0.0)
    state.v[a], state.w[a] = state.v[a] + w[0:3] * step, state.w[a] + w[3:6] * step
    state.v[b], state.w[b] = state.v[b] + w[6:9] * step, state.w[b] + w[9:12] * step
