"""Reference path of the soft step: Box2D v3's schedule one contact point at a time.

The plain twin of :mod:`soft_step` (read that module's docstring for the equations),
written like Box2D v3's scalar ``b2SolveContact`` (``contact_solver.c``): per substep the
forces' share, a warm start, one soft sweep of the normal rows, the displacement ``d +=
h v``, ``relax_iterations`` relax sweeps of the normal and friction rows; then the
restitution pass and the stage's last word. A point's separation is ``s = -depth + n .
((d_b + theta_b x r_b) - (d_a + theta_a x r_a))`` (the relative velocity formula applied
to the displacements).

It reuses the rigid reference's rows (:func:`reference_solver.build_rows`: anchors,
tangents, split effective masses), friction and restitution updates and stage pass; the
soft normal row is its own. Tests check it agrees with :func:`soft_step.solve_soft` to
rounding.
"""

from __future__ import annotations

import numpy as np

from ..collision.contacts import SLOTS, ManifoldStore
from ..core.bodies import Bodies
from ..core.reference_geometry import dot
from ..core.settings import IMPACT_SPEED, SOFT_SPECULATIVE_TOLERANCE, SolverSettings
from ..solver.rolling_friction import ContactLoads
from ..solver.soft_step import Softness, check_soft_settings, contact_softness
from .reference_solver import (
    Bodies6,
    ContactRow,
    ManifoldRows,
    _block_steps,
    _friction_impulses,
    _restitution_impulses,
    _slot_groups,
    build_rows,
    contact_loads,
    stage_rows_last,
)


def separation(moved: Bodies6, m: ManifoldRows, p: ContactRow) -> float:
    """m, ``-depth + n . (relative displacement at the point)`` (linearized)."""
    return -p.depth + dot(moved.relative_velocity(m.body_a, m.body_b, p), p.directions[0])


def soft_row(s: float, h: float, soft: Softness, push: float) -> tuple[float, float, float]:
    """``(bias, mass scale, impulse scale)`` of a point with separation ``s`` in a soft
    sweep: speculative ``(s / h, 1, 0)`` when ``s > SOFT_SPECULATIVE_TOLERANCE``, else
    the soft push."""
    if s > SOFT_SPECULATIVE_TOLERANCE:
        return s / h, 1.0, 0.0
    return max(soft.mass_scale * soft.bias_rate * s, -push), soft.mass_scale, soft.impulse_scale


def _soft_normal_impulses(
    state: Bodies6, m: ManifoldRows, group: list, rows: list, block: bool = False
) -> None:
    """Normal rows of ``group`` with their ``rows`` ``(bias, mass scale, impulse
    scale)``: ``dl = -m_n (mass scale v_n + bias) - impulse scale lambda`` (the bias
    holds the mass scale already, as Box2D v3 writes it), the accumulated impulse clamped
    ``>= 0``, then applied together (a Jacobi block). ``block`` (a relax sweep's rigid
    rows, with the manifold's normal block): the block solve where it keeps every impulse
    non-negative (``reference_solver._block_steps``)."""
    residual, steps = [], []
    for p, (bias, mass_scale, impulse_scale) in zip(group, rows, strict=True):
        vn = dot(state.relative_velocity(m.body_a, m.body_b, p), p.directions[0])
        residual.append(vn + bias)
        steps.append(
            -p.masses[0] * mass_scale * vn - p.masses[0] * bias - impulse_scale * p.impulse[0]
        )
    if block and m.block is not None:
        steps = _block_steps(m, residual, steps)
    for k, p in enumerate(group):
        steps[k] = max(steps[k], -p.impulse[0])
        p.impulse[0] += steps[k]
    for p, step in zip(group, steps, strict=True):
        state.apply(m.body_a, m.body_b, p, step * p.directions[0])


def solve_soft_reference(
    bodies: Bodies,
    store: ManifoldStore,
    problem,
    h: float,
    settings: SolverSettings,
    with_loads: bool = True,
) -> tuple[np.ndarray, np.ndarray, ContactLoads | None]:
    """Reference for the soft branch of ``solve_stage._solve_batched``: updates
    ``problem.velocity`` and the store's impulses; returns pseudo velocities ``(n, 6)``,
    depths ``(m, S)`` and the normal loads (None unless ``with_loads``)."""
    check_soft_settings(settings)
    substeps, relaxes = int(settings.soft_substeps), int(settings.relax_iterations)
    hs = h / substeps
    forces = problem.velocity - problem.approach_velocity
    state = Bodies6(problem.approach_velocity, problem.inv_mass, problem.inv_inertia)
    approach = Bodies6(problem.approach_velocity, problem.inv_mass, problem.inv_inertia)
    manifolds = build_rows(bodies, store, problem.rows, state, approach, settings)
    for m in manifolds:
        for p in m.points:  # per substep inside the loop
            p.impulse = [value / substeps for value in p.impulse]
    moving_soft, stage_soft = contact_softness(settings, hs)
    stage = _stage_manifolds(problem)
    moved = Bodies6(np.zeros_like(problem.velocity), problem.inv_mass, problem.inv_inertia)
    groups = _slot_groups(settings.block_jacobi)
    n = len(state.v)
    for sub in range(substeps):
        for b in range(n):
            state.v[b] = state.v[b] + forces[b, :3] / substeps
            state.w[b] = state.w[b] + forces[b, 3:] / substeps
        _warm_start(state, manifolds, settings.warm_starting)
        biases = {}
        for k, m in enumerate(manifolds):
            soft = stage_soft if stage[k] else moving_soft
            for p in m.points:
                s = separation(moved, m, p)
                biases[id(p)] = soft_row(s, hs, soft, settings.contact_push_speed)
        for m in manifolds:
            for group in groups(m):
                _soft_normal_impulses(state, m, group, [biases[id(p)] for p in group])
        stage_rows_last(state, manifolds, problem, lambda p, b=biases: b[id(p)][0], settings)
        for b in range(n):
            moved.v[b] = moved.v[b] + hs * state.v[b]
            moved.w[b] = moved.w[b] + hs * state.w[b]
        relax = _relax_rows(moved, manifolds, hs)
        for sweep in range(sub * relaxes, (sub + 1) * relaxes):
            block = sweep < settings.block_normal_sweeps
            for m in manifolds:
                for group in groups(m):
                    rows = [relax[id(p)] for p in group]
                    _soft_normal_impulses(state, m, group, rows, block)
                    _friction_impulses(state, m, group, True)
    for m in manifolds:
        for group in groups(m):
            _restitution_impulses(state, m, group)
    stage_rows_last(state, manifolds, problem, lambda p: relax[id(p)][0], settings)
    problem.velocity[...] = state.array()
    depth = _store_impulses(store, problem.rows, manifolds, substeps)
    pseudo = np.zeros_like(problem.velocity)
    touched = sorted({b for m in manifolds for b in (m.body_a, m.body_b)})
    for b in touched:
        pseudo[b] = np.concatenate([moved.v[b], moved.w[b]]) / h - problem.velocity[b]
    loads = contact_loads(manifolds, problem.color_slices) if with_loads else None
    return pseudo, depth, loads


def _stage_manifolds(problem) -> list[bool]:
    """Per manifold: a stage row (from its color's first stage row on)."""
    stage = []
    for (start, stop), first in zip(problem.color_slices, problem.priority_starts, strict=True):
        stage += [k >= first for k in range(start, stop)]
    return stage


def _warm_start(state: Bodies6, manifolds: list[ManifoldRows], warm: bool) -> None:
    """Apply every point's accumulated impulse (every substep, as Box2D v3 does); without
    warm starting, set them to zero instead."""
    for m in manifolds:
        for p in m.points:
            if not warm:
                p.impulse = [0.0, 0.0, 0.0]
                continue
            impulse = sum(lam * d for lam, d in zip(p.impulse, p.directions, strict=True))
            state.apply(m.body_a, m.body_b, p, impulse)


def _relax_rows(moved: Bodies6, manifolds: list[ManifoldRows], h: float) -> dict:
    """Per point ``(bias, 1, 0)``: the relax sweep's rigid row, speculative bias ``s / h``
    for ``s > 0``, else none."""
    return {
        id(p): (max(separation(moved, m, p), 0.0) / h, 1.0, 0.0)
        for m in manifolds
        for p in m.points
    }


def _store_impulses(store: ManifoldStore, rows: np.ndarray, manifolds, substeps: int):
    """Write the step's impulses (``substeps`` times the last substep's) to the store,
    none for an impact (``IMPACT_SPEED``, as the rigid path); returns the depths ``(m,
    S)``."""
    depth = np.zeros((len(manifolds), SLOTS))
    for k, (row, m) in enumerate(zip(rows.tolist(), manifolds, strict=True)):
        for slot, p in enumerate(m.points):
            p.impulse = [value * substeps for value in p.impulse]
            impact = p.approach_speed < -IMPACT_SPEED
            store.impulse[row, slot] = 0.0 if impact else p.impulse
            depth[k, slot] = p.depth
    return depth
