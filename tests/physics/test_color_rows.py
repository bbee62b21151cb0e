"""The fused color update (``solver/color_rows.py``) against the equations it folds together.

One sweep of :func:`fused_update` over a color must give the impulses and velocities of the
plain sequential-impulse steps written one manifold and one row at a time (Catto 2005): the
normal rows with the accumulated impulse clamped ``>= 0`` and the velocities updated, then
the friction rows reading those velocities, clamped to the Coulomb circle. The whole-step
agreement of the batched and the plain solver is ``tests/physics/test_reference_path.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

from engine.physics.core.settings import SolverSettings
from engine.physics.solver import color_rows
from engine.physics.solver.contact_batch import (
    ColorOrder,
    ManifoldPoints,
    PairCoefficients,
    SolverBodies,
    build_batch,
)
from engine.physics.solver.sequential_impulses import _solver_rows


def random_batch(seed: int, counts=(4, 3, 2)):
    """Manifolds (static 0, body 1), (body 1, body 2), (static 0, body 3), one color each
    but the last two (bodies 2 and 3 are distinct), random points, normals, velocities,
    masses, inertias and cached impulses."""
    rng = np.random.default_rng(seed)
    m = len(counts)
    normal = rng.normal(size=(m, 3))
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    normals = np.repeat(normal[:, None], 4, axis=1)
    points_a = rng.normal(scale=0.1, size=(m, 4, 3))
    points_b = points_a - 0.01 * rng.random((m, 4, 1)) * normals
    inertia = np.zeros((4, 3, 3))
    for k in range(1, 4):
        a = rng.normal(size=(3, 3))
        inertia[k] = np.linalg.inv(a @ a.T + np.eye(3))
    impulse = rng.random((m, 4, 3)) * [1.0, 0.2, 0.2]
    batch = build_batch(
        ManifoldPoints(
            points_a,
            points_b,
            normals,
            np.array(counts),
            np.array([0, 1, 0]),
            np.array([1, 2, 3]),
        ),
        SolverBodies(
            rng.normal(scale=0.2, size=(4, 3)),
            np.array([0.0, 1.0, 0.5, 2.0]),
            inertia,
            rng.normal(size=(4, 6)),
        ),
        PairCoefficients(np.array([0.5, 0.8, 0.3]), np.zeros(m), impulse),
        ColorOrder([(0, 1), (1, 3)]),
        split_mass=True,
    )
    velocity = rng.normal(size=(4, 6))
    velocity[0] = 0.0
    return batch, velocity


def plain_sweep(batch, velocity, bias, block_jacobi: bool):
    """The impulses ``(m, S, 3)`` and velocities after one sweep, one manifold at a time."""
    lam = batch.impulse.copy()
    v = velocity.copy()
    for k in range(len(batch.body_a)):
        a, b = batch.body_a[k], batch.body_b[k]
        groups = [range(4)] if block_jacobi else [[slot] for slot in range(4)]
        for group in groups:
            vab = np.concatenate([v[a], v[b]])
            steps = []
            for slot in group:  # normal rows: read the velocities before the group
                d = -batch.normal_mass[k, slot] * (batch.normal_jac[k, slot] @ vab + bias[k, slot])
                new = max(lam[k, slot, 0] + d, 0.0)
                steps.append(new - lam[k, slot, 0])
                lam[k, slot, 0] = new
            for slot, step in zip(group, steps, strict=True):
                vab = vab + batch.normal_w[k, :, slot] * step
            steps = []
            for slot in group:  # friction rows: read the velocities after the normal rows
                rows = [2 * slot, 2 * slot + 1]
                new = lam[k, slot, 1:] - batch.tangent_mass[k, rows] * (
                    batch.tangent_jac[k, rows] @ vab
                )
                limit = batch.friction[k, 0] * lam[k, slot, 0]
                length = np.hypot(*new)
                if length > limit:
                    new = new * limit / length
                steps.append((rows, new - lam[k, slot, 1:]))
                lam[k, slot, 1:] = new
            for rows, step in steps:
                vab = vab + batch.tangent_w[k][:, rows] @ step
            v[a], v[b] = (vab[:6], vab[6:]) if a != 0 else (v[a], vab[6:])
    return lam, v


@pytest.mark.parametrize("block_jacobi", [True, False])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_one_fused_sweep_equals_the_normal_then_friction_rows(seed, block_jacobi):
    batch, velocity = random_batch(seed)
    bias = np.random.default_rng(seed + 10).random((3, 4, 1)) * 0.1
    settings = SolverSettings(block_jacobi=block_jacobi, block_normal_sweeps=0)
    expected_lam, expected_v = plain_sweep(batch, velocity, bias[..., 0], block_jacobi)
    work, _, colors = _solver_rows(batch, bias, settings)
    flat = velocity.copy().reshape(-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        for color in colors:
            for rows in color:
                color_rows.fused_update(rows, flat, True, False)
    np.testing.assert_allclose(color_rows.impulses(work), expected_lam, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(flat.reshape(4, 6), expected_v, rtol=1e-12, atol=1e-12)
    assert np.any(expected_lam[..., 0] == 0.0)  # some normal rows clamped
    assert np.any(np.hypot(expected_lam[..., 1], expected_lam[..., 2]) > 0)


def test_the_row_views_write_into_the_work_array():
    batch, _ = random_batch(0)
    work, _, colors = _solver_rows(batch, np.zeros((3, 4, 1)), SolverSettings())
    for color in colors:
        for rows in color:
            for view in (rows.v, rows.lam, rows.primed_n, rows.friction_out, rows.pairs):
                assert np.shares_memory(view, work)
            assert np.shares_memory(rows.pairs, rows.friction_out)


def test_impulses_round_trip_through_the_work_array():
    impulse = np.random.default_rng(4).random((5, 4, 3))
    work = color_rows.new_work(impulse)
    np.testing.assert_array_equal(color_rows.impulses(work), impulse)
    assert np.all(work[:, color_rows.ONE] == 1.0)
