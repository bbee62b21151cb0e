"""Stage priority: push-only sweeps that end the contact solver's velocity and
position solves.

The stage always wins (``SolverSettings.stage_iterations``): push-only sweeps of one lumped
normal row per manifold (:func:`lumped_rows`) over the *stage rows* (manifolds with a body
the solver does not move: the stage, static and kinematic bodies), then over the dynamic
pairs with the body nearer the stage held fixed (:func:`shock_rows`), end both the
velocity and the position solve. Gauss-Seidel with a
mass ratio of 1000 converges far too slowly for a light box under a heavy one to be held
up by the floor; the last word of the stage rows guarantees the light box does not move
into the floor this step (it may be squeezed into the heavy box instead, which is
harmless). Bullet has no such rule (its light bodies sink); Box2D v3 keeps the contacts of
a dynamic and a static body in its last graph colors (``B2_DYNAMIC_COLOR_COUNT`` = colors
- 4) so every iteration solves them after the dynamic pairs, "to reduce tunneling due to
push through" (we also put the stage rows last in each color); Jolt relies on iterations
and contact callbacks that scale masses; Guendelman et al.'s shock propagation freezes the
bodies below, a stronger form of the same priority.

:mod:`solver` calls :func:`stage_rows_last`; the reference is
:func:`reference_solver.stage_rows_last`.
"""

from __future__ import annotations

import numpy as np

from ..core.settings import SolverSettings
from .contact_batch import ContactBatch, batch_gathers
from .lumped_rows import LumpedRows


def stage_rows_last(batch, flat, bias, settings: SolverSettings) -> None:
    """The stage wins: ``stage_iterations`` lumped sweeps over the stage rows, then as many
    over the dynamic pairs with the lower body held fixed (:func:`shock_rows`).

    Reference: :func:`reference_solver.stage_rows_last`."""
    sweeps = _stage_blocks(batch)
    _lumped_sweeps(sweeps, lumped_rows(batch, bias), flat, settings.stage_iterations)
    shock = shock_rows(batch)
    if shock is not None:
        sweeps = _sweep_blocks(batch, "shock", batch.color_slices, shock)
        _lumped_sweeps(sweeps, shock.with_bias(bias), flat, settings.stage_iterations)


def lumped_rows(batch: ContactBatch, bias: np.ndarray) -> LumpedRows:
    """Each manifold's points lumped into one normal row: ``J = mean_i J_i``, ``W = mean_i
    W_i``, ``m_eff = 1 / (J W^T)``, bias = the mean of its points' biases; rows without an
    active point get ``m_eff = 0`` (made once per batch and cached).

    One row per manifold cannot explode the way a clamped block solve of nearly dependent
    rows can, and it removes a uniform approach in one sweep (mass splitting removes a
    quarter of a box's per sweep).
    """
    return _lumped(batch).with_bias(bias)


def _lumped(batch: ContactBatch) -> LumpedRows:
    """The lumped rows without bias, made once per batch and cached."""
    if batch.cache.lumped is None:
        active = batch.mask & (batch.normal_mass > 0)
        batch.cache.lumped = LumpedRows.of(batch.normal_jac, batch.normal_w, active)
    return batch.cache.lumped


def shock_rows(batch: ContactBatch) -> LumpedRows | None:
    """The lumped rows of the shock pass (Guendelman et al. 2003, "shock propagation"),
    made once and cached: in each dynamic pair the body nearer the stage (``lower``) gets
    infinite mass (its half of ``W`` is zeroed); the other rows get ``m_eff = 0``. None when
    no pair has a lower body."""
    if not batch.cache.shock_ready:
        shock = None
        lower = batch.lower
        if lower is not None and bool(np.any(lower)):
            # mean_i (W_i with the lower body's 6 entries zeroed) = (mean_i W_i) zeroed there
            lumped = _lumped(batch)
            keep = np.repeat(~lower, 6, axis=1)  # (m, 12)
            points = (batch.mask & (batch.normal_mass > 0)).any(axis=1)
            active = np.any(lower, axis=1) & points
            shock = LumpedRows.with_mobility(
                lumped.jac[:, 0], lumped.w[:, :, 0] * keep, active, lumped.weight
            )
        batch.cache.shock, batch.cache.shock_ready = shock, True
    return batch.cache.shock


def _stage_blocks(batch: ContactBatch) -> list[tuple]:
    """The sweep blocks of the stage rows (the last rows of each color): one block of all
    of them when no body the sweep moves is in two of them (the usual case: one manifold
    with the stage per body), since then the colors' order changes no number; otherwise one
    block per color, in color order (Gauss-Seidel). Made once per batch."""
    if "stage" not in batch.cache.sweeps:
        rows = _lumped(batch)
        ranges = [
            (start, stop)
            for (_, stop), start in zip(batch.color_slices, batch.priority_starts, strict=True)
        ]
        index = np.concatenate([np.arange(start, stop) for start, stop in ranges])
        # the bodies each stage row moves: those whose half of W is not zero
        moves = rows.w[index, :, 0].reshape(-1, 2, 6).any(axis=2)  # (k, 2)
        moved = batch.pair_bodies[index][moves]
        if len(index) and len(np.unique(moved)) == len(moved):
            gather = batch_gathers(batch)[index]
            block = (index, gather, rows.scaled_jac[index], rows.w[index])
            batch.cache.sweeps["stage"] = [block]
        else:
            _sweep_blocks(batch, "stage", ranges, rows)
    return batch.cache.sweeps["stage"]


def _sweep_blocks(batch, key: str, ranges, rows: LumpedRows) -> list[tuple]:
    """Per non-empty manifold range ``(start, stop)`` (one per color): ``(s, gather, -m_eff
    J, W)``, the slice (an index array for :func:`_stage_blocks`' single block), the flat
    velocity indices of its bodies and the views of its ``rows``; made once per batch and
    kept in ``batch.cache.sweeps[key]``, since the velocity and the position solve sweep
    the same rows (only their biases differ)."""
    if key not in batch.cache.sweeps:
        blocks = []
        gathers = batch_gathers(batch)
        for start, stop in ranges:
            if start == stop:
                continue
            s = slice(start, stop)
            gather = gathers[s]
            blocks.append((s, gather, rows.scaled_jac[s], rows.w[s]))
        batch.cache.sweeps[key] = blocks
    return batch.cache.sweeps[key]


def _lumped_sweeps(blocks: list[tuple], rows: LumpedRows, flat, iterations: int) -> None:
    """``iterations`` push-only sweeps of the lumped rows ``blocks`` (:func:`_sweep_blocks`)
    with the biases of ``rows``: ``d_lambda = max(-m_eff (J V + b), 0)``, ``V += W
    d_lambda`` (impulses are only added, so a bounce solved before is kept)."""
    mass_bias = rows.mass_bias if rows.mass_bias is not None else np.zeros((len(rows.jac), 1, 1))
    work = [(gather, j, w, mass_bias[s]) for s, gather, j, w in blocks]
    for _ in range(iterations):
        for gather, j, w, b in work:
            vab = flat[gather]
            step = np.maximum(j @ vab + b, 0.0)  # (k, 1, 1)
            vab += w @ step
            flat[gather] = vab
