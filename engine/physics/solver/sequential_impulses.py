"""Sequential impulses (projected Gauss-Seidel) for contacts with friction and restitution.

The rows (Jacobians ``J``, ``W = M^-1 J^T``, effective masses ``m_eff``) are made by
:mod:`contact_batch`; this module runs the iterations on them (Catto, "Iterative Dynamics
with Temporal Coherence", GDC 2005; box2d-lite ``Arbiter.cpp``). Each iteration computes
``d_lambda = -m_eff (J V + b)``, clamps the *accumulated* impulse (normal: ``>= 0``;
friction: the 2-D tangent impulse inside the circle ``|lambda_t| <= mu lambda_n``, isotropic
Coulomb cone) and applies only the change, ``V += W d_lambda``. Warm starting applies last
step's impulses first.

Vectorization (Box2D v3 ``contact_solver.c``): manifolds are sorted by graph color; all
manifolds of one color touch distinct dynamic bodies and are solved by one NumPy batch, so
colors remain Gauss-Seidel. The (up to) four points of one manifold share their bodies: they
are solved together as a Jacobi block with mass splitting (Tonge et al. 2012, see
:mod:`contact_batch`), which keeps the block convergent. :mod:`reference_solver` is the
plain version of this module (one point at a time); tests check both agree to rounding
(the sums run in a different order). Each batched function names the reference it mirrors.

The loops cost NumPy call overhead (arrays hold a few hundred numbers), so the inner loop
is kept to few calls: :mod:`color_rows` gathers each manifold's velocities as one column
(ending in a constant 1 that carries the bias), multiplies it by small manifold-major
matrices, and keeps the accumulated impulses and every clamp quantity-major (manifolds
contiguous): 17 NumPy calls per color and sweep, the matrices and each color's views made
once per step. The solve's floor is colors x iterations x those calls; the coloring
already uses as many colors as the busiest body has contacts (the least possible:
measured on the benchmark piles). The accumulated impulses are kept with their own sign
(``lambda >= 0``), as the formulas read.

Block normal solve (``SolverSettings.block_normal_sweeps``, Box2D's block solver
``b2_contact_solver.cpp``, its all-points-active case): mass splitting removes only
``1/n`` of a manifold's common residual per sweep (a box face's four points: a quarter,
``(3/4)^10`` = 5.6 % left after ten sweeps), which left a zero-gravity cube a warm-started
upward speed after an inelastic impact. So the first sweep of a step computes the solution
of the touching points' normal rows, ``d_lambda = -B (J V + b)`` with ``B`` a smooth
pseudo-inverse of ``K = J M^-1 J^T`` (made once per step by :func:`contact_batch.normal_blocks`),
and takes it for a manifold only where every accumulated ``lambda + d_lambda`` stays
``>= 0`` (there complementarity holds: every touching point ends with ``v_n + b = 0`` and
``lambda >= 0``); elsewhere, and in the later sweeps, the mass-split Jacobi update, so a
sweep is never worse than without it (:func:`color_rows._block_candidates`).

Position correction (split impulses, Catto / Bullet): a separate pseudo velocity solve
pushes penetrations deeper than the slop apart at ``beta (depth - slop) / h`` (slop:
``PENETRATION_SLOP``, capped at the manifold's feature length for small bodies);
the pseudo velocity moves the bodies this step and is then discarded, so it adds no energy.
Bodies created overlapping (contacts deeper than ``DEEP_OVERLAP``) get more sweeps and,
for those contacts, a firmer ``OVERLAP_BAUMGARTE``; the push stays a pseudo velocity capped at
``MAX_CORRECTION_SPEED`` (2 m/s), so they separate calmly, never launched. This is Bullet's
split impulse (``m_splitImpulsePenetrationThreshold``, pseudo velocities that are thrown
away), Box2D v3's soft contact with ``contactPushMaxVelocity`` (3 m/s by default) and
Jolt's position solve (Baumgarte 0.2 beyond ``mPenetrationSlop`` = 2 cm, at most
``mMaxPenetrationDistance`` = 0.2 m corrected per step).
Restitution (Box2D v3 "relax + restitution"): after the iterations, points that approached
faster than ``RESTITUTION_VELOCITY_THRESHOLD`` and carry load get ``v_n = -e v_n0``.

The stage always wins (``SolverSettings.stage_iterations``): :mod:`stage_priority` ends
both the velocity and the position solve with push-only sweeps that give the stage
contacts, then the body nearer the stage, the last word.
"""

from __future__ import annotations

import numpy as np

from ..core.settings import (
    DEEP_OVERLAP,
    MAX_CORRECTION_SPEED,
    OVERLAP_BAUMGARTE,
    POSITION_BAUMGARTE,
    RESTITUTION_VELOCITY_THRESHOLD,
    SolverSettings,
)
from .color_rows import (
    ColorRows,
    color_rows,
    impulses,
    new_impulses,
    normal_matrix,
    normal_update,
    row_matrices,
    rows_matrix,
    store_tangents,
    velocity_update,
    with_constant,
)
from .contact_batch import SLOTS, ContactBatch, batch_gathers
from .stage_priority import stage_rows_last


def warm_start(batch: ContactBatch, velocity: np.ndarray) -> None:
    """Apply the cached impulses: ``V += W lambda`` for all rows (a body's changes from all
    its manifolds summed by one ``bincount`` over the flat velocity indices)."""
    lam_t = batch.impulse[:, :, 1:].reshape(len(batch.body_a), 2 * SLOTS, 1)
    dv = batch.normal_w @ batch.impulse[:, :, :1] + batch.tangent_w @ lam_t  # (m, 12, 1)
    change = np.bincount(batch_gathers(batch).ravel(), dv.ravel(), minlength=velocity.size)
    velocity += change.reshape(velocity.shape)


def with_one(velocity: np.ndarray) -> np.ndarray:
    """The flat velocities ``(6 n + 1,)`` of ``velocity (n, 6)`` followed by the constant 1
    that every manifold's velocity column ends in (:mod:`color_rows`)."""
    return np.append(velocity.reshape(-1), 1.0)


def _solver_rows(batch: ContactBatch, bias: np.ndarray, settings: SolverSettings, one: int):
    """``(state, matrices, colors)`` of the batch (:mod:`color_rows`) for the velocity bias
    ``bias (m, S, 1)``; ``one`` is the index of the flat velocities' constant 1. Made once and
    kept on the batch (the position solve reuses the rows)."""
    if batch.cache.rows is None:
        state = new_impulses(batch.impulse)
        matrices = row_matrices(batch, bias, settings.accumulate_impulses)
        colors = [
            (slice(start, stop), used)
            for (start, stop), used in zip(batch.color_slices, batch.color_points, strict=True)
        ]
        gathers = with_constant(batch_gathers(batch), one)
        rows = color_rows(state, matrices, gathers, colors, settings.block_jacobi)
        batch.cache.rows = (state, matrices, rows)
    return batch.cache.rows


def solve_velocities(
    batch: ContactBatch, velocity: np.ndarray, h: float, settings: SolverSettings
) -> None:
    """Velocity iterations (one slim normal and friction update per color), then the
    restitution pass and the stage's last word.

    Reference: the loops of :func:`reference_solver.solve_reference`."""
    flat = with_one(velocity)  # (n * 6 + 1,)
    # speculative contacts: a gap g > 0 may close by g / h this step, b = g / h
    bias = (np.maximum(-batch.depth, 0.0) / h)[..., None]
    state, matrices, colors = _solver_rows(batch, bias, settings, len(flat) - 1)
    accumulate = settings.accumulate_impulses
    block_sweeps = settings.block_normal_sweeps if matrices.block is not None else 0
    with np.errstate(divide="ignore", invalid="ignore"):  # the friction circle's 0 / 0
        for sweep in range(settings.velocity_iterations):
            block = sweep < block_sweeps
            for color in colors:
                for rows in color:
                    velocity_update(rows, flat, accumulate, block, sweep)
    store_tangents(colors, state, settings.velocity_iterations)
    _restitution(batch, flat, colors, state[0])
    stage_rows_last(batch, flat[:-1], bias, settings)
    batch.impulse[...] = impulses(state)
    velocity[...] = flat[:-1].reshape(velocity.shape)


def _restitution(batch, flat, colors: list[list[ColorRows]], lam_n) -> None:
    """Bounce pass: target ``v_n = -e v_n0`` on the loaded, fast-approaching points;
    ``lam_n (S, m)`` the accumulated normal impulses (the rows' views are updated)."""
    fast = batch.approach_speed < -RESTITUTION_VELOCITY_THRESHOLD
    bounce = (batch.restitution > 0) & fast & (lam_n.T > 0)
    if not bounce.any():
        return
    # rows where bouncing: q = m_n (J V + e v_n0), lambda_n' = max(lambda_n - q, 0); the
    # others have q = 0 and keep lambda_n
    goal = (batch.restitution * batch.approach_speed)[..., None]  # e v_n0
    matrix = normal_matrix(batch.normal_mass, batch.normal_jac, goal)
    matrix = np.where(bounce[..., None], matrix, 0.0)
    # a color without a bouncing point would apply zero impulses: it is skipped (colors
    # are never empty, so reduceat over their starts gives one answer per color)
    bouncing = np.logical_or.reduceat(bounce.any(axis=1), [a for a, _ in batch.color_slices])
    for color, bounces in zip(colors, bouncing.tolist(), strict=True):
        if bounces:
            for rows in color:
                normal_update(rows, flat, rows_matrix(rows, matrix), rows.lam_n)


def solve_positions(
    batch: ContactBatch, n_bodies: int, h: float, settings: SolverSettings
) -> np.ndarray:
    """Split-impulse pseudo velocities ``(n, 6)`` removing penetration beyond the slop.

    Reference: :func:`reference_solver.solve_positions_reference`."""
    flat = np.zeros(6 * n_bodies + 1)
    pseudo = flat[:-1].reshape(n_bodies, 6)
    if not settings.position_correction or settings.position_iterations == 0:
        return pseudo
    flat[-1] = 1.0  # the velocity columns' constant (color_rows)
    # target pseudo speed: beta (depth - slop) / h, clamped to MAX_CORRECTION_SPEED
    excess = np.maximum(batch.depth - batch.slop, 0.0)
    # bodies created overlapping (contacts deeper than DEEP_OVERLAP): more sweeps, and a
    # firmer push for those contacts
    deep = excess > DEEP_OVERLAP
    beta = np.where(deep, OVERLAP_BAUMGARTE, POSITION_BAUMGARTE)
    iterations = settings.position_iterations
    if deep.any():
        iterations = max(iterations, settings.overlap_position_iterations)
    target = np.minimum(beta * excess / h, MAX_CORRECTION_SPEED)
    if not target.any():
        # nothing deeper than the slop: every row's q = m_n (J 0 + 0) = 0, the sweeps and
        # the stage's pass would leave the pseudo velocities exactly zero
        return pseudo
    bias = -target[..., None]  # b = -target: drive v_n towards +target
    _, matrices, colors = _solver_rows(batch, np.zeros_like(bias), settings, len(flat) - 1)
    matrix = normal_matrix(batch.normal_mass, batch.normal_jac, bias)
    lam = np.zeros((SLOTS, len(bias)))  # accumulated pseudo impulses, quantity-major
    passes = [
        [(rows, rows_matrix(rows, matrix), lam[rows.slots, rows.manifolds]) for rows in color]
        for color in colors
    ]
    for _ in range(iterations):
        for color in passes:
            for rows, slot_matrix, lam_n in color:
                normal_update(rows, flat, slot_matrix, lam_n)
    stage_rows_last(batch, flat[:-1], bias, settings)
    return pseudo


def solve_contacts(
    batch: ContactBatch, velocity: np.ndarray, h: float, settings: SolverSettings
) -> np.ndarray:
    """Full solve: warm start, velocity iterations, restitution; returns pseudo velocities."""
    if settings.warm_starting:
        warm_start(batch, velocity)
    else:
        batch.impulse[:] = 0.0
    solve_velocities(batch, velocity, h, settings)
    return solve_positions(batch, len(velocity), h, settings)
