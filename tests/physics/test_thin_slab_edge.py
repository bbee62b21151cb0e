"""A fast spinning cube flying into the edge of a thin table top (the seed-1 CI soak's sink).

The seed-1 CI soak (``benchmarks/soak.py``, the CI mix) records a 0.2 m cube 12.9 cm below
the stage: a push toward a wall left it at 5 m/s and 27 rad/s, and it flew into the edge of
the apartment's 4 cm table top (``y`` in [-0.73, -0.69], front face at ``z = -0.25``), then
straddled it. This is that flight, from the soak's state at full precision, against a box
of the table top's size over a floor (the trajectory matches the soak's to 0.1 mm).

The cause, on both paths (stage contact generation): after three steps the cube's only
vertex inside the slab's footprint is 2.3 cm *below* the slab's bottom face, outside the
solid and just past the 2 cm speculative reach, while the cube's edge crosses the slab's
front-bottom edge by 0.3 cm (the true overlap, separating axis test). The vertex lies in
the prism of a *top*-face triangle 6.3 cm behind its plane, inside the accepted window
(``STAGE_BELOW_FRACTION`` times the cube's extent), so it becomes a resting contact of the
top face: the stage pushing the cube up (+Y), 6.3 cm deep, more than the slab is thick.
The spin moves that vertex up at 4.8 m/s, so the solve gives it no impulse, while the
position correction lifts the cube toward the slab; and the spurious vertex contact keeps
the edge-crossing fallback (fcl's points) from running, so the real edge contact is never
made. The cube flies on into the slab at 4.4 m/s; the true overlap passes 15 cm within
0.24 s.

The fix, on both paths: a vertex rests on a triangle only when the segment from it to its
foot on the triangle stays inside the stage's solid, crossing no other stage triangle
(:mod:`engine.physics.collision.stage_crossings`); the vertex below the slab is then no
contact, and the edge-crossing fallback takes fcl's points with the normal of the face
the cube entered through (the named triangle it is least deep behind: the front face,
not the bottom face, which gave 6.9 cm). Measured: 1.08 cm deepest on both paths.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, floor_mesh, make_world, register_primitive
from test_stage_corners import narrow_phase_contacts

from engine import mn
from engine.attributes import StageAttributes
from engine.physics.collision.pair_rules import FCL_FEATURE, RULE_SHIFT
from engine.physics.core.quaternions import quat_to_matrix
from engine.physics.core.vectors import dot
from engine.scene.assets import MeshData

SLAB_LOW = np.array([5.9, -0.73, -0.95])  # the table top's corners, m
SLAB_HIGH = np.array([6.9, -0.69, -0.25])
HALF = 0.1  # the cube's half side, m
TOLERANCE = 0.02  # m, the soak's sink tolerance
#: the cube after the soak's step 1338: position, rotation (xyzw), velocity, spin
START = (
    [6.842481015598837, -0.7498043316758346, -0.00795748730937193],
    [-0.26862028169297975, 0.2657184645175239, 0.26674246283657344, -0.8866145162343739],
    [-2.426537313871449, -0.21286195831079685, -4.392864479945353],
    [26.663501233472125, 9.142984726669216, -14.372856932184666],
)


def box_mesh(low: np.ndarray, high: np.ndarray) -> MeshData:
    """A closed box, its twelve triangles wound to face outward."""
    corners = [
        (x, y, z) for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])
    ]
    vertices = np.array(corners, dtype=float)  # index = 4 ix + 2 iy + iz
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    faces = np.array([tri for a, b, c, d in quads for tri in ((a, b, c), (a, c, d))])
    center = 0.5 * (low + high)
    for k, (a, b, c) in enumerate(faces):
        normal = np.cross(vertices[b] - vertices[a], vertices[c] - vertices[a])
        if np.dot(normal, vertices[a] - center) < 0.0:
            faces[k] = (a, c, b)
    return MeshData(vertices=vertices, faces=faces)


def box_overlap(position: np.ndarray, rotation: np.ndarray) -> float:
    """Overlap (m) of the cube and the slab along their least separating axis of the 15
    (faces of both, edge pairs): how far the cube must move to leave the slab."""
    axes_cube = quat_to_matrix(rotation[None])[0]
    center, half = 0.5 * (SLAB_LOW + SLAB_HIGH), 0.5 * (SLAB_HIGH - SLAB_LOW)
    axes = [axes_cube[:, i] for i in range(3)] + list(np.eye(3))
    axes += [np.cross(axes_cube[:, i], np.eye(3)[j]) for i in range(3) for j in range(3)]
    least = np.inf
    for axis in axes:
        length = np.linalg.norm(axis)
        if length < 1e-9:
            continue
        axis = axis / length
        reach = HALF * np.abs(axes_cube.T @ axis).sum() + np.abs(axis) @ half
        least = min(least, reach - abs(float(np.dot(position - center, axis))))
    return float(least)


def spinning_cube(vectorized: bool):
    """The table top over the floor and the cube in its state after the soak's step 1338."""
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    world.set_stage(
        [floor_mesh(20.0, height=-1.45), box_mesh(SLAB_LOW, SLAB_HIGH)], StageAttributes()
    )
    cube = add(world, templates, register_primitive(templates, half=(HALF,) * 3), START[0])
    cube.rotation = mn.Quaternion.from_xyzw(np.array(START[1]))
    cube.linear_velocity, cube.angular_velocity = START[2], START[3]
    return world, cube


@pytest.mark.parametrize("vectorized", [True, False], ids=["batched", "reference"])
def test_a_spinning_cube_does_not_fly_into_a_thin_table_top(vectorized):
    world, cube = spinning_cube(vectorized)
    b, index = world.bodies, cube.object_id
    assert box_overlap(b.body_position[index], b.body_rotation[index]) < -0.05  # apart
    deepest = 0.0
    for _ in range(30):  # 0.24 s of fixed steps
        world.step_physics(0.008)
        deepest = max(deepest, box_overlap(b.body_position[index], b.body_rotation[index]))
    assert deepest < TOLERANCE, f"{deepest * 100:.2f} cm into the table top"


# ------------------------------------------------------------------------------------------
# a cone lying on the floor driven into a thin slab's side (a bed's 3 cm base, 10 cm up)
# ------------------------------------------------------------------------------------------
CONE = "coneSolid_segments_12_halfLen_1.25_rings_1_useTexCoords_false_useTangents_false_capEnd_true"
BASE_LOW = np.array([0.5, 0.10, -0.6])  # the bed base's corners, m: its west side at x = 0.5
BASE_HIGH = np.array([1.5, 0.13, 0.6])


def cone_depths(world, index: int) -> tuple[float, float, float]:
    """How far the cone's hull is in the stage (m): its lowest vertex below the floor, its
    deepest vertex inside the slab (distance to the slab's nearest face), and the deepest
    point of the slab's west edges (y = 0.10 and 0.13, sampled every 5 mm) inside the
    hull (distance to the hull's nearest face plane)."""
    b = world.bodies
    shape = world.collision_objects.shape_entries[index][0][0]
    rotation = quat_to_matrix(b.body_rotation[index][None])[0]
    position = b.body_position[index]
    vertices = shape.hull_vertices @ rotation.T + position
    below = max(0.0, -float(vertices[:, 1].min()))
    inside = np.all((vertices > BASE_LOW) & (vertices < BASE_HIGH), axis=1)
    to_face = np.minimum(vertices - BASE_LOW, BASE_HIGH - vertices).min(axis=1)
    in_slab = float(to_face[inside].max()) if inside.any() else 0.0
    z = np.linspace(BASE_LOW[2], BASE_HIGH[2], 241)
    edge_depth = 0.0
    for y in (BASE_LOW[1], BASE_HIGH[1]):
        edge = np.column_stack([np.full_like(z, BASE_LOW[0]), np.full_like(z, y), z])
        local = (edge - position) @ rotation  # body frame
        depth = (shape.plane_offsets - local @ shape.plane_normals.T).min(axis=1)
        edge_depth = max(edge_depth, float(depth.max()))
    return below, in_slab, edge_depth


def cone_at_the_base(vectorized: bool, yaw: float):
    """A 25 cm cone (10 cm radius) lying on the floor 0.5 m west of the bed base, its axis
    turned ``yaw`` about +Y from +Z (0: its side toward the base; +-pi/2: its base or its
    tip), settled for 0.48 s; returns the world and the cone."""
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    world.set_stage([floor_mesh(5.0), box_mesh(BASE_LOW, BASE_HIGH)], StageAttributes())
    cone = add(world, templates, register_primitive(templates, CONE, half=(0.1,) * 3), [0, 0.12, 0])
    lying = mn.Quaternion.rotation(mn.Rad(np.pi / 2), mn.Vector3(1, 0, 0))
    cone.rotation = mn.Quaternion.rotation(mn.Rad(yaw), mn.Vector3(0, 1, 0)) * lying
    for _ in range(60):
        world.step_physics(0.008)
    return world, cone


@pytest.mark.parametrize("vectorized", [True, False], ids=["batched", "reference"])
@pytest.mark.parametrize("yaw", [0.0, np.pi / 2, -np.pi / 2], ids=["side", "base", "tip"])
def test_a_cone_driven_into_a_thin_slabs_side_stops_at_it(vectorized, yaw):
    """The walls soak's cone wedged under the bed's base: lying on the floor, driven at
    3.2 m/s into the base's 3 cm high side. Its rim vertices are 5 cm apart, so none lies
    in the side's band while its edges cross the slab's edge, and its other vertices rest
    on the floor. Before: no contact held the slab's edge (the job had vertex contacts, so
    it never asked for edge contacts); the slab's edge went 4.2-6.2 cm into the cone, and
    base or tip first the cone passed under the slab, whose top then pressed the vertices
    that crossed it 10.7-13.0 cm below the floor. Now the side the hull crosses without a
    vertex resting on it takes fcl's points with its normal, and a vertex below the slab
    never rests on its top: the cone stops at the side (measured: at most 1.5 cm, 0.9 cm
    below the floor)."""
    world, cone = cone_at_the_base(vectorized, yaw)
    index = cone.object_id
    assert max(cone_depths(world, index)) < 0.005  # resting on the floor, clear of the base
    cone.linear_velocity = [3.2, 0.0, 0.0]
    worst = np.zeros(3)
    for _ in range(90):  # 0.72 s
        world.step_physics(0.008)
        worst = np.maximum(worst, cone_depths(world, index))
    below, in_slab, edge = worst
    assert below < TOLERANCE, f"{below * 100:.2f} cm below the floor"
    assert in_slab < TOLERANCE, f"a vertex {in_slab * 100:.2f} cm inside the slab"
    assert edge < TOLERANCE, f"the slab's edge {edge * 100:.2f} cm inside the cone"


# ------------------------------------------------------------------------------------------
# the batched rules and their plain twins agree
# ------------------------------------------------------------------------------------------
def table_top_world(vectorized: bool):
    """The floor and the table top of the soak's scene with one 0.2 m cube, at rest."""
    world, templates = make_world(floor=False, gravity=(0.0, 0.0, 0.0))
    world.settings.use_vectorized = vectorized
    world.set_stage(
        [floor_mesh(20.0, height=-1.45), box_mesh(SLAB_LOW, SLAB_HIGH)], StageAttributes()
    )
    cube = add(world, templates, register_primitive(templates, half=(HALF,) * 3), START[0])
    return world, cube


def narrow_phase_points(world, vectorized: bool):
    """This step's stage contacts of body 1 on the chosen path: ``(point_a, point_b,
    normal)``, ``(k, 3)`` each."""
    from engine.physics.pipeline.collision_stage import update_world_aabbs
    from engine.physics.pipeline.narrow_phase import narrow_phase
    from engine.physics.pipeline.reference_contacts import pair_contacts

    b, objects = world.bodies, world.collision_objects
    rotation = quat_to_matrix(b.body_rotation[: b.count])
    update_world_aabbs(b, rotation)
    objects.move(b, np.arange(1, b.count), rotation[1:])
    if vectorized:
        _, point_a, point_b, normal, _ = narrow_phase(
            b, objects, world.manifolds, [(0, 1)], rotation
        )
        return point_a, point_b, normal
    contacts = pair_contacts(b, objects, world.manifolds, 0, 1, rotation)
    return tuple(
        np.array([getattr(c, k) for c in contacts]).reshape(-1, 3)
        for k in ("point_a", "point_b", "normal")
    )


def vertices_over_the_slab(world, index: int) -> np.ndarray:
    """World hull vertices of body ``index`` over the slab's footprint (x and z), (k, 3)."""
    b = world.bodies
    vertices = b.shapes[index][0].hull_vertices @ quat_to_matrix(b.body_rotation[index]).T
    vertices = vertices + b.body_position[index]
    footprint = (vertices[:, [0, 2]] > SLAB_LOW[[0, 2]]) & (vertices[:, [0, 2]] < SLAB_HIGH[[0, 2]])
    return vertices[footprint[:, 0] & footprint[:, 1]]


@pytest.mark.parametrize("vectorized", [True, False], ids=["batched", "reference"])
def test_a_vertex_just_below_a_thin_slab_does_not_rest_on_its_top(vectorized):
    """The flight until the cube's highest vertex over the slab's footprint is about the
    speculative reach below the slab's bottom face (1.9-3.5 cm below it, 6-7.5 cm below its
    top, in the top's prism; main: held by the top that deep, +Y). Its way up to the top
    crosses the bottom face: no contact pushes the cube up into the slab."""
    world, cube = spinning_cube(vectorized)
    for _ in range(8):
        world.step_physics(0.008)
        over = vertices_over_the_slab(world, cube.object_id)
        if len(over) and 0.019 < SLAB_LOW[1] - over[:, 1].max() < 0.035:
            break
    else:
        raise AssertionError("the cube's vertices were never just below the slab")
    point_a, point_b, normal = narrow_phase_points(world, vectorized)
    depth = dot(point_a - point_b, normal)
    up = normal[:, 1] > 0.5
    assert (depth[up] <= 0.0).all(), depth[up].tolist()  # nothing pushes it up (main: 6.3 cm)


def test_cube_contacts_at_a_thin_table_top_agree_with_the_reference():
    """The stage-hull rule on both paths for a cube around the table top's front edge, on
    a grid of poses (below, across, inside and above the slab, turned about two axes): the
    same contacts to 1e-12; the grid holds poses with vertex contacts, without (fcl's
    edge points) and with none."""
    world, cube = table_top_world(True)
    kinds = set()
    for y in (-0.86, -0.835, -0.8, -0.75, -0.71, -0.6, -0.585):
        for z in (-0.4, -0.3, -0.22, -0.14):
            for angle in (0.0, 0.5):
                cube.translation = [6.4, y, z]
                turn = mn.Quaternion.rotation(mn.Rad(angle), mn.Vector3(1, 0, 0))
                cube.rotation = mn.Quaternion.rotation(mn.Rad(angle), mn.Vector3(0, 0, 1)) * turn
                batched = narrow_phase_contacts(world, True, keys=True)
                plain = narrow_phase_contacts(world, False, keys=True)
                assert len(batched[2]) == len(plain[2])
                for mine, theirs in zip(batched, plain, strict=True):
                    if len(mine):
                        np.testing.assert_allclose(mine, theirs, atol=1e-12)
                feature = batched[2] & ((1 << RULE_SHIFT) - 1)
                kinds.add("none" if len(feature) == 0 else str(bool(feature.max() >= FCL_FEATURE)))
    assert kinds == {"none", "True", "False"}


@pytest.mark.parametrize("yaw", [0.0, np.pi / 2, -np.pi / 2])
def test_cone_contacts_at_a_thin_slab_agree_with_the_reference(yaw):
    """The whole stage-hull rule (vertex contacts with the way-out test, the crossed side's
    points) on both paths for the cone at the bed base, on a grid of poses: before the
    side, across its edge, half under the slab, turned, sunk a little into the floor; the
    same contacts to 1e-12, and the grid holds poses where the side takes fcl's points."""
    world, cone = cone_at_the_base(True, yaw)
    start, turn = cone.translation, cone.rotation
    side_points = 0
    for dx in (0.0, 0.3, 0.38, 0.42, 0.46, 0.5, 0.56):
        for dy in (-0.008, 0.0, 0.015):
            for roll in (0.0, 0.2):
                cone.translation = start + mn.Vector3(dx, dy, 0.0)
                cone.rotation = mn.Quaternion.rotation(mn.Rad(roll), mn.Vector3(1, 0, 0)) * turn
                batched = narrow_phase_contacts(world, True, keys=True)
                plain = narrow_phase_contacts(world, False, keys=True)
                for mine, theirs in zip(batched, plain, strict=True):
                    np.testing.assert_allclose(mine, theirs, atol=1e-12)
                feature = batched[2] & ((1 << RULE_SHIFT) - 1)
                side_points += int(np.count_nonzero(feature >= FCL_FEATURE))
    assert side_points > 0
