"""Hull vertices in a corner of the stage (a floor meeting a wall): which surfaces hold them.

A box beside a wall (x = 0.5, facing -X) on a floor (y = 0), on the batched and the
reference path alike: a vertex in front of both surfaces is held by the nearer one; a
vertex pressed into both keeps both contacts through the manifold merge, and the
manifold's four slots keep the floor's supporting polygon beside the wall's deepest point.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, floor_mesh, make_world, register_primitive

from engine import mn
from engine.attributes import StageAttributes
from engine.physics.core.quaternions import quat_to_matrix
from engine.scene.assets import MeshData

WALL_X = 0.5
HALF = 0.1  # the box's half side, m


def corner_world(vectorized: bool, gap_floor: float, gap_wall: float):
    """A world with the floor, the wall and a 0.2 m box whose bottom is ``gap_floor`` above
    the floor and whose side is ``gap_wall`` before the wall (negative: inside)."""
    wall = MeshData(
        vertices=np.array(
            [[WALL_X, -1, -2], [WALL_X, 2, -2], [WALL_X, 2, 2], [WALL_X, -1, 2]], dtype=float
        ),
        faces=np.array([[0, 1, 2], [0, 2, 3]]),  # normal -X, towards the box
    )
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    world.set_stage([floor_mesh(), wall], StageAttributes())
    position = [WALL_X - HALF - gap_wall, HALF + gap_floor, 0.0]
    box = add(world, templates, register_primitive(templates, half=(HALF,) * 3), position)
    return world, box


def narrow_phase_contacts(world, vectorized: bool, keys: bool = False):
    """This step's stage contacts of body 1 on the chosen path: ``(point_b, normal)``, and
    their contact keys with ``keys``."""
    from engine.physics.pipeline.collision_stage import update_world_aabbs
    from engine.physics.pipeline.narrow_phase import narrow_phase
    from engine.physics.pipeline.reference_contacts import pair_contacts

    b, objects = world.bodies, world.collision_objects
    rotation = quat_to_matrix(b.body_rotation[: b.count])
    update_world_aabbs(b, rotation)
    objects.move(b, np.arange(1, b.count), rotation[1:])
    if vectorized:
        _, _, point_b, normal, key = narrow_phase(b, objects, world.manifolds, [(0, 1)], rotation)
        return (point_b, normal, key) if keys else (point_b, normal)
    contacts = pair_contacts(b, objects, world.manifolds, 0, 1, rotation)
    point_b, normal = (
        np.array([c.point_b for c in contacts]),
        np.array([c.normal for c in contacts]),
    )
    if keys:
        return point_b, normal, np.array([c.feature for c in contacts], dtype=np.int64)
    return point_b, normal


def test_a_vertex_in_front_of_a_floor_and_a_wall_is_held_by_the_nearer():
    """The box's bottom 1.6 mm above the floor and its side 1.1 cm before the wall (both
    within the 2 cm speculative reach): its two bottom vertices by the wall face both
    surfaces, and the floor, which they meet first, holds them (they kept the farther
    wall: a cone's tip 1.6 mm above a bed's top and 1.1 cm before the mattress's side went
    4.5 cm into the top in the next step). The same contacts on both paths."""
    world, _ = corner_world(True, 0.0016, 0.011)
    batched = narrow_phase_contacts(world, True)
    plain = narrow_phase_contacts(world, False)
    for mine, theirs in zip(batched, plain, strict=True):
        np.testing.assert_allclose(mine, theirs, atol=1e-12)
    point_b, normal = batched
    up, back = np.isclose(normal[:, 1], 1.0), np.isclose(normal[:, 0], -1.0)
    assert np.count_nonzero(up) == 4  # the four bottom vertices on the floor
    assert np.count_nonzero(back) == 2  # only the top two by the wall on the wall
    assert (point_b[back, 1] > 0.1).all()


@pytest.mark.parametrize("vectorized", [True, False])
def test_a_vertex_pressed_into_floor_and_wall_keeps_both_in_the_manifold(vectorized):
    """The box 1 cm into the floor and 3 cm into the wall: the two bottom vertices inside
    the wall have a floor and a (deeper) wall contact at one point. The merge dropped the
    floor one as a duplicate of the deeper point, and the four slots then kept three wall
    points and one floor point, so the body could tip about it into the floor (a cone's
    tip struck into a wall sank 4 cm). Now the manifold keeps the floor's supporting
    polygon, a vertex inside the wall among it, and the wall's deepest point."""
    world, box = corner_world(vectorized, -0.01, -0.03)
    world.step_physics(0.008)
    store = world.manifolds
    row = store.row((0, box.object_id))
    count = int(store.count[row])
    normals = store.normal_local[row, :count]  # the stage's frame is the world's
    stage_points = store.local_a[row, :count]
    up, back = normals[:, 1] > 0.99, normals[:, 0] < -0.99
    assert count == 4 and np.count_nonzero(up) == 3 and np.count_nonzero(back) == 1
    assert (stage_points[up, 0] > WALL_X).any()  # a floor point under a vertex in the wall


SLAB_LOW, SLAB_HIGH = 0.10, 0.13  # a 3 cm slab 10 cm above the floor (a bed's base)


def slab_mesh() -> MeshData:
    """A closed box x in [0, 0.6], y in [SLAB_LOW, SLAB_HIGH], z in [-0.4, 0.4], wound
    outward (counter-clockwise seen from outside)."""
    lo, hi = np.array([0.0, SLAB_LOW, -0.4]), np.array([0.6, SLAB_HIGH, 0.4])
    corners = np.array([[(lo, hi)[i >> k & 1][k] for k in range(3)] for i in range(8)])
    faces = np.array(
        [
            [0, 4, 6], [0, 6, 2],  # x = lo (its normal -X)
            [1, 3, 7], [1, 7, 5],  # x = hi
            [0, 1, 5], [0, 5, 4],  # y = lo (down)
            [2, 6, 7], [2, 7, 3],  # y = hi (up)
            [0, 2, 3], [0, 3, 1],  # z = lo
            [4, 5, 7], [4, 7, 6],  # z = hi
        ]
    )  # fmt: skip
    return MeshData(vertices=corners.astype(float), faces=faces)


@pytest.mark.parametrize("vectorized", [True, False])
def test_a_vertex_beside_a_thin_slab_below_its_top_is_not_pushed_into_its_side(vectorized):
    """A 0.2 m box whose center is 1 cm past the west side (x = 0) of a 3 cm slab and above
    it, its bottom 5 mm below the slab's top: the bottom vertices beyond the side are in
    the air, 9 cm before the side. The side's outward way was the center's side, so they
    counted as 9 cm behind it and were pushed into the slab (a cone sliding off a bed's
    base this way ended wedged under it, 10 cm below the floor, in the walls soak). The
    center is above that low face, so its front decides: no contact on the side, the
    vertices over the slab rest on its top (before: 6 contacts, the two vertices in the air
    each held by the side and, as in a corner, by the top); the same on both paths. The
    box then tips off the edge onto the floor."""
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    world.set_stage([floor_mesh(), slab_mesh()], StageAttributes())
    position = [0.01, SLAB_HIGH + HALF - 0.005, 0.0]
    add(world, templates, register_primitive(templates, half=(HALF,) * 3), position)
    point_b, normal = narrow_phase_contacts(world, vectorized)
    batched = narrow_phase_contacts(world, not vectorized)
    for mine, theirs in zip((point_b, normal), batched, strict=True):
        np.testing.assert_allclose(mine, theirs, atol=1e-12)
    assert len(normal) == 2 and np.allclose(normal, [0.0, 1.0, 0.0])  # the top only
    assert (point_b[:, 0] > 0.0).all()  # under the vertices over the slab
    deepest = 0.0  # m, the deepest any box vertex gets into the slab or the floor
    for _ in range(60):  # it tips off the edge onto the floor
        world.step_physics(1.0 / 60.0)
        deepest = max(deepest, slab_or_floor_depth(world))
    assert deepest < 0.02


def slab_or_floor_depth(world) -> float:
    """How deep (m) body 1's deepest hull vertex is in the slab (its way out: the nearest
    face) or below the floor, 0 when outside both."""
    b = world.bodies
    vertices = b.shapes[1][0].hull_vertices @ quat_to_matrix(b.body_rotation[1]).T
    vertices = vertices + b.body_position[1]
    lo, hi = np.array([0.0, SLAB_LOW, -0.4]), np.array([0.6, SLAB_HIGH, 0.4])
    inside = np.minimum(vertices - lo, hi - vertices).min(axis=1)  # > 0: in the slab
    return float(max(0.0, inside.max(), -vertices[:, 1].min()))


def test_center_decides_agrees_with_its_reference():
    """The batched rule choosing when the body's center decides a wall's side, and its
    plain twin, on a grid of heights (level or not, the plane near or clear of the
    center); and the two hand cases: a thin slab's side 1 cm from the center of a 0.2 m
    body whose center is above it (not decided: the front) and a skirting board's back 10
    cm from the center (decided: the center's side)."""
    from engine.physics.collision.contact_helpers import center_decides
    from engine.physics.reference.reference_pairs import center_decides_reference

    values = np.array([-0.2, -0.06, -0.04, -0.01, 0.0, 0.01, 0.04, 0.06, 0.2])
    level, center, high, low = (
        a.ravel() for a in np.meshgrid([False, True], values, values, -values)
    )
    batched = center_decides(level, center, high, low)
    plain = [center_decides_reference(*case) for case in zip(level, center, high, low, strict=True)]
    np.testing.assert_array_equal(batched, plain)
    assert not center_decides(
        np.array([False]), np.array([-0.01]), np.array([0.09]), np.array([-0.11])
    )[0]
    assert center_decides(np.array([False]), np.array([-0.1]), np.array([0.01]), np.array([-0.19]))[
        0
    ]


def board_and_wall() -> list[MeshData]:
    """A 10 cm wall box (z in [2.5, 2.6]) with a 15 mm, 10 cm high skirting board in front
    of it (z in [2.485, 2.5]): the board's back and the wall's face share the plane z = 2.5,
    facing each other; both boxes wound outward."""
    meshes = []
    for lo, hi in (([-2.0, 0.0, 2.5], [2.0, 2.0, 2.6]), ([-2.0, 0.0, 2.485], [2.0, 0.1, 2.5])):
        box = slab_mesh()
        unit = (box.vertices - [0.0, SLAB_LOW, -0.4]) / [0.6, SLAB_HIGH - SLAB_LOW, 0.8]
        meshes.append(MeshData(vertices=lo + unit * (np.array(hi) - lo), faces=box.faces))
    return meshes


@pytest.mark.parametrize("vectorized", [True, False])
def test_a_vertex_inside_a_skirting_board_is_not_pushed_into_the_wall(vectorized):
    """A 0.2 m box turned 45 degrees about x, its center 4 mm before the board's back
    (z = 2.5) and 5 cm above the board's top, one edge inside the board nearer its back
    than its front. The center is
    above the board's back and near its plane, but that face is backed by the wall's face
    (its front is inside the wall): it keeps the side of the body's center and pushes
    nothing into the wall (a rule taking its front lost two cones through the wall in the
    walls soak); the same contacts on both paths."""
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    world.set_stage([floor_mesh(), *board_and_wall()], StageAttributes())
    box = add(world, templates, register_primitive(templates, half=(HALF,) * 3), [0, 0.15, 2.496])
    box.rotation = mn.Quaternion.rotation(mn.Deg(45.0), mn.Vector3.x_axis())
    point_b, normal = narrow_phase_contacts(world, vectorized)
    batched = narrow_phase_contacts(world, not vectorized)
    for mine, theirs in zip((point_b, normal), batched, strict=True):
        np.testing.assert_allclose(mine, theirs, atol=1e-12)
    assert len(normal) > 0 and (normal[:, 2] < 0.5).all()  # none toward the wall
