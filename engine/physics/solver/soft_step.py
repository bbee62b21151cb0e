"""The soft step: Box2D v3's solver schedule (soft contacts, substeps, relax sweeps).

Erin Catto's "Solver2D" comparison and Box2D v3 (``solver.c``, ``contact_solver.c``)
replace many rigid velocity sweeps plus a position solve by a few *substeps*, each::

    v += (h / n) (g + F / m)              the forces' share (here: 1/n of the step's)
    warm start                             apply the accumulated impulses (each substep)
    soft sweep (normal rows, with bias)    push-out of overlaps as a damped spring
    x += (h / n) v                         the bodies' displacement d
    relax sweeps (normal + friction rows)  the same rows without the push-out bias

and after the substeps the restitution pass. ``SolverSettings.soft_step`` selects it;
the contacts, manifolds and colors are the step's (no collision detection per substep).

**Separation.** A point's separation follows the bodies' displacement within the step,
linearized: ``s = s_0 + J_n d`` (``s_0 = -depth``, ``d = [d_a, dtheta_a, d_b, dtheta_b]``
the accumulated linear and angular displacements), Box2D's ``baseSeparation + dot(ds,
normal)``. It is computed for every manifold once per sweep (one gather, one stacked
matmul), since the positions only move between the sweeps.

**Soft rows** (``b2MakeSoft``): with ``omega = 2 pi f`` (f ``contact_hertz``, twice it for
a contact with the stage, at most an eighth of the substep rate), ``zeta`` the damping
ratio and ``h`` the substep, ``a_1 = 2 zeta + h omega``, ``a_2 = h omega a_1``::

    bias rate = omega / a_1,  mass scale = a_2 / (1 + a_2),  impulse scale = 1 / (1 + a_2)

A point with ``s > 0`` (beyond ``SOFT_SPECULATIVE_TOLERANCE``, so round-off never picks
the row) is speculative, bias ``s / h``, mass scale 1, impulse scale 0 (in both sweeps).
An overlapping point (``s <= 0``) gets in the soft sweep the bias ``max(mass scale x rate
x s, -contact_push_speed)`` and the increment ``d_lambda = -m_n (mass scale J v + bias) -
impulse scale lambda``; in the relax sweep no bias (rigid).
Friction rows are solved in the relax sweeps only (as Box2D v3 does),
``relax_iterations`` of them per substep (Box2D v3's ``RELAX_ITERATIONS``, 1). The first
``block_normal_sweeps`` relax sweeps solve each manifold's touching normal rows as one
block where its impulses stay non-negative (:mod:`color_rows`, the rigid solve's block
sweep): one Jacobi sweep of mass-split rows removes only part of a face's common error,
and the cubes of a pile resting that way never fell asleep (measured: apartment-30).
Each soft sweep is :func:`color_rows.normal_update` with the matrix ``[m_n mass scale J |
m_n bias]`` and the impulse scales, 9 NumPy calls per color; each relax sweep the
velocity update of :mod:`color_rows` (17 calls, 23 as a block sweep) with the relax bias
in its matrix.

**Stage priority** (:mod:`stage_priority`): its push-only pass ends every soft sweep (the
displacement then never takes a body into the stage) with the soft biases, and the
step (after restitution) with the relax biases.

**Impulses and positions.** The accumulated impulses are per substep inside the loop
(Box2D's), per step outside it (``ContactBatch.impulse`` and the manifolds hold ``n`` times
the last substep's, so warm starting, the contact forces and rolling friction read what
they read after the rigid solve). The bodies in contact end at their displacement ``d``:
the solve returns ``d / h - v`` as the step's pseudo velocity, which the integrate stage
adds to ``v`` as it does the split impulses'. Bodies in no contact keep the plain
integrator (their free flight does not depend on another body's contacts).

The plain twin, one point at a time, is :func:`reference_soft.solve_soft_reference`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.settings import SOFT_SPECULATIVE_TOLERANCE, SolverSettings
from .color_rows import (
    COLUMN,
    ColorRows,
    color_rows,
    impulses,
    new_impulses,
    normal_update,
    row_matrices,
    rows_matrix,
    store_tangents,
    velocity_update,
    with_constant,
)
from .contact_batch import ContactBatch, batch_gathers
from .sequential_impulses import _restitution, warm_start, with_one
from .stage_priority import stage_rows_last


@dataclass
class Softness:
    """Box2D v3's ``b2Softness`` of one contact stiffness: ``bias_rate`` 1/s,
    ``mass_scale`` and ``impulse_scale`` (1)."""

    bias_rate: float
    mass_scale: float
    impulse_scale: float


def softness(hertz: float, damping_ratio: float, h: float) -> Softness:
    """``b2MakeSoft``: the soft row of a damped spring of ``hertz`` and ``damping_ratio``
    over a substep ``h`` (module docstring); ``hertz = 0``: a rigid row without bias."""
    if hertz == 0.0:
        return Softness(0.0, 1.0, 0.0)
    omega = 2.0 * math.pi * hertz
    a1 = 2.0 * damping_ratio + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return Softness(omega / a1, a2 * a3, a3)


def contact_softness(settings: SolverSettings, h: float) -> tuple[Softness, Softness]:
    """``(between moving bodies, with the stage)`` for the substep ``h``: the contact
    hertz at most an eighth of the substep rate, twice it with the stage (Box2D v3's
    ``contactSoftness`` and ``staticSoftness``)."""
    check_soft_settings(settings)
    hertz = min(settings.contact_hertz, 0.125 / h)
    zeta = settings.contact_damping_ratio
    return softness(hertz, zeta, h), softness(2.0 * hertz, zeta, h)


def check_soft_settings(settings: SolverSettings) -> None:
    """Raise ``ValueError`` naming the first soft-step setting out of its range."""
    for name in ("soft_substeps", "relax_iterations"):
        value = getattr(settings, name)
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ValueError(f"{name} must be an int >= 1, got {value!r}")
    for name in ("contact_hertz", "contact_damping_ratio", "contact_push_speed"):
        value = float(getattr(settings, name))
        if not (math.isfinite(value) and value >= 0.0):
            raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
    if not settings.accumulate_impulses:
        raise ValueError("soft_step needs accumulate_impulses=True (its rows scale lambda)")


@dataclass
class SoftRows:
    """What one step's soft sweeps write once per sweep and read per color: the soft
    matrix ``soft (m, S, 13)`` and impulse scales ``relaxation (S, m)`` (quantity-major),
    each color's ``(rows, soft rows, relaxation rows)`` views, and the per-manifold
    stiffness of its kind (stage or not): ``rate, mass_scale, impulse_scale (m, 1)``."""

    soft: np.ndarray
    relaxation: np.ndarray
    colors: list[list[tuple[ColorRows, np.ndarray, np.ndarray]]]
    rate: np.ndarray
    mass_scale: np.ndarray
    impulse_scale: np.ndarray


def stage_manifolds(batch: ContactBatch) -> np.ndarray:
    """``(m,)`` bool: the stage rows (a body the solver does not move), the end of each
    color from its ``priority_starts`` entry."""
    stage = np.zeros(len(batch.body_a), dtype=bool)
    for (_, stop), first in zip(batch.color_slices, batch.priority_starts, strict=True):
        stage[first:stop] = True
    return stage


def soft_rows(batch, colors: list[list[ColorRows]], settings, h: float) -> SoftRows:
    """The :class:`SoftRows` of a batch for the substep ``h``."""
    moving, stage = contact_softness(settings, h)
    kind = stage_manifolds(batch)[:, None]
    m = len(kind)
    soft = np.zeros((m, batch.normal_mass.shape[1], COLUMN))
    relaxation = np.zeros((soft.shape[1], m))
    views = [
        [(rows, rows_matrix(rows, soft), relaxation[rows.slots, rows.manifolds]) for rows in color]
        for color in colors
    ]
    return SoftRows(
        soft,
        relaxation,
        views,
        np.where(kind, stage.bias_rate, moving.bias_rate),
        np.where(kind, stage.mass_scale, moving.mass_scale),
        np.where(kind, stage.impulse_scale, moving.impulse_scale),
    )


def separations(batch: ContactBatch, displacement: np.ndarray) -> np.ndarray:
    """``(m, S)`` m: ``s = -depth + J_n d`` of every point for the accumulated
    displacements ``displacement (6 n,)`` (linearized; Box2D's current separation)."""
    moved = displacement[batch_gathers(batch)]  # (m, 12, 1)
    return (batch.normal_jac @ moved)[..., 0] - batch.depth


def set_soft_rows(rows: SoftRows, batch, s: np.ndarray, h: float, push: float) -> np.ndarray:
    """Write the soft sweep's matrix and impulse scales for the separations ``s (m, S)``;
    returns the velocity biases ``(m, S)`` (speculative ``s / h``, else the soft push)."""
    speculative = s > SOFT_SPECULATIVE_TOLERANCE
    bias = np.where(
        speculative, s / h, np.maximum(rows.mass_scale * rows.rate * s, -push)
    )  # (m, S)
    scale = np.where(speculative, batch.normal_mass, batch.normal_mass * rows.mass_scale)
    np.multiply(batch.normal_jac, scale[..., None], out=rows.soft[:, :, :12])
    np.multiply(batch.normal_mass, bias, out=rows.soft[:, :, 12])
    rows.relaxation[...] = np.where(speculative, 0.0, rows.impulse_scale).T
    return bias


def solve_soft(
    batch: ContactBatch, velocity: np.ndarray, forces: np.ndarray, h: float, settings
) -> np.ndarray:
    """The soft step (module docstring) on ``velocity (n, 6)`` (updated), which holds the
    step's force increments ``forces (n, 6)`` already; returns the pseudo velocities
    ``(n, 6)`` that take the bodies in contact to their substepped displacement.

    Reference: :func:`reference_soft.solve_soft_reference`."""
    check_soft_settings(settings)
    substeps, relaxes = int(settings.soft_substeps), int(settings.relax_iterations)
    hs = h / substeps
    batch.impulse /= substeps  # per substep inside the loop
    flat = with_one(velocity - forces)  # the start velocities, then the constant 1
    share = forces.reshape(-1) / substeps
    state = new_impulses(batch.impulse)
    # the relax sweeps' matrix: m_n [J_n | b], its bias column set per sweep
    matrices = row_matrices(batch, np.zeros((*batch.depth.shape, 1)), True)
    gathers = with_constant(batch_gathers(batch), len(flat) - 1)
    slices = [slice(a, b) for a, b in batch.color_slices]
    color_slots = list(zip(slices, batch.color_points, strict=True))
    colors = color_rows(state, matrices, gathers, color_slots, settings.block_jacobi)
    rows = soft_rows(batch, colors, settings, hs)
    displacement = np.zeros(len(flat) - 1)
    bodies_velocity = flat[:-1].reshape(velocity.shape)
    relax_bias = np.zeros((*batch.depth.shape, 1))
    with np.errstate(divide="ignore", invalid="ignore"):  # the friction circle's 0 / 0
        for sub in range(substeps):
            flat[:-1] += share
            warm = settings.warm_starting
            _warm_start(batch, bodies_velocity, colors, state, sub * relaxes, warm)
            s = separations(batch, displacement)
            bias = set_soft_rows(rows, batch, s, hs, settings.contact_push_speed)
            for soft_color in rows.colors:
                for one, soft, relaxation in soft_color:
                    normal_update(one, flat, soft, one.lam_n, relaxation)
            stage_rows_last(batch, flat[:-1], bias[..., None], settings)
            displacement += hs * flat[:-1]
            relax_bias[..., 0] = np.maximum(separations(batch, displacement), 0.0) / hs
            np.multiply(batch.normal_mass, relax_bias[..., 0], out=matrices.normal[:, :, 12])
            if matrices.block is not None and batch.normal_block is not None:
                matrices.block[:, :, 12:] = batch.normal_block @ relax_bias  # B b
            for sweep in range(sub * relaxes, (sub + 1) * relaxes):
                block = sweep < settings.block_normal_sweeps and matrices.block is not None
                for color in colors:
                    for one in color:
                        velocity_update(one, flat, True, block, sweep)
    store_tangents(colors, state, substeps * relaxes)
    _restitution(batch, flat, colors, state[0])
    stage_rows_last(batch, flat[:-1], relax_bias, settings)
    batch.impulse[...] = impulses(state) * substeps
    velocity[...] = bodies_velocity
    pseudo = np.zeros_like(velocity)
    touched = np.unique(batch.pair_bodies)
    pseudo[touched] = displacement.reshape(velocity.shape)[touched] / h - velocity[touched]
    return pseudo


def _warm_start(batch, velocity, colors, state, sweeps: int, warm: bool) -> None:
    """Apply the accumulated impulses at the start of a substep, after ``sweeps`` relax
    sweeps (Box2D v3 warm starts every substep); without warm starting each substep
    starts from zero."""
    if not warm:
        state[...] = 0.0
        for color in colors:
            for rows in color:
                rows.tangents[sweeps % 2].lam[...] = 0.0
        return
    if sweeps:  # the friction impulses of the relax sweeps so far, then the (m, S, 3) form
        store_tangents(colors, state, sweeps)
        batch.impulse[...] = impulses(state)
    warm_start(batch, velocity)
