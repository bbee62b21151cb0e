"""Graph coloring; fast bodies do not tunnel; determinism; docs/physics.md, validation.

The two solver paths are compared in test_reference_path.py, the switches in
test_solver_switches.py."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

from engine import mn
from engine.physics import MotionType
from engine.physics.solver.coloring import color_manifolds


def _pile_world(**solver_options):
    world, templates = make_world()
    for name, value in solver_options.items():
        setattr(world.settings, name, value)
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    rng = np.random.default_rng(7)
    for k in range(6):
        box = add(
            world,
            templates,
            handle,
            [0.15 * (k % 3) - 0.15, 0.12 + 0.25 * (k // 3), rng.uniform(-0.05, 0.05)],
        )
        q = rng.normal(size=4)
        box.rotation = mn.Quaternion.from_xyzw(q / np.linalg.norm(q))
    return world


def test_graph_coloring_puts_each_dynamic_body_once_per_color():
    rng = np.random.default_rng(1)
    body_a = rng.integers(0, 12, size=60)
    body_b = (body_a + rng.integers(1, 12, size=60)) % 12  # never a self pair
    is_dynamic = np.arange(12) > 1  # bodies 0 and 1 are static: they may repeat
    colors = color_manifolds(body_a, body_b, is_dynamic)
    assert sorted(np.concatenate(colors).tolist()) == list(range(60))
    for color in colors:
        used = [b for m in color for b in (body_a[m], body_b[m]) if is_dynamic[b]]
        assert len(used) == len(set(used))


def test_color_order_ends_each_color_with_its_stage_rows_and_keeps_the_rest():
    from engine.physics.pipeline.solve_stage import color_order

    rng = np.random.default_rng(4)
    for _ in range(50):
        n, m = int(rng.integers(2, 20)), int(rng.integers(1, 60))
        body_a = rng.integers(0, n, size=m)
        body_b = (body_a + rng.integers(1, n, size=m)) % n  # never a self pair
        solvable = rng.random(n) < 0.7
        colors = color_manifolds(body_a, body_b, solvable)
        stage_row = ~(solvable[body_a] & solvable[body_b])
        order, slices, priority_starts = color_order(colors, stage_row)
        assert len(slices) == len(priority_starts) == len(colors)
        for color, (start, stop), first_stage in zip(colors, slices, priority_starts, strict=True):
            inner = [i for i in color.tolist() if not stage_row[i]]
            outer = [i for i in color.tolist() if stage_row[i]]
            assert order[start:stop].tolist() == inner + outer
            assert first_stage == start + len(inner)


def test_small_fast_sphere_does_not_tunnel_through_a_thin_static_wall():
    world, templates = make_world(floor=False, gravity=(0.0, 0.0, 0.0))
    wall_handle = register_primitive(templates, "cubeSolid", (0.01, 0.5, 0.5))  # 2 cm thick
    wall = add(world, templates, wall_handle, [1.0, 0.0, 0.0])
    wall.motion_type = MotionType.STATIC
    ball_handle = register_primitive(
        templates, "icosphereSolid_subdivs_1", (0.025,) * 3, restitution_coefficient=0.5
    )
    ball = add(world, templates, ball_handle, [0.0, 0.0, 0.0], linear_velocity=[50.0, 0, 0])
    for _ in range(30):
        world.step_physics(1.0 / 60.0)
        assert ball.translation[0] < 1.0  # never behind the wall's center plane
    assert ball.linear_velocity[0] <= 0.0  # it bounced back


def test_same_script_is_bit_identical_in_one_process():
    hashes = []
    for _ in range(2):
        world = _pile_world()
        run(world, 0.5)
        hashes.append(world.state_hash())
    assert hashes[0] == hashes[1]


def test_same_script_is_bit_identical_across_processes():
    script = textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {str(Path(__file__).parent)!r})
        from test_solver_and_robustness import _pile_world
        from helpers import run
        world = _pile_world()
        run(world, 0.5)
        print(world.state_hash())
    """)
    outputs = [
        subprocess.run(
            [sys.executable, "-c", script], capture_output=True, text=True, check=True
        ).stdout.strip()
        for _ in range(2)
    ]
    world = _pile_world()
    run(world, 0.5)
    assert outputs[0] == outputs[1] == world.state_hash()


BAD_VECTORS = [[np.nan, 0, 0], [0, np.inf, 0], [1, 2], None, "abc", [[1, 2, 3]]]


def _setup_bad_input_world():
    world, templates = make_world()
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    box = add(world, templates, handle, [0.0, 0.5, 0.0])
    run(world, 0.1)
    return world, box


@pytest.mark.parametrize(
    "name", ["translation", "linear_velocity", "angular_velocity", "intertia_diagonal"]
)
@pytest.mark.parametrize("value", BAD_VECTORS)
def test_bad_vectors_raise_and_leave_the_world_unchanged(name, value):
    world, box = _setup_bad_input_world()
    before = world.state_hash()
    with pytest.raises((ValueError, TypeError), match=name):
        setattr(box, name, value)
    assert world.state_hash() == before


@pytest.mark.parametrize(
    "call",
    [
        lambda box: box.apply_force([np.nan, 0, 0], [0, 0, 0]),
        lambda box: box.apply_force([1, 0, 0], [0, np.inf, 0]),
        lambda box: box.apply_torque([1, 0]),
        lambda box: box.apply_impulse(None, [0, 0, 0]),
        lambda box: box.apply_impulse_torque([np.nan] * 3),
        lambda box: setattr(box, "rotation", [0, 0, 0, 0]),
        lambda box: setattr(box, "rotation", [np.nan, 0, 0, 1]),
        lambda box: setattr(box, "transformation", np.full((4, 4), np.nan)),
        lambda box: setattr(box, "mass", 0.0),
        lambda box: setattr(box, "mass", -1.0),
        lambda box: setattr(box, "mass", np.inf),
        lambda box: setattr(box, "friction_coefficient", -0.1),
        lambda box: setattr(box, "linear_damping", np.nan),
        lambda box: setattr(box, "motion_type", 7),
        lambda box: setattr(box, "awake", "yes"),
        lambda box: box.translate([np.nan, 0, 0]),
        lambda box: box.rotate_x(np.nan),
    ],
)
def test_bad_calls_raise_and_leave_the_world_unchanged(call):
    world, box = _setup_bad_input_world()
    before = world.state_hash()
    with pytest.raises((ValueError, TypeError)):
        call(box)
    assert world.state_hash() == before


@pytest.mark.parametrize("dt", [np.nan, np.inf, "0.1", None, 1e9])
def test_bad_step_raises_and_leaves_the_world_unchanged(dt):
    world, _ = _setup_bad_input_world()
    before = world.state_hash()
    with pytest.raises((ValueError, TypeError), match="dt"):
        world.step_physics(dt)
    assert world.state_hash() == before


def test_bad_gravity_and_empty_stage_meshes_raise():
    world, _ = _setup_bad_input_world()
    before = world.state_hash()
    with pytest.raises(ValueError, match="gravity"):
        world.set_gravity([0, np.nan, 0])
    from engine.scene.assets import MeshData

    empty = MeshData(vertices=np.zeros((0, 3)), faces=np.zeros((0, 3), dtype=np.int64))
    with pytest.raises(ValueError, match="stage"):
        world.set_stage([empty], None)
    bad = MeshData(
        vertices=np.array([[0, 0, 0], [1, 0, 0], [0, 0, np.nan]]), faces=np.array([[0, 1, 2]])
    )
    with pytest.raises(ValueError, match="NaN"):
        world.set_stage([bad], None)
    assert world.state_hash() == before


def test_translate_local_of_a_turned_object_adds_the_vector_as_habitats_trs_node_does():
    """Habitat's objects move their Magnum TRS node with ``translateLocal``, which adds the
    vector without rotating it: a box turned 90 degrees about +Y still moves along world -Z."""
    world, templates = make_world()
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    box = add(world, templates, handle, [0.0, 0.5, 0.0], motion_type=MotionType.KINEMATIC)
    box.rotation = mn.Quaternion.rotation(mn.Deg(90.0), [0.0, 1.0, 0.0])
    box.translate_local([0.0, 0.0, -1.0])
    np.testing.assert_allclose(np.asarray(box.translation), [0.0, 0.5, -1.0], atol=1e-12)
