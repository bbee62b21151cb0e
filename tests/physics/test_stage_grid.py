"""The stage triangle grid (stage_grid.py) against brute force and against fcl.

The grid must name exactly the triangles a brute-force AABB test names (it is only an
acceleration), every triangle fcl's BVH reports for a body's probe, and the stage contacts
made from its triangles must equal those made from fcl's.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, floor_mesh, make_world, register_primitive

from engine import mn
from engine.attributes import StageAttributes
from engine.physics.collision.contact_helpers import fcl_raw_contacts
from engine.physics.collision.stage_grid import StageGrid, candidate_triangles_reference, stage_grid
from engine.physics.core import settings
from engine.physics.core.quaternions import quat_to_matrix
from engine.physics.reference.reference_pairs import stage_polyhedron_contacts
from engine.scene.assets import load_meshes

FLOOR = -1.45  # the demo apartment's floor height


@pytest.fixture(scope="module")
def apartment_triangles(demo_data) -> np.ndarray:
    meshes = load_meshes(demo_data / "scene_datasets" / "demo" / "apartment.glb")
    return np.concatenate([np.asarray(m.vertices)[np.asarray(m.faces)] for m in meshes])


def random_boxes(triangles: np.ndarray, n: int, seed: int, size: float = 0.3):
    """``n`` query boxes ``(lo, hi)`` of side up to ``size`` around points spread over the
    stage's bounds and a little beyond them (some boxes lie outside the grid)."""
    rng = np.random.default_rng(seed)
    lo, hi = triangles.reshape(-1, 3).min(0) - 1.0, triangles.reshape(-1, 3).max(0) + 1.0
    center = rng.uniform(lo, hi, size=(n, 3))
    half = rng.uniform(0.0, size / 2, size=(n, 3))
    return center - half, center + half


@pytest.mark.parametrize("cell", [0.25, 1.0, 4.0])
def test_grid_names_exactly_the_triangles_of_the_brute_force_aabb_test(apartment_triangles, cell):
    grid = StageGrid.build(apartment_triangles, cell)
    lo, hi = random_boxes(apartment_triangles, 400, seed=1)
    box, triangle = grid.candidates(lo, hi)
    expected = candidate_triangles_reference(apartment_triangles, lo, hi)
    assert sum(len(ids) for ids in expected) > 100  # the boxes do meet triangles
    for k, ids in enumerate(expected):
        np.testing.assert_array_equal(triangle[box == k], ids)


def test_grid_of_a_huge_stage_grows_its_cells_under_the_cell_limit():
    v = np.array([[-1e4, 0, -1e4], [1e4, 0, -1e4], [1e4, 0, 1e4]], dtype=np.float64)
    grid = StageGrid.build(v[None], cell=0.5)
    assert grid.shape[0] * grid.shape[1] <= settings.STAGE_GRID_MAX_CELLS
    assert grid.cell >= 0.5 * 2 * 1e4 / 1000  # doubled until 2e4 m spans <= 1000 cells
    box, triangle = grid.candidates(np.array([[0.0, -0.1, -5e3]]), np.array([[0.1, 0.1, -4e3]]))
    assert triangle.tolist() == [0] and box.tolist() == [0]


def test_grid_query_of_no_box_and_of_a_box_beside_the_stage_is_empty():
    grid = StageGrid.build(floor_mesh(1.0).vertices[floor_mesh(1.0).faces])
    box, triangle = grid.candidates(np.zeros((0, 3)), np.zeros((0, 3)))
    assert len(box) == len(triangle) == 0
    box, triangle = grid.candidates(np.array([[5.0, -1.0, 5.0]]), np.array([[6.0, 1.0, 6.0]]))
    assert len(triangle) == 0


def apartment_box_world(demo_data, pose_seed: int):
    """The apartment stage and a 0.2 m box at a random pose near its floor or table."""
    meshes = load_meshes(demo_data / "scene_datasets" / "demo" / "apartment.glb")
    world, templates = make_world(floor=False)
    world.set_stage(meshes, StageAttributes())
    rng = np.random.default_rng(pose_seed)
    over_table = pose_seed % 2 == 0
    x, z = (
        (rng.uniform(2.2, 2.9), rng.uniform(-0.45, 0.55))
        if over_table
        else rng.uniform(1.0, 2.0, 2)
    )
    y = (-1.05 if over_table else FLOOR) + rng.uniform(0.05, 0.2)
    box = add(world, templates, register_primitive(templates), [x, y, z])
    q = rng.normal(size=4)
    box.rotation = mn.Quaternion.from_xyzw(q / np.linalg.norm(q))
    return world, world.bodies.count - 1  # the box's body index


@pytest.mark.parametrize("pose_seed", range(12))
def test_grid_holds_every_triangle_fcl_reports_and_gives_fcls_contacts(demo_data, pose_seed):
    world, body = apartment_box_world(demo_data, pose_seed)
    world.perform_discrete_collision_detection()  # AABBs and fcl objects at the pose
    b, objects = world.bodies, world.collision_objects
    rotation = quat_to_matrix(b.body_rotation[body])
    objects.move(b, np.array([body]), rotation[None])  # with its probe
    found = fcl_raw_contacts(objects.shape_objects[0][0], objects.probe_objects[body][0])
    from_fcl = sorted({int(r.b1) for r in found if r.b1 >= 0})
    grown = settings.STAGE_NEAR_DISTANCE
    stage = b.shapes[0][0]
    box, near = stage_grid(stage).candidates(
        b.body_aabb_min[[body]] - grown, b.body_aabb_max[[body]] + grown
    )
    assert set(from_fcl) <= set(near.tolist())
    pose = (rotation, b.body_position[body])
    no_cache: list = []
    with_fcl = stage_polyhedron_contacts(stage, b.shapes[body][0], pose, from_fcl, no_cache)
    with_grid = stage_polyhedron_contacts(stage, b.shapes[body][0], pose, near.tolist(), no_cache)
    assert len(with_grid) == len(with_fcl)
    for mine, theirs in zip(with_grid, with_fcl, strict=True):
        np.testing.assert_allclose(mine.point_b, theirs.point_b, atol=1e-12)
        np.testing.assert_allclose(mine.normal, theirs.normal, atol=1e-12)


def test_vertex_in_a_floor_wall_corner_gets_both_surfaces_on_both_paths():
    """A 0.2 m box pressed 1 cm into a floor and 5 mm into a wall (x = 0.5, normal -X): its
    four vertices inside the wall keep the wall's contact (their shallowest) and the two on
    the floor also the floor's (before, each vertex kept only its shallowest surface, and a
    body driven into a corner sank into the floor), on the batched and the reference path
    alike (same points, same order)."""
    from engine.physics.pipeline.collision_stage import update_world_aabbs
    from engine.physics.pipeline.narrow_phase import narrow_phase
    from engine.physics.pipeline.reference_contacts import pair_contacts
    from engine.scene.assets import MeshData

    wall = MeshData(
        vertices=np.array([[0.5, -1, -2], [0.5, 2, -2], [0.5, 2, 2], [0.5, -1, 2]], dtype=float),
        faces=np.array([[0, 1, 2], [0, 2, 3]]),  # normal -X, towards the box; below the floor too
    )
    world, templates = make_world(floor=False)
    world.set_stage([floor_mesh(), wall], StageAttributes())
    add(world, templates, register_primitive(templates), [0.5 - 0.095, 0.09, 0.0])
    b, objects = world.bodies, world.collision_objects
    rotation = quat_to_matrix(b.body_rotation[: b.count])
    update_world_aabbs(b, rotation)
    objects.move(b, np.arange(1, b.count), rotation[1:])
    _, point_a, point_b, normal, _ = narrow_phase(b, objects, world.manifolds, [(0, 1)], rotation)
    reference = pair_contacts(b, objects, world.manifolds, 0, 1, rotation)
    assert len(reference) == len(normal)
    for contact, a, p, n in zip(reference, point_a, point_b, normal, strict=True):
        np.testing.assert_allclose(contact.point_a, a, atol=1e-12)
        np.testing.assert_allclose(contact.point_b, p, atol=1e-12)
        np.testing.assert_allclose(contact.normal, n, atol=1e-12)
    depth = ((point_a - point_b) * normal).sum(axis=1)
    inside = point_b[:, 0] > 0.5  # the four vertices inside the wall
    up, back = np.isclose(normal[:, 1], 1.0), np.isclose(normal[:, 0], -1.0)
    assert np.count_nonzero(inside & back) == 4 and np.count_nonzero(inside & up) == 2
    np.testing.assert_allclose(depth[inside & back], 0.005, atol=1e-9)
    np.testing.assert_allclose(depth[up], 0.01, atol=1e-9)  # all four bottom vertices
    assert np.count_nonzero(up) == 4


def _tilted_square(degrees: float) -> np.ndarray:
    """Two triangles of a 2 m square turned ``degrees`` about the x axis, ``(2, 3, 3)``."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    corners = np.array([[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]])
    turned = corners @ np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])
    return turned[[[0, 2, 1], [0, 3, 2]]]


def test_a_stage_is_corner_free_only_when_no_two_triangles_could_form_a_corner():
    floor = _tilted_square(0.0)
    # 45.6 degrees apart is a corner (STAGE_CORNER_COSINE 0.7); below half of it, either
    # way of winding, every pair is safely less than that apart
    half = np.degrees(0.5 * np.arccos(settings.STAGE_CORNER_COSINE))
    assert StageGrid.build(floor).corner_free
    assert StageGrid.build(np.concatenate([floor, _tilted_square(half - 0.5)])).corner_free
    assert StageGrid.build(np.concatenate([floor, _tilted_square(180.0 - 10.0)])).corner_free
    assert not StageGrid.build(np.concatenate([floor, _tilted_square(half + 0.5)])).corner_free
    assert not StageGrid.build(np.concatenate([floor, _tilted_square(90.0)])).corner_free
    degenerate = np.concatenate([floor, np.zeros((1, 3, 3))])
    assert not StageGrid.build(degenerate).corner_free


def test_the_apartment_has_corners_and_the_benchmark_floor_has_none(apartment_triangles):
    assert not StageGrid.build(apartment_triangles).corner_free
    vertices, faces = floor_mesh(20.0).vertices, floor_mesh(20.0).faces
    assert StageGrid.build(np.asarray(vertices)[np.asarray(faces)].astype(float)).corner_free
