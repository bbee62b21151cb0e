"""Issue 10: no dynamic body leaves the stage through a floor or wall it did not start behind.

Small cubes and thin plates on the demo apartment's floor (y = -1.45), bodies thrown at
200 m/s (the speed limit) at the floor, a wall and a corner of the apartment, a 100 kg box
dropped on a 0.1 kg box, bodies created half inside the stage, and templates below the
documented minimum size. Every test tracks the body at every frame, not only at the end.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, floor_mesh, make_world, register_primitive

from engine import mn
from engine.attributes import StageAttributes
from engine.physics.core import settings
from engine.scene.assets import load_meshes

FLOOR = -1.45  # the apartment's floor height (tests/engine/test_datasets.py)
FRAME = 1.0 / 60.0


@pytest.fixture(scope="module")
def apartment_meshes(demo_data):
    return load_meshes(demo_data / "scene_datasets" / "demo" / "apartment.glb")


def apartment_world(meshes):
    world, templates = make_world(floor=False)
    world.set_stage(meshes, StageAttributes())
    return world, templates


def track(world, obj, frames: int) -> np.ndarray:
    """Positions ``(frames, 3)`` of ``obj`` after each 1/60 s frame."""
    path = []
    for _ in range(frames):
        world.step_physics(FRAME)
        path.append(np.asarray(obj.translation))
    return np.array(path)


@pytest.mark.parametrize("half", [0.0025, 0.005])
def test_small_cube_placed_just_above_the_apartment_floor_rests_on_it(apartment_meshes, half):
    """A 5 mm and a 1 cm cube placed 6 mm above the floor (issue 10: the 1 cm cube was at
    y = -5.5 one second later)."""
    world, templates = apartment_world(apartment_meshes)
    cube = add(
        world,
        templates,
        register_primitive(templates, half=(half,) * 3),
        [1.75, FLOOR + half + 0.006, 0.4],
    )
    path = track(world, cube, 60)
    assert path[:, 1].min() > FLOOR + half - 0.002  # never more than 2 mm into the floor
    assert abs(path[-1, 1] - (FLOOR + half)) < 0.001  # resting on it
    np.testing.assert_allclose(path[-1, [0, 2]], [1.75, 0.4], atol=0.005)


@pytest.mark.parametrize("thickness", [0.001, 0.002])
def test_thin_plate_dropped_on_the_apartment_floor_rests_on_it(apartment_meshes, thickness):
    """10 x 10 cm plates 1 and 2 mm thick dropped from 25 cm (issue 10: both fell through)."""
    world, templates = apartment_world(apartment_meshes)
    plate = add(
        world,
        templates,
        register_primitive(templates, half=(0.05, thickness / 2, 0.05)),
        [1.75, FLOOR + 0.25, 0.4],
    )
    path = track(world, plate, 60)
    assert path[:, 1].min() > FLOOR - 0.002
    assert abs(path[-1, 1] - (FLOOR + thickness / 2)) < 0.001


def test_plate_1_mm_thrown_down_at_the_speed_limit_stops_on_the_floor(apartment_meshes):
    world, templates = apartment_world(apartment_meshes)
    # restitution 0: the plate must stop where it hits (with 0.1 it bounces up at 20 m/s)
    plate = add(
        world,
        templates,
        register_primitive(templates, half=(0.05, 0.0005, 0.05), restitution_coefficient=0.0),
        [1.75, -1.2, 0.4],
    )
    plate.linear_velocity = [0.0, -settings.MAX_LINEAR_SPEED, 0.0]
    path = track(world, plate, 30)
    assert path[:, 1].min() > FLOOR - 0.002
    assert abs(path[-1, 1] - (FLOOR + 0.0005)) < 0.001


@pytest.mark.parametrize(
    "direction",
    [(1.0, 0.0, 0.0), (-1.0, -0.2, -1.0), (1.0, -0.3, 1.0)],
    ids=["wall", "corner", "corner-and-floor"],
)
def test_cube_1_cm_thrown_at_the_speed_limit_stays_in_the_room(apartment_meshes, direction):
    """The living room spans x -1.0 .. 5.0 and z -3.5 .. 2.5 at y = -0.5 (walls 10 cm thick);
    a 1 cm cube thrown at 200 m/s at a wall or a corner stays inside."""
    world, templates = apartment_world(apartment_meshes)
    cube = add(
        world, templates, register_primitive(templates, half=(0.005,) * 3), [2.0, -0.5, -0.5]
    )
    u = np.asarray(direction) / np.linalg.norm(direction)
    cube.linear_velocity = list(settings.MAX_LINEAR_SPEED * u)
    path = track(world, cube, 30)
    margin = 0.005
    assert path[:, 0].min() > -1.0 - margin and path[:, 0].max() < 5.0 + margin
    assert path[:, 2].min() > -3.5 - margin and path[:, 2].max() < 2.5 + margin
    assert path[:, 1].min() > FLOOR - margin


def test_heavy_box_on_light_box_never_pushes_it_through_the_floor():
    """100 kg dropped on 0.1 kg (ratio 1000; issue 10: the light box ended at y = -15)."""
    world, templates = make_world()
    light = add(
        world,
        templates,
        register_primitive(templates, half=(0.1,) * 3, mass=0.1, handle="light"),
        [0.0, 0.1, 0.0],
    )
    heavy = add(
        world,
        templates,
        register_primitive(templates, half=(0.1,) * 3, mass=100.0, handle="heavy"),
        [0.0, 0.5, 0.0],
    )
    lows, highs = [], []
    for _ in range(90):
        world.step_physics(FRAME)
        lows.append(light.translation[1])
        highs.append(heavy.translation[1])
    assert min(lows) > 0.1 - 0.01  # at most 1 cm into the floor at any time
    assert abs(lows[-1] - 0.1) < 0.002  # the light box ends on the floor...
    assert abs(highs[-1] - 0.3) < 0.005  # ...and the heavy one on top of it


def test_stage_and_shock_passes_agree_between_vectorized_and_scalar_solvers():
    """The two paths of the solver, on a scene where the stage rows and the shock pass act
    (a 100 kg box landing on a 0.1 kg one, on a 2 x 2 grid of light boxes)."""
    results = []
    for vectorized in (True, False):
        world, templates = make_world()
        world.settings.use_vectorized = vectorized
        light = register_primitive(templates, half=(0.1,) * 3, mass=0.1, handle="light")
        heavy = register_primitive(templates, half=(0.1,) * 3, mass=100.0, handle="heavy")
        for x in (-0.1, 0.1):
            for z in (-0.1, 0.1):
                add(world, templates, light, [x * 2.05, 0.1, z * 2.05])
        add(world, templates, heavy, [0.02, 0.45, -0.01])
        for _ in range(40):
            world.step_physics(FRAME)
        n = world.bodies.count
        results.append(
            (world.bodies.body_position[:n].copy(), world.bodies.body_linear_velocity[:n].copy())
        )
    np.testing.assert_allclose(results[0][0], results[1][0], atol=1e-9)
    np.testing.assert_allclose(results[0][1], results[1][1], atol=1e-8)
    assert results[0][0][1:5, 1].min() > 0.1 - 0.01  # the light boxes stay on the floor


@pytest.mark.parametrize("sunk", [0.05, 0.09])
def test_box_created_half_inside_the_floor_is_pushed_out_upwards_calmly(sunk):
    world, templates = make_world()
    box = add(
        world, templates, register_primitive(templates, half=(0.1,) * 3), [0.0, 0.1 - sunk, 0.0]
    )
    path, speeds = [], []
    for _ in range(60):
        world.step_physics(FRAME)
        path.append(box.translation[1])
        speeds.append(np.linalg.norm(np.asarray(box.linear_velocity)))
    assert min(path) > 0.1 - sunk - 0.002  # never pushed down
    assert abs(path[-1] - 0.1) < 0.005  # out and resting on the floor
    assert max(speeds) < 5.0


@pytest.mark.parametrize("on_apartment", [True, False])
def test_cube_teleported_15_cm_into_the_floor_comes_out_upwards_at_a_bounded_speed(
    apartment_meshes, on_apartment
):
    """Issue 22: a 0.2 m cube teleported 15 cm into the apartment's floor (its center 5 cm
    below the surface) left through the floor at 8.7 m/s. A new stage contact takes the
    triangle's front when part of the body is in front of it, so the cube is pushed up;
    the position solve's push is capped at MAX_CORRECTION_SPEED (2 m/s)."""
    world, templates = apartment_world(apartment_meshes) if on_apartment else make_world()
    floor = FLOOR if on_apartment else 0.0
    cube = add(world, templates, register_primitive(templates), [1.75, floor + 0.1, 0.4])
    # teleported before any step: no manifold remembers the side it came from
    cube.translation = [1.75, floor + 0.1 - 0.15, 0.4]
    path, speeds = [], []
    for _ in range(120):
        world.step_physics(FRAME)
        path.append(cube.translation[1] - floor)
        speeds.append(np.linalg.norm(np.asarray(cube.linear_velocity)))
    assert min(path) > -0.05 - 0.002  # never pushed down (the center started at -5 cm)
    assert max(speeds) <= settings.MAX_CORRECTION_SPEED
    assert abs(path[-1] - 0.1) < 0.005  # out and resting on the floor (hand geometry)


def test_plate_created_half_inside_a_thin_floor_comes_out_on_its_side():
    """A 1 mm plate sunk by half its thickness into a floor: the manifold remembers the
    outward side, so it comes out upwards."""
    world, templates = make_world()
    plate = add(
        world, templates, register_primitive(templates, half=(0.05, 0.0005, 0.05)), [0.0, 0.0, 0.0]
    )
    path = track(world, plate, 30)
    assert path[:, 1].min() > -0.0015
    assert abs(path[-1, 1] - 0.0005) < 0.001


def test_templates_thinner_than_the_minimum_are_refused_and_the_world_steps_on():
    """Issue 10: a cube at scale 1e-7 dropped on another made every later step raise."""
    world, templates = make_world()
    big = add(world, templates, register_primitive(templates, half=(0.1,) * 3), [0, 0.1, 0])
    tiny = register_primitive(templates, half=(1e-7,) * 3, handle="tiny")
    before = world.state_hash()
    with pytest.raises(ValueError, match="MIN_BODY_DIMENSION"):
        world.rigid_object_manager.add_object_by_template_handle(tiny)
    assert world.state_hash() == before and world.rigid_object_manager.get_num_objects() == 1
    smallest = register_primitive(
        templates, half=(settings.MIN_BODY_DIMENSION / 2,) * 3, handle="smallest"
    )
    speck = add(world, templates, smallest, [0.0, 0.25, 0.0])
    for _ in range(30):
        world.step_physics(FRAME)
    assert np.all(np.isfinite(np.asarray(speck.translation)))
    assert speck.translation[1] > 0.2 - 0.002  # on the big box
    assert abs(big.translation[1] - 0.1) < 0.001


def test_floor_mesh_helper_faces_up():
    """The outward side used above: the helper floor's triangles wind counter-clockwise
    seen from +Y."""
    mesh = floor_mesh()
    a, b, c = (mesh.vertices[mesh.faces[0, k]] for k in range(3))
    assert np.cross(b - a, c - a)[1] > 0


@pytest.mark.parametrize("vectorized", [True, False])
def test_cube_sliding_down_a_wall_past_a_shelf_lands_on_the_apartment_floor(
    apartment_meshes, vectorized
):
    """The 10^4-operation soak (seed 0, op 4290) lost a 20 cm cube falling at 2.4 m/s along
    the wall in front of a cabinet (x = 3.45): its corner grazed the underside of the
    cabinet's shelf (y = -1.13, normal down), and that cached down normal then turned the
    floor's triangles (y = -1.45, parallel to it) over, so the floor pushed the cube down
    through it. A cached normal now decides a triangle's side only from its own plane."""
    world, templates = apartment_world(apartment_meshes)
    world.settings.use_vectorized = vectorized  # the reference path must agree
    cube = add(
        world,
        templates,
        register_primitive(templates, half=(0.1, 0.1, 0.1)),
        [3.343778865714829, -0.9169544273314506, -0.5989303073564052],
    )
    cube.rotation = mn.to_quaternion(
        [-0.24487793855340748, -0.5635814113154825, 0.16232292414606286, 0.7720505529602023]
    )
    cube.linear_velocity = [0.07236584518466511, -2.427533555197379, 0.15870247137538934]
    world.step_physics(0.008 - 1e-15)  # the soak's accumulator: no step yet
    path = track(world, cube, 40)
    assert path[:, 1].min() > FLOOR  # its center never goes below the floor
    assert FLOOR + 0.09 < path[-1, 1] < FLOOR + 0.18  # resting on it (half 0.1 to 0.17)


SPHERE = "icosphereSolid_subdivs_1"
CAPSULE = (
    "capsule3DSolid_hemiRings_4_cylRings_1_segments_12_halfLen_0.75"
    "_useTexCoords_false_useTangents_false"
)
#: primitive -> its resting center height on a floor at y = 0 with scale 0.1 (hand geometry:
#: half side 0.1; sphere radius 0.1; capsule radius 0.1 plus half its 0.075 m segment)
RESTING_HEIGHT = {"cubeSolid": 0.1, SPHERE: 0.1, CAPSULE: 0.1 + 0.075}


@pytest.mark.parametrize("primitive", list(RESTING_HEIGHT))
@pytest.mark.parametrize("faces_down", [False, True])
@pytest.mark.parametrize("vectorized", [True, False])
def test_body_spawned_half_buried_in_a_floor_wound_either_way_comes_out_on_top(
    primitive, faces_down, vectorized
):
    """Mutation testing (issue 26) found a ball spawned half buried in a floor whose
    triangles face down falling through it; a capsule spawned 5 cm into an up-facing floor
    ended half sunk (its lower end sphere was pushed down). A new contact with a floor-like
    triangle now pushes a body whose center is on or above the plane up, whatever the
    winding (contact_helpers.new_contact_side)."""
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    floor = floor_mesh()
    if faces_down:
        floor.faces = floor.faces[:, ::-1].copy()
    world.set_stage([floor], StageAttributes())
    body = add(world, templates, register_primitive(templates, primitive), [0.0, 0.0, 0.0])
    path = track(world, body, 120)[:, 1]
    assert path.min() > -0.002  # never pushed down (the center started on the plane)
    assert abs(path[-1] - RESTING_HEIGHT[primitive]) < 0.006  # out, resting on the floor


@pytest.mark.parametrize("faces_down", [False, True])
def test_ball_dropped_on_a_floor_wound_either_way_rests_on_it(faces_down):
    """The other side of the rule: a ball falling on a floor touches it from above, so
    either winding holds it at its radius (a down-facing floor's back is outward)."""
    world, templates = make_world(floor=False)
    floor = floor_mesh()
    if faces_down:
        floor.faces = floor.faces[:, ::-1].copy()
    world.set_stage([floor], StageAttributes())
    ball = add(world, templates, register_primitive(templates, SPHERE), [0.0, 0.5, 0.0])
    path = track(world, ball, 120)[:, 1]
    assert path.min() > 0.1 - 0.01 and abs(path[-1] - 0.1) < 0.003


def test_new_contact_side_agrees_with_its_reference_on_every_case():
    """The batched rule and its plain twin on a grid of normals and heights (both signs,
    floor-like and wall-like, the center on the plane)."""
    from engine.physics.collision.contact_helpers import new_contact_side
    from engine.physics.reference.reference_pairs import new_contact_side_reference

    values = np.array([-1.0, -0.6, -0.5, -0.2, 0.0, 0.2, 0.5, 0.6, 1.0])
    ny, hc, hm = (a.ravel() for a in np.meshgrid(values, values / 10, values / 10))
    batched = new_contact_side(ny, hc, hm)
    plain = [new_contact_side_reference(*case) for case in zip(ny, hc, hm, strict=True)]
    np.testing.assert_array_equal(batched, plain)
    # hand cases: an up-facing floor under a body whose center sank below it: the front
    assert new_contact_side(np.array([1.0]), np.array([-0.05]), np.array([0.05]))[0] == 1.0
    # a down-facing floor under a body whose center is above it: up (the back)
    assert new_contact_side(np.array([-1.0]), np.array([-0.05]), np.array([0.05]))[0] == -1.0
    # a ceiling (facing down) pressed from below: its front (down)
    assert new_contact_side(np.array([-1.0]), np.array([0.05]), np.array([0.15]))[0] == 1.0
    # a body wholly behind a one-sided wall stays behind it
    assert new_contact_side(np.array([0.0]), np.array([-0.2]), np.array([-0.1]))[0] == -1.0
    # a body poking through the back of a thin board: pulled back to its center's side
    assert new_contact_side(np.array([0.0]), np.array([-0.04]), np.array([0.02]))[0] == -1.0


def lowest_point(world, index: int) -> float:
    """The lowest world y of body ``index``'s hull vertices, m."""
    from engine.physics.core.quaternions import quat_to_matrix

    b = world.bodies
    vertices = np.concatenate([shape.hull_vertices for shape in b.shapes[index]])
    return float((vertices @ quat_to_matrix(b.body_rotation[index]).T)[:, 1].min()) + float(
        b.body_position[index][1]
    )


@pytest.mark.parametrize("template", ["mug", "cubeSolid"])
@pytest.mark.parametrize("vectorized", [True, False])
def test_body_driven_into_a_skirting_board_corner_stays_out_of_the_floor(
    demo_data, template, vectorized
):
    """The 10^4 soak left a mug 2.5 cm below the floor against a wall: velocity control
    drove it at (1, -0.5, 0) m/s into the corner of the floor and the 15 mm skirting board
    in front of the wall at x = 5 (a thin slab). Its vertices poked through the board's back
    face (x = 5.0, facing the wall); as a new contact that face took its front and pushed
    the mug on into the wall, and its cached normal then turned the board's room-side face
    over (within the old 2 cm plane tolerance), so every contact pushed +x and none held it
    up: 5 cm into the floor. Now a wall-like face takes the side of the body's center, a
    cached normal turns only its own plane (1 mm) and a vertex in a corner keeps a floor
    contact beside its wall contact."""
    sim = apartment_sim(demo_data)
    templates = sim.get_object_template_manager()
    templates.load_configs(str(demo_data / "objects/example_objects/"))
    world = sim.get_physics_world()
    world.settings.use_vectorized = vectorized
    handle = templates.get_template_handles(template)[0]
    body = sim.get_rigid_object_manager().add_object_by_template_handle(handle)
    body.translation = [4.85, -1.3, -0.04]
    control = body.velocity_control
    control.controlling_lin_vel = control.controlling_ang_vel = True
    control.linear_velocity, control.angular_velocity = [1.0, -0.5, 0.0], [0.0, 0.0, 0.0]
    lowest = []
    for _ in range(150):
        sim.step_physics(FRAME)
        lowest.append(lowest_point(world, body.object_id))
    center_x = body.translation[0]
    sim.close()
    assert min(lowest) > FLOOR - 0.02  # never 2 cm into the floor, while pushed into it
    assert center_x < 5.0  # and never through the board into the wall


def apartment_sim(demo_data):
    """A simulator on the demo apartment with no sensors."""
    import engine as habitat_sim

    cfg = habitat_sim.SimulatorConfiguration()
    cfg.scene_id = str(demo_data / "scene_datasets/demo/apartment.glb")
    agent = habitat_sim.agent.AgentConfiguration()
    agent.sensor_specifications = []
    return habitat_sim.Simulator(habitat_sim.Configuration(cfg, [agent]))


SOAK_CONE = (
    "coneSolid_segments_12_halfLen_1.25_rings_1_useTexCoords_false_useTangents_false_capEnd_true"
)


@pytest.mark.parametrize("vectorized", [True, False])
def test_cone_whose_tip_hits_the_wall_floor_corner_stays_above_the_floor(demo_data, vectorized):
    """The walls soak (``benchmarks/soak.py --walls``, seed 1) lost cones through the
    apartment's outer walls. This 25 cm cone (its state recorded 5 frames before) lands
    spinning at 11 rad/s with its tip in the corner of the floor (y = -1.45, ending at
    z = -3.5) and the wall, whose box reaches 5 cm below the floor. Pressed a few mm into
    the wall, the tip had left the floor triangle's prism: nothing held it up and it sank
    down the wall to the wall's underside, 5.5 cm below the floor, and stayed there; a push
    toward the wall at 4 m/s then slid the cone under the wall, out of the apartment. A
    vertex pushed back out of the wall is over the floor again: the floor still holds it."""
    sim = apartment_sim(demo_data)
    templates = sim.get_object_template_manager()
    template = templates.create_new_template("wall_cone")
    template.render_asset_handle = template.collision_asset_handle = SOAK_CONE
    template.scale = [0.1, 0.1, 0.1]
    templates.register_template(template, "wall_cone")
    world = sim.get_physics_world()
    world.settings.use_vectorized = vectorized
    cone = sim.get_rigid_object_manager().add_object_by_template_handle("wall_cone")
    cone.translation = [3.0316563862895918, -1.3759921080092803, -3.395706320438366]
    cone.rotation = mn.Quaternion(
        mn.Vector3(-0.5664223064782975, 0.5633365249178134, -0.5330897646307982),
        -0.2786270504872203,
    )
    cone.linear_velocity = [-1.9360993202619035, -1.44966208670521, -1.1490114335784234]
    cone.angular_velocity = [4.387194955772162, -1.0286335436551384, 10.918710193601841]
    world.step_physics(0.004666666666666489)  # the soak's accumulator: no step yet
    lowest, centers = [], []
    for frame in range(90):
        if frame == 60:  # resting in the corner: struck toward the wall, as the soak did
            cone.linear_velocity = [-1.0, 0.0, -4.0]
        sim.step_physics(FRAME)
        lowest.append(lowest_point(world, cone.object_id))
        centers.append(np.asarray(cone.translation))
    sim.close()
    assert min(lowest) > FLOOR - 0.02  # the tip never 2 cm below the floor (was 5.5 cm)
    assert np.array(centers)[:, 2].min() > -3.5  # the center stays in front of the wall
    assert centers[-1][1] > FLOOR  # and in the room (it was lost under the wall)
