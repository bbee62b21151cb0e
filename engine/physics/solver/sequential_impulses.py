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
is kept to few calls: each color's :class:`RowBlock` views are made once per batch, the
effective masses are folded into the Jacobians (``-m_eff J``: one matmul gives the
``-m_eff J V`` part of ``d_lambda``) and body velocities are gathered with one flat index.
About 27 calls per color and sweep (22 without the block normal solve, whose normal update
takes 12 calls instead of 7), 13 us at the least (the stacked matmuls cost ~50 ns per
manifold each): the solve's floor is colors x iterations, not the array sizes. The
accumulated impulses are kept with their own sign (``lambda >= 0``), as the formulas read;
a version that kept ``-lambda`` to save one negation per color and sweep had no measurable
gain and was reverted.

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
sweep is never worse than without it. Both candidates come from one stacked matmul
(``[-m_eff J; -B J] V``).

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
    BLOCK_FEASIBILITY_TOLERANCE,
    DEEP_OVERLAP,
    MAX_CORRECTION_SPEED,
    OVERLAP_BAUMGARTE,
    POSITION_BAUMGARTE,
    RESTITUTION_VELOCITY_THRESHOLD,
    TINY,
    SolverSettings,
)
from .contact_batch import SLOTS, ColorBlocks, ContactBatch, RowBlock, velocity_gather
from .stage_priority import stage_rows_last

#: the block solve's bound on ``d_lambda``: ``-lambda`` less the round-off tolerance
FEASIBLE_FLOOR = 1.0 + BLOCK_FEASIBILITY_TOLERANCE


def warm_start(batch: ContactBatch, velocity: np.ndarray) -> None:
    """Apply the cached impulses: ``V += W lambda`` for all rows (duplicates summed)."""
    lam_t = batch.impulse[:, :, 1:].reshape(len(batch.body_a), 2 * SLOTS)
    dv = (batch.normal_w @ batch.impulse[:, :, :1])[..., 0] + (batch.tangent_w @ lam_t[..., None])[
        ..., 0
    ]
    np.add.at(velocity, batch.body_a, dv[:, :6])
    np.add.at(velocity, batch.body_b, dv[:, 6:])


def _color_blocks(batch: ContactBatch, block_jacobi: bool) -> list[ColorBlocks]:
    """The colors of the batch as :class:`ColorBlocks`, made once and cached on the batch.

    Block Jacobi solves all slots of a color at once (one block, as many slots as the
    color's fullest manifold: the slots after it are empty in every manifold of the color);
    Gauss-Seidel over the slots makes one block per used slot, solved in slot order.
    """
    cached = batch.cache.jacobi_colors if block_jacobi else batch.cache.slot_colors
    if cached is None:
        scaled = (
            -batch.normal_mass[..., None] * batch.normal_jac,  # -m_n J_n, (m, S, 12)
            -batch.tangent_mass[..., None] * batch.tangent_jac,  # -m_t J_t, (m, 2S, 12)
            None if batch.normal_block is None else -batch.normal_block @ batch.normal_jac,
        )
        colors = []
        for color, (start, stop) in enumerate(batch.color_slices):
            s, used = slice(start, stop), batch.color_points[color]
            slots = [slice(0, used)] if block_jacobi else [slice(k, k + 1) for k in range(used)]
            colors.append(
                ColorBlocks(
                    velocity_gather(batch.pair_bodies[s]),
                    [_row_block(batch, scaled, s, rows) for rows in slots],
                )
            )
        if block_jacobi:
            batch.cache.jacobi_colors = colors
        else:
            batch.cache.slot_colors = colors
        cached = colors
    return cached


def _row_block(batch: ContactBatch, scaled, s: slice, rows: slice) -> RowBlock:
    """Views of the manifolds ``s``, point slots ``rows`` and their tangent rows;
    ``scaled`` holds the batch's ``-m_eff J`` of the normal and of the tangent rows and
    ``-B J`` of the block normal solve (None: no block solve)."""
    t_rows = slice(2 * rows.start, 2 * rows.stop)
    stacked = touching = None
    if scaled[2] is not None and batch.touching is not None:
        stacked = np.concatenate([scaled[0][s, rows], scaled[2][s, rows]], axis=1)
        touching = batch.touching[s, rows][..., None]
    return RowBlock(
        (s, rows),
        (s, t_rows),
        scaled[0][s, rows],
        batch.normal_jac[s, rows],
        batch.normal_w[s, :, rows],
        batch.normal_mass[s, rows][..., None],
        batch.friction[s][:, :, None],
        scaled[1][s, t_rows],
        batch.tangent_w[s, :, t_rows],
        stacked,
        touching,
    )


def _gather(flat_velocity, color):
    """Velocities ``(k, 12, 1)`` = [v_a, w_a, v_b, w_b] of the manifolds of one color.

    The bodies of one color are distinct (static ones excepted, whose rows of W are zero),
    so the color can be solved on this local copy and written back once (:func:`_scatter`).
    """
    return flat_velocity[color.gather]


def _scatter(flat_velocity, color, vab):
    flat_velocity[color.gather] = vab


def _normal_rows(block, vab, mass_bias, lam, accumulate):
    """One normal-impulse update of a block; updates ``vab (k, 12, 1)`` and the accumulated
    impulses ``lam (k, r, 1)`` in place; ``mass_bias (k, r, 1)`` is ``m_eff b``."""
    d_lambda = block.scaled_normal_jac @ vab  # -m_eff J V, (k, r, 1)
    d_lambda -= mass_bias  # d_lambda = -m_eff (J V + b)
    # clamp: the accumulated lam + d_lambda stays >= 0 (or each increment: box2d-lite)
    np.maximum(d_lambda, -lam if accumulate else 0.0, out=d_lambda)
    lam += d_lambda
    vab += block.normal_w @ d_lambda  # V += W d_lambda


def _block_normal_rows(block, vab, stacked_bias, lam):
    """The block normal solve of a block, or its mass-split Jacobi update where the block
    solution would make an accumulated impulse negative; updates ``vab`` and ``lam (k, r,
    1)`` in place. ``stacked_bias (k, 2r, 1)`` is ``[m_eff b; B b]`` (accumulated impulses
    only: the block solve clamps them).

    "Negative" allows round-off: a warm start that the block takes back whole (a body
    stopped last step and now free) lands on ``lambda + d_lambda = 0`` give or take a few
    ulps, so the test is ``d_lambda >= -(1 + BLOCK_FEASIBILITY_TOLERANCE) lambda`` and the
    accepted step is then clamped to ``lambda + d_lambda >= 0`` like the Jacobi one."""
    both = block.stacked_normal_jac @ vab  # [-m_eff J V; -B J V], (k, 2r, 1)
    both -= stacked_bias  # [-m_eff (J V + b); -B (J V + b)]
    rows = lam.shape[1]
    jacobi, exact = both[:, :rows], both[:, rows:]  # views
    floor = -lam  # d_lambda >= -lam keeps the accumulated lam + d_lambda >= 0
    feasible = (exact >= floor * FEASIBLE_FLOOR).all(axis=1, keepdims=True)  # (k, 1, 1)
    # the block's rows of non-touching slots are zero: they always take the Jacobi update
    d_lambda = np.where(feasible & block.touching, exact, jacobi)
    np.maximum(d_lambda, floor, out=d_lambda)
    lam += d_lambda
    vab += block.normal_w @ d_lambda  # V += W d_lambda


def _friction_rows(block, vab, lam_n, lam_t, accumulate):
    """Friction update of a block; ``lam_t (k, 2r, 1)`` holds (t1, t2) of each slot.

    The 2-D impulse of a slot is clamped to the Coulomb circle ``|lambda_t| <= mu lambda_n``.
    """
    new = block.scaled_tangent_jac @ vab  # d_lambda = -m_t J_t V
    if accumulate:
        new += lam_t
    t1, t2 = new[:, 0::2], new[:, 1::2]  # (k, r, 1) views
    scale = np.hypot(t1, t2)  # |lambda_t|
    np.maximum(scale, TINY, out=scale)
    np.divide(block.friction * lam_n, scale, out=scale)  # mu lambda_n / |lambda_t|
    np.minimum(scale, 1.0, out=scale)  # back onto the circle: the same scale for t1 and t2
    pairs = new.reshape(*scale.shape[:2], 2)  # (k, r, 2) view: (t1, t2) of each slot
    pairs *= scale  # scale (k, r, 1) multiplies t1 and t2 in one call
    if accumulate:
        new -= lam_t  # the increment
    lam_t += new
    vab += block.tangent_w @ new  # V += W_t d_lambda


def solve_velocities(
    batch: ContactBatch, velocity: np.ndarray, h: float, settings: SolverSettings
) -> None:
    """Velocity iterations (normal then friction per color), then the restitution pass.

    Reference: the loops of :func:`reference_solver.solve_reference`."""
    flat = velocity.reshape(-1)  # (n * 6,), a view when velocity is contiguous
    # speculative contacts: a gap g > 0 may close by g / h this step, b = g / h
    bias = (np.maximum(-batch.depth, 0.0) / h)[..., None]
    mass_bias = batch.normal_mass[..., None] * bias  # m_eff b
    lam_n = batch.impulse[..., :1].copy()  # (m, S, 1) accumulated normal impulses
    lam_t = batch.impulse[..., 1:].reshape(len(lam_n), 2 * SLOTS, 1)  # (m, 2S, 1) copy
    colors = _color_blocks(batch, settings.block_jacobi)
    stacked_bias = _stacked_bias(batch, bias, mass_bias)
    work = [
        [
            (
                block,
                mass_bias[block.normal_index],
                stacked_bias(block),
                lam_n[block.normal_index],
                lam_t[block.tangent_index],
            )
            for block in color.blocks
        ]
        for color in colors
    ]
    accumulate = settings.accumulate_impulses
    block_sweeps = settings.block_normal_sweeps if batch.normal_block is not None else 0
    for sweep in range(settings.velocity_iterations):
        for color, blocks in zip(colors, work, strict=True):
            vab = _gather(flat, color)
            for block, b, stacked, ln, lt in blocks:
                if sweep < block_sweeps:
                    _block_normal_rows(block, vab, stacked, ln)
                else:
                    _normal_rows(block, vab, b, ln, accumulate)
                _friction_rows(block, vab, ln, lt, accumulate)
            _scatter(flat, color, vab)
    _restitution(batch, flat, colors, lam_n)
    stage_rows_last(batch, flat, bias, settings)
    batch.impulse[..., :1] = lam_n
    batch.impulse[..., 1:] = lam_t.reshape(-1, SLOTS, 2)
    velocity[...] = flat.reshape(velocity.shape)  # no-op unless reshape had to copy


def _stacked_bias(batch: ContactBatch, bias: np.ndarray, mass_bias: np.ndarray):
    """Each block's bias term of the block normal solve, ``[m_eff b; B b] (k, 2r, 1)``
    (None for every block when the batch has no normal blocks)."""
    if batch.normal_block is None:
        return lambda block: None
    block_bias = batch.normal_block @ bias  # B b, (m, S, 1)

    def stacked(block: RowBlock) -> np.ndarray:
        index = block.normal_index
        return np.concatenate([mass_bias[index], block_bias[index]], axis=1)

    return stacked


def _restitution(batch, flat, colors, lam_n):
    """Bounce pass: target ``v_n = -e v_n0`` on the loaded, fast-approaching points."""
    fast = batch.approach_speed < -RESTITUTION_VELOCITY_THRESHOLD
    bounce = (batch.restitution > 0) & fast & (lam_n[..., 0] > 0)
    if not bounce.any():
        return
    # bias b = e v_n0 where bouncing (0 at the other points, which get no impulse)
    goal = np.where(bounce, batch.restitution * batch.approach_speed, 0.0)[..., None]
    active = bounce[..., None]
    # a color without a bouncing point would apply zero impulses: it is skipped (colors
    # are never empty, so reduceat over their starts gives one answer per color)
    bouncing = np.logical_or.reduceat(bounce.any(axis=1), [a for a, _ in batch.color_slices])
    for color, bounces in zip(colors, bouncing.tolist(), strict=True):
        if not bounces:
            continue
        vab = _gather(flat, color)
        for block in color.blocks:
            index = block.normal_index
            _restitution_rows(block, vab, active[index], goal[index], lam_n[index])
        _scatter(flat, color, vab)


def _restitution_rows(block, vab, active, goal, lam):
    """Rows where ``active``: ``d_lambda = -m_eff (v_n + e v_n0)`` (``goal`` holds
    ``e v_n0``), accumulated impulse clamped ``>= 0``; the others get no impulse."""
    vn = block.normal_jac @ vab
    d_lambda = np.where(active, -block.normal_mass * (vn + goal), 0.0)
    new = np.maximum(lam + d_lambda, 0.0)  # the accumulated lam + d_lambda >= 0
    d_lambda = new - lam  # the clamped increment
    lam[...] = new
    vab += block.normal_w @ d_lambda


def solve_positions(
    batch: ContactBatch, n_bodies: int, h: float, settings: SolverSettings
) -> np.ndarray:
    """Split-impulse pseudo velocities ``(n, 6)`` removing penetration beyond the slop.

    Reference: :func:`reference_solver.solve_positions_reference`."""
    pseudo = np.zeros((n_bodies, 6))
    if not settings.position_correction or settings.position_iterations == 0:
        return pseudo
    flat = pseudo.reshape(-1)
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
    bias = -target[..., None]  # b = -target: drive v_n towards +target
    mass_bias = batch.normal_mass[..., None] * bias  # m_eff b
    lam = np.zeros_like(bias)  # accumulated pseudo impulses
    colors = _color_blocks(batch, settings.block_jacobi)
    work = [
        [(block, mass_bias[block.normal_index], lam[block.normal_index]) for block in c.blocks]
        for c in colors
    ]
    for _ in range(iterations):
        for color, blocks in zip(colors, work, strict=True):
            vab = _gather(flat, color)
            for block, b, block_lam in blocks:
                _normal_rows(block, vab, b, block_lam, True)
            _scatter(flat, color, vab)
    stage_rows_last(batch, flat, bias, settings)
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
