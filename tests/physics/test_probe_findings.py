"""Defects found by the reliability probe of issue 22's follow-up (docs/reliability.md,
"Probe"), each reduced to its smallest repro: the world stays finite whatever inertia a
template or the Habitat setter gives a body, within the engine's speed limits.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from helpers import add, make_world, register_primitive

from engine import mn
from engine.physics.core import settings

FRAME = 1.0 / 60.0


def _state_is_finite(world) -> bool:
    b, n = world.bodies, world.bodies.count
    arrays = (b.body_position, b.body_rotation, b.body_linear_velocity, b.body_angular_velocity)
    return all(bool(np.all(np.isfinite(a[:n]))) for a in arrays)


@pytest.mark.parametrize("inertia", [1e-300, 1e-200])
@pytest.mark.parametrize("through_setter", [False, True])
@pytest.mark.parametrize("vectorized", [True, False])
def test_cube_with_a_vanishing_inertia_stays_finite_on_the_floor(
    inertia, through_setter, vectorized
):
    """A 1 kg, 20 cm cube given an inertia of 1e-300 kg m^2 (accepted: Habitat takes any
    positive inertia) and dropped tilted onto the floor: its split-impulse turn
    I^-1 lambda overflowed the rotation to NaN 16 frames later. The turn now obeys the
    angular speed limit like the velocity does."""
    world, templates = make_world()
    world.settings.use_vectorized = vectorized
    fields = {} if through_setter else {"inertia": [inertia] * 3}
    handle = register_primitive(templates, handle="cube", **fields)
    cube = add(world, templates, handle, [0.0, 0.3, 0.0])
    if through_setter:
        cube.intertia_diagonal = [inertia] * 3
    cube.rotation = mn.Quaternion(mn.Vector3(0.1, 0.2, 0.0), 0.97)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no overflow on the way
        for _ in range(60):
            world.step_physics(FRAME)
            assert _state_is_finite(world)
            w = np.asarray(cube.angular_velocity)
            assert np.linalg.norm(w) <= settings.MAX_ANGULAR_SPEED * (1 + 1e-12)


FLOOR = -1.45  # the demo apartment's floor height
CYLINDER = (
    "cylinderSolid_rings_1_segments_12_halfLen_1_useTexCoords_false_useTangents_false_capEnds_true"
)


def _lowest_point(world, index: int) -> float:
    """The lowest world y of body ``index``'s hull vertices, m."""
    from engine.physics.core.quaternions import quat_to_matrix

    b = world.bodies
    vertices = np.concatenate([shape.hull_vertices for shape in b.shapes[index]])
    rotation = quat_to_matrix(b.body_rotation[index][None])[0]
    return float((vertices @ rotation.T)[:, 1].min() + b.body_position[index][1])


@pytest.mark.parametrize("vectorized", [True, False])
def test_cylinder_rolling_into_a_floor_level_corner_keeps_its_floor_contact(demo_data, vectorized):
    """Probe seed throw-floor/apartment/1: a 41 cm cylinder thrown down at 9 m/s lands on
    its rim and rolls at 5 m/s into a corner of furniture at floor level (x = 1.8,
    z = -1.0). Its stage manifold got 18-30 fresh points along three normals (+y floor, -x
    and +z sides up to 20 cm deep); the four kept were all side points, so nothing held it
    up and its rim sank 5 cm into the floor in three frames. A manifold now keeps the
    deepest point of each other direction before its supporting polygon."""
    from engine.attributes import StageAttributes
    from engine.scene.assets import load_meshes

    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    meshes = load_meshes(demo_data / "scene_datasets" / "demo" / "apartment.glb")
    world.set_stage(meshes, StageAttributes())
    handle = register_primitive(
        templates, CYLINDER, half=(0.205958,) * 3, restitution_coefficient=0.8537845024235194
    )
    body = add(world, templates, handle, [1.5, -0.7380833846884569, 0.4])
    body.rotation = mn.to_quaternion(
        [0.7059025442445032, 0.3480365654178443, -0.4186604062930267, 0.45309558744689377]
    )
    body.linear_velocity = [0.6186970338853612, -6.237659094480411, -5.893850387767529]
    body.angular_velocity = [0.14211120657898393, 2.733564933062235, -3.6822704350083346]
    lowest = []
    for _ in range(40):
        world.step_physics(FRAME)
        lowest.append(_lowest_point(world, body.object_id))
    assert min(lowest) > FLOOR - 0.01  # the rim never 1 cm into the floor (was 5.1 cm)


def _corner_row(rng):
    """One manifold row of 10 points: 6 on a wall (normal +x, 5-20 cm deep) and 4 on the
    floor (normal +y, 0-5 mm deep), shuffled."""
    wall = np.column_stack([np.zeros(6), rng.uniform(0, 0.3, 6), rng.uniform(-0.2, 0.2, 6)])
    floor = np.column_stack([rng.uniform(0, 0.2, 4), np.zeros(4), rng.uniform(-0.2, 0.2, 4)])
    points = np.concatenate([wall, floor])
    normals = np.array([[1.0, 0.0, 0.0]] * 6 + [[0.0, 1.0, 0.0]] * 4)
    depth = np.concatenate([rng.uniform(0.05, 0.2, 6), rng.uniform(0.0, 0.005, 4)])
    order = rng.permutation(10)
    return points[order], normals[order], depth[order]


def test_select_with_corners_keeps_the_floor_and_agrees_with_its_reference():
    from engine.physics.collision.manifold_merge import select_with_corners
    from engine.physics.reference.reference_manifolds import select_with_corners as reference

    rng = np.random.default_rng(3)
    rows = [_corner_row(rng) for _ in range(8)]
    points = np.stack([r[0] for r in rows])
    normals = np.stack([r[1] for r in rows])
    depth = np.stack([r[2] for r in rows])
    deepest = depth.argmax(axis=1)
    reference_normal = normals[np.arange(8), deepest]
    count = np.full(8, 4)
    valid = np.ones((8, 10), dtype=bool)
    batched = select_with_corners(points, depth, normals, reference_normal, count, valid)
    for k in range(8):
        plain = reference(list(points[k]), list(depth[k]), list(normals[k]), reference_normal[k], 4)
        np.testing.assert_array_equal(batched[k], plain)
        kept = normals[k][batched[k]]
        assert batched[k].sum() == 4
        # the floor bears the body: its supporting polygon (3 points) with its deepest
        # point; the far deeper wall keeps its deepest point only
        assert (kept[:, 1] > 0.9).sum() == 3
        floor_depths = np.where(normals[k][:, 1] > 0.9, depth[k], -np.inf)
        wall_depths = np.where(normals[k][:, 0] > 0.9, depth[k], -np.inf)
        assert batched[k][floor_depths.argmax()] and batched[k][wall_depths.argmax()]


@pytest.mark.parametrize("speed", [1.0, 3.0])
@pytest.mark.parametrize("vectorized", [True, False])
def test_kinematic_box_moved_by_its_translation_pushes_a_cube_ahead_of_it(speed, vectorized):
    """Habitat's kinematic objects have a Bullet motion state: a box moved by setting
    ``obj.translation`` every frame has the velocity of that motion in its contacts
    (``saveKinematicState``). Here it had none: the cube it met was only pushed out of the
    overlap (1.3 cm deep at 1 m/s) and never moved on; at 3 m/s the box passed through it
    (47 cm). Now the cube is pushed at the box's speed and never overlaps it by 1 cm."""
    from engine.physics import MotionType

    world, templates = make_world()
    world.settings.use_vectorized = vectorized
    box = add(world, templates, register_primitive(templates, half=(0.2,) * 3), [-0.5, 0.2, 0.0])
    box.motion_type = MotionType.KINEMATIC
    cube = add(world, templates, register_primitive(templates), [0.0, 0.1, 0.0])
    overlaps = []
    for _ in range(int(round(60 / speed))):  # 1 m of travel
        box.translation = list(np.asarray(box.translation) + [speed * FRAME, 0.0, 0.0])
        world.step_physics(FRAME)
        overlaps.append((box.translation[0] + 0.2) - (cube.translation[0] - 0.1))
    assert max(overlaps) < 0.01
    assert abs(cube.linear_velocity[0] - speed) < 0.1 * speed  # carried at the box's speed


@pytest.mark.parametrize("vectorized", [True, False])
def test_cube_rides_a_kinematic_turntable_turned_by_its_rotation(vectorized):
    """The angular half of the same rule: a 2 x 2 m kinematic plate turned at 1 rad/s by
    setting ``obj.rotation`` every frame carries a cube 0.5 m from its axis round with it
    (friction 0.4 x 1; on main the cube stayed where it was)."""
    from engine.physics import MotionType

    world, templates = make_world()
    world.settings.use_vectorized = vectorized
    plate = add(
        world, templates, register_primitive(templates, half=(1.0, 0.05, 1.0)), [0.0, 0.05, 0.0]
    )
    plate.motion_type = MotionType.KINEMATIC
    handle = register_primitive(templates, half=(0.05,) * 3, friction_coefficient=1.0)
    cube = add(world, templates, handle, [0.5, 0.15, 0.0])
    for frame in range(1, 121):
        half_angle = 0.5 * frame * FRAME  # 1 rad/s
        plate.rotation = mn.Quaternion(mn.Vector3(0.0, np.sin(half_angle), 0.0), np.cos(half_angle))
        world.step_physics(FRAME)
    x, _, z = np.asarray(cube.translation)
    assert abs(np.arctan2(-z, x) - 2.0) < 0.1  # turned with the plate (2 rad)
    assert abs(np.hypot(x, z) - 0.5) < 0.02  # at its radius


@pytest.mark.parametrize("vectorized", [True, False])
def test_thin_slab_thrown_at_the_floor_never_digs_a_spinning_corner_into_it(vectorized):
    """Probe seed thin/box/1: a 54 x 54 cm slab 1 mm thick thrown tilted at the floor at
    28.5 m/s. The impact spins it up to 47 rad/s; a corner then swings 15 cm a step, and the
    swept test, which moved the slab along its translation only, let that corner dig
    7.9 cm into the floor. The vertices are now also swept along the chords of the turn."""
    world, templates = make_world()
    world.settings.use_vectorized = vectorized
    slab = add(
        world,
        templates,
        register_primitive(templates, half=(0.268115, 0.0005, 0.268115)),
        [0.0, 0.6, 0.0],
    )
    slab.rotation = mn.to_quaternion(
        [0.19655204737110374, -0.7751497649015157, 0.5385277924904597, 0.26551450311179786]
    )
    slab.linear_velocity = [5.493277777584843, -27.93832925124164, -1.5220946546492793]
    lowest = []
    for _ in range(60):
        world.step_physics(FRAME)
        lowest.append(_lowest_point(world, slab.object_id))
    assert min(lowest) > -0.005  # no corner 5 mm into the floor (was 7.9 cm)
    assert abs(slab.translation[1] - 0.0005) < 0.002  # lying on it after a second


CONE = "coneSolid_segments_12_halfLen_1_rings_1_useTexCoords_false_useTangents_false_capEnd_true"


@pytest.mark.parametrize("vectorized", [True, False])
def test_cone_thrown_at_the_apartment_floor_at_a_grazing_angle_stays_out_of_it(
    demo_data, vectorized
):
    """Probe seed throw-wall/apartment/5: a 24 cm cone thrown at 18 m/s, 22 degrees below
    the horizontal, grazes the floor, spins up to 35 rad/s and one frame later its rim was
    4.0 cm in: the vertex that started the step 2 mm inside the floor was not swept (its ray
    started behind the surface). Vertex rays now start the stage's speculative distance
    earlier; a crossing there counts when the surface faces the body's center."""
    from engine.attributes import StageAttributes
    from engine.scene.assets import load_meshes

    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    meshes = load_meshes(demo_data / "scene_datasets" / "demo" / "apartment.glb")
    world.set_stage(meshes, StageAttributes())
    cone = add(
        world,
        templates,
        register_primitive(templates, CONE, half=(0.117933,) * 3),
        [2.0, -0.5, -0.5],
    )
    cone.rotation = mn.to_quaternion(
        [0.08975594104764606, -0.45214664439660573, -0.6420655471793384, 0.6125839665979168]
    )
    cone.linear_velocity = [-3.7439148694909856, -6.170775863901161, 16.36188522489565]
    lowest = []
    for _ in range(30):
        world.step_physics(FRAME)
        lowest.append(_lowest_point(world, cone.object_id))
    assert min(lowest) > FLOOR - 0.02  # the rim never 2 cm into the floor (was 4.0 cm)


#: Habitat's default cone primitive (half length 1.25), the one the probe found sinking
DEFAULT_CONE = (
    "coneSolid_segments_12_halfLen_1.25_rings_1_useTexCoords_false_useTangents_false_capEnd_true"
)


@pytest.mark.parametrize("factor", [50.0, 100.0])
@pytest.mark.parametrize("primitive", [CYLINDER, DEFAULT_CONE], ids=["cylinder", "cone"])
@pytest.mark.parametrize("vectorized", [True, False])
def test_body_whose_mass_is_raised_far_above_its_inertia_rests_on_the_floor(
    factor, primitive, vectorized
):
    """``obj.mass *= 50`` or ``100`` on a 20 cm cylinder or cone keeps its inertia (as
    Habitat's ``setMassProps`` does): a contact point's effective mass becomes about
    ``I / r^2``, far below ``m``, and the mass-split Jacobi sweeps alone let the body sink
    through the floor (it was 22-76 m down after 5 s). The block normal sweep supports it:
    after 5 s it rests where the same body with its template mass rests, and never dipped
    below that height by more than twice the penetration slop."""
    resting = {}
    for scale in (1.0, factor):
        world, templates = make_world()
        world.settings.use_vectorized = vectorized
        handle = register_primitive(templates, primitive, (0.1, 0.1, 0.1))
        body = add(world, templates, handle, [0.0, 0.3, 0.0])
        body.mass = body.mass * scale
        lowest = np.inf
        for _ in range(300):  # 5 s
            world.step_physics(FRAME)
            lowest = min(lowest, float(body.translation[1]))
        resting[scale] = (lowest, float(body.translation[1]))
    light_end = resting[1.0][1]
    heavy_lowest, heavy_end = resting[factor]
    # the heavy body rests where the light one does, within twice the penetration slop
    assert abs(heavy_end - light_end) < 2 * settings.PENETRATION_SLOP
    assert heavy_lowest > light_end - 2 * settings.PENETRATION_SLOP
