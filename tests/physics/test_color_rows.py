"""The slim color update (``solver/color_rows.py``) against the rows written one at a time.

One sweep of :func:`velocity_update` over a color must give the impulses and velocities of the
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
from engine.physics.solver.sequential_impulses import _solver_rows, with_one


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
def test_one_slim_sweep_equals_the_normal_then_friction_rows(seed, block_jacobi):
    batch, velocity = random_batch(seed)
    bias = np.random.default_rng(seed + 10).random((3, 4, 1)) * 0.1
    settings = SolverSettings(block_jacobi=block_jacobi, block_normal_sweeps=0)
    expected_lam, expected_v = plain_sweep(batch, velocity, bias[..., 0], block_jacobi)
    flat = with_one(velocity)
    state, _, colors = _solver_rows(batch, bias, settings, len(flat) - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        for color in colors:
            for rows in color:
                color_rows.velocity_update(rows, flat, True, False, 0)
    color_rows.store_tangents(colors, state, 1)
    np.testing.assert_allclose(color_rows.impulses(state), expected_lam, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(flat[:-1].reshape(4, 6), expected_v, rtol=1e-12, atol=1e-12)
    assert flat[-1] == 1.0  # the velocity columns' constant is never changed
    assert np.any(expected_lam[..., 0] == 0.0)  # some normal rows clamped
    assert np.any(np.hypot(expected_lam[..., 1], expected_lam[..., 2]) > 0)


def test_the_row_views_write_into_the_impulses_and_the_scratch():
    batch, velocity = random_batch(0)
    flat = with_one(velocity)
    state, _, colors = _solver_rows(batch, np.zeros((3, 4, 1)), SolverSettings(), len(flat) - 1)
    for color in colors:
        for rows in color:
            assert np.shares_memory(rows.lam_n, state)
            assert np.shares_memory(rows.q, rows.q_col) and np.shares_memory(rows.dt, rows.dt_col)
            first, second = rows.tangents
            assert not np.shares_memory(first.lam, second.lam)
            for tangent in rows.tangents:
                for view in (tangent.t1, tangent.t2, tangent.col):
                    assert np.shares_memory(view, tangent.lam)
            # the first sweep reads the cached friction impulses
            np.testing.assert_array_equal(first.lam, state[1:, rows.slots, rows.manifolds])


def test_impulses_round_trip_through_the_quantity_major_state():
    impulse = np.random.default_rng(4).random((5, 4, 3))
    state = color_rows.new_impulses(impulse)
    assert state.shape == (3, 4, 5) and state.flags.c_contiguous
    np.testing.assert_array_equal(color_rows.impulses(state), impulse)
