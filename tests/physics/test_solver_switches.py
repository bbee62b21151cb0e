"""Every ``SolverSettings`` switch does what it exists for (box2d-lite's demo toggles).

Each test turns one idea off (or down) and checks the physical symptom the idea prevents:
a stack that cannot rest, a box left inside the floor, a stack that leans. ``use_vectorized``
is covered by tests/physics/test_reference_path.py.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

from engine.physics.core.settings import SolverSettings
from engine.physics.solver.color_rows import LAMBDA_N
from engine.physics.solver.contact_batch import (
    ColorOrder,
    ManifoldPoints,
    PairCoefficients,
    SolverBodies,
    build_batch,
)
from engine.physics.solver.sequential_impulses import _restitution, _solver_rows

BOX_HALF = 0.1


def stack(n_boxes: int = 6, seconds: float = 1.5, **settings):
    """A stack of ``n_boxes`` 20 cm boxes, exactly aligned, after ``seconds``; returns the
    boxes and the largest |v_y| seen after the first 0.5 s."""
    world, templates = make_world()
    for name, value in settings.items():
        setattr(world.settings, name, value)
    handle = register_primitive(templates, "cubeSolid", (BOX_HALF,) * 3)
    boxes = [
        add(world, templates, handle, [0.0, BOX_HALF + 2 * BOX_HALF * i, 0.0])
        for i in range(n_boxes)
    ]
    run(world, 0.5)
    largest_vy = 0.0
    for _ in range(int(round((seconds - 0.5) * 60))):
        world.step_physics(1.0 / 60.0)
        largest_vy = max(largest_vy, max(abs(box.linear_velocity[1]) for box in boxes))
    return boxes, largest_vy


def top_height(boxes) -> float:
    return float(boxes[-1].translation[1])


RESTING_TOP = BOX_HALF + 2 * BOX_HALF * 5  # center of the 6th box when nothing sinks


def test_default_stack_rests_and_sleeps():
    boxes, largest_vy = stack()
    assert abs(top_height(boxes) - RESTING_TOP) < 0.01  # 1 cm for six contacts' slop
    assert largest_vy < 0.01 and not any(box.awake for box in boxes)


def test_without_accumulated_impulses_a_stack_cannot_rest():
    # clamping each increment (>= 0) instead of the accumulated impulse means an impulse
    # can only grow within a step: an overshoot (or a warm-started impulse grown too large)
    # can never be taken back, so the stack is pushed apart and falls back, over and over
    boxes, largest_vy = stack()
    assert largest_vy < 0.01
    boxes, largest_vy = stack(accumulate_impulses=False)
    assert largest_vy > 0.1
    assert any(box.awake for box in boxes)


def test_without_warm_starting_a_stack_sags_and_shakes():
    # 15 iterations from zero impulses cannot carry six boxes' weight down the stack in one
    # step: every step the stack sinks a little and is pushed back (warm starting carries
    # last step's impulses over, so a resting stack starts each step already solved)
    warm, warm_vy = stack()
    cold, cold_vy = stack(warm_starting=False)
    assert cold_vy > 0.01 > 100 * warm_vy
    assert top_height(cold) < top_height(warm) - 0.002


def sag(**settings) -> float:
    """How far a six-box stack without the stage's last word sinks in 1 s, m."""
    boxes, _ = stack(seconds=1.0, stage_iterations=0, **settings)
    return RESTING_TOP - top_height(boxes)


def test_more_velocity_iterations_and_substeps_make_a_stiffer_stack():
    # the mass-split Jacobi rows alone (no block normal solve), without the stage's last
    # word: 2 iterations let the stack sink into itself; substeps give the solver more
    # passes per frame
    soft = sag(velocity_iterations=2, block_normal_sweeps=0)
    assert soft > 0.02
    assert sag(velocity_iterations=2, substeps=4, block_normal_sweeps=0) < 0.25 * soft
    assert sag(block_normal_sweeps=0) < 0.01


def test_block_normal_solve_makes_a_stiffer_stack():
    # mass splitting carries only a quarter of a face's common load error per sweep; the
    # block solve of the four rows carries all of it. One block sweep a step (the default)
    # at 2 iterations: the stack sinks a third of what the Jacobi rows let it (measured
    # 10 mm against 32 mm); block solves in every sweep stiffen it further
    jacobi = sag(velocity_iterations=2, block_normal_sweeps=0)
    assert sag(velocity_iterations=2) < 0.5 * jacobi
    assert sag(velocity_iterations=2, block_normal_sweeps=2) < 0.25 * jacobi  # 5 mm
    assert sag(block_normal_sweeps=10) < 0.002  # 0.8 mm (7.5 mm with Jacobi rows only)


def test_stage_iterations_hold_up_a_stack_the_iterations_cannot():
    # the stage rows get the last word: even with 2 iterations of the Jacobi rows the floor
    # holds the stack
    held, _ = stack(seconds=1.0, velocity_iterations=2, block_normal_sweeps=0)
    sunk, _ = stack(seconds=1.0, velocity_iterations=2, stage_iterations=0, block_normal_sweeps=0)
    assert RESTING_TOP - top_height(held) < 0.01
    assert RESTING_TOP - top_height(sunk) > 0.02


def box_started_in_floor(**settings) -> float:
    """Height of a 20 cm box placed 3 cm into the floor, after 1 s."""
    world, templates = make_world()
    for name, value in settings.items():
        setattr(world.settings, name, value)
    box = add(
        world,
        templates,
        register_primitive(templates, "cubeSolid", (BOX_HALF,) * 3),
        [0.0, BOX_HALF - 0.03, 0.0],
    )
    run(world, 1.0)
    return float(box.translation[1])


def test_position_correction_pushes_a_sunken_box_out_and_only_it_does():
    assert box_started_in_floor() > BOX_HALF - 0.006  # out to within the slop (4 mm)
    # without the split-impulse solve nothing removes the overlap: it stays 3 cm deep
    np.testing.assert_allclose(
        box_started_in_floor(position_correction=False), BOX_HALF - 0.03, atol=0.001
    )
    np.testing.assert_allclose(
        box_started_in_floor(position_iterations=0), BOX_HALF - 0.03, atol=0.001
    )


def test_block_jacobi_keeps_a_perfect_stack_perfect():
    # the 4 corners solved together are symmetric; one slot after the other (Gauss-Seidel)
    # favours the first corner and the stack starts to lean
    def lean(block_jacobi: bool) -> float:
        boxes, _ = stack(10, seconds=3.0, block_jacobi=block_jacobi)
        return max(float(np.hypot(b.translation[0], b.translation[2])) for b in boxes)

    assert lean(True) < 1e-9
    assert lean(False) > 1e-3


def test_restitution_pass_never_pulls_a_point_already_separating_faster_than_its_bounce():
    """One contact row, a 1 kg body B above a static A (normal +y, anchors at the centers):
    B approached at 2 m/s, already separates at 3 m/s, its bounce target is only e |v_n0| =
    0.5 * 2 = 1 m/s, and the row holds 0.5 N s. The pass may take back at most those 0.5 N s
    (the accumulated impulse stays >= 0: a contact pushes, never pulls), leaving 2.5 m/s."""
    start = np.zeros((2, 6))
    start[1, 1] = -2.0  # v_n0 = -2 m/s
    impulse = np.zeros((1, 4, 3))
    impulse[0, 0, 0] = 0.5
    up = np.tile([0.0, 1.0, 0.0], (1, 4, 1))
    batch = build_batch(
        ManifoldPoints(np.zeros((1, 4, 3)), np.zeros((1, 4, 3)), up, np.array([1]), *[[0], [1]]),
        SolverBodies(np.zeros((2, 3)), np.array([0.0, 1.0]), np.zeros((2, 3, 3)), start),
        PairCoefficients(np.zeros(1), np.array([0.5]), impulse),
        ColorOrder([(0, 1)]),
    )
    velocity = np.zeros((2, 6))
    velocity[1, 1] = 3.0
    work, matrices, colors = _solver_rows(batch, np.zeros((1, 4, 1)), SolverSettings())
    _restitution(batch, velocity.reshape(-1), colors, work[:, LAMBDA_N], matrices.normal)
    assert work[0, LAMBDA_N.start, 0] == 0.0
    assert velocity[1, 1] == pytest.approx(2.5)
