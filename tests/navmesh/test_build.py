"""Build pipeline against geometric truths (docs/physics.md, validation).

Geometry: boxes in the world frame, Y up, meters; default NavMeshSettings (cell 0.05 m,
agent radius 0.1 m, height 1.5 m, max climb 0.2 m) unless stated.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from navmesh import NavMeshSettings, build_navmesh

CELL = 0.05  # default cell size, meters: the resolution every tolerance below is stated in


def cell_centers(data):
    nz, nx = data.floor.shape[1:]
    x = data.origin_xz[0] + (np.arange(nx) + 0.5) * data.cell_size
    z = data.origin_xz[1] + (np.arange(nz) + 0.5) * data.cell_size
    return np.meshgrid(x, z)  # (nz, nx) each


def distance_to_rectangle(x, z, lo, hi):
    """XZ distance from points to the axis-aligned rectangle [lo, hi] (0 inside)."""
    dx = np.maximum(np.maximum(lo[0] - x, 0.0), x - hi[0])
    dz = np.maximum(np.maximum(lo[1] - z, 0.0), z - hi[1])
    return np.hypot(dx, dz)


def test_box_obstacle_is_dilated_by_agent_radius_within_one_cell(geometry):
    floor = geometry.box((-3, -0.1, -3), (3, 0.0, 3))
    lo, hi = (0.33, -0.77), (1.21, 0.41)  # obstacle footprint, unaligned with the grid
    obstacle = geometry.box((lo[0], 0.0, lo[1]), (hi[0], 1.0, hi[1]))
    pf = geometry.build(floor, obstacle)
    data = pf.navmesh_data
    x, z = cell_centers(data)
    on_floor = np.any(data.navigable & (np.abs(data.floor) < 1e-6), axis=0)
    d = distance_to_rectangle(x, z, lo, hi)
    interior = (np.abs(x) < 2.5) & (np.abs(z) < 2.5)  # away from the floor's own edge
    radius = 0.1
    # expected mask = floor minus obstacle dilated by the radius, within one cell
    assert np.all(on_floor[interior & (d > radius + CELL)])
    assert not np.any(on_floor[interior & (d < radius - CELL)])
    assert pf.num_islands == 1  # the 1 m^2 box top is under region_min_size^2 cells


def test_floor_is_one_island_with_expected_area(geometry):
    pf = geometry.build(geometry.box((0, -0.1, 0), (4, 0, 3)), filter_ledge_spans=False)
    # the 4 x 3 m floor eroded by 0.1 m on every side
    np.testing.assert_allclose(pf.navigable_area, 3.8 * 2.8, rtol=1e-9)
    assert pf.num_islands == 1


def stairs(geometry, riser):
    """Floor for x in [0, 3] at y = 0 and a tread for x in [3, 6] at y = riser, 4 m deep."""
    return geometry.build(
        geometry.box((0, -0.1, 0), (3, 0, 4)), geometry.box((3, -0.1, 0), (6, riser, 4))
    )


@pytest.mark.parametrize(("riser", "climbable"), [(0.15, True), (0.25, False)])
def test_risers_up_to_max_climb_are_climbable(geometry, riser, climbable):
    pf = stairs(geometry, riser)
    low, high = np.array([1.5, 0.0, 2.0]), np.array([4.5, riser, 2.0])
    assert pf.is_navigable(low) and pf.is_navigable(high)
    assert (pf.get_island(low) == pf.get_island(high)) == climbable
    assert pf.num_islands == (1 if climbable else 2)


@pytest.mark.parametrize(("ceiling", "blocked"), [(1.4, True), (1.6, False)])
def test_low_ceiling_blocks_a_taller_agent(geometry, ceiling, blocked):
    floor = geometry.box((0, -0.1, 0), (6, 0, 4))
    slab = geometry.box((3, ceiling, 0), (6, ceiling + 0.1, 4))  # covers x in [3, 6]
    pf = geometry.build(floor, slab)
    under = np.array([4.5, 0.0, 2.0])
    assert pf.is_navigable([1.5, 0.0, 2.0])
    assert pf.is_navigable(under) != blocked


def test_platform_over_floor_gives_two_layers(geometry):
    floor = geometry.box((0, -0.1, 0), (6, 0, 6))
    deck = geometry.box((1, 2.0, 1), (5, 2.1, 5))  # 2 m above the floor: both walkable
    pf = geometry.build(floor, deck)
    data = pf.navmesh_data
    assert data.shape[0] == 2
    assert pf.is_navigable([3, 0.0, 3]) and pf.is_navigable([3, 2.1, 3])
    assert pf.get_island([3, 0.0, 3]) != pf.get_island([3, 2.1, 3])
    np.testing.assert_allclose(pf.snap_point([3, 1.9, 3])[1], 2.1, atol=1e-9)
    np.testing.assert_allclose(pf.snap_point([3, 0.3, 3])[1], 0.0, atol=1e-9)


def test_steep_ramp_is_not_walkable_gentle_ramp_is(geometry):
    for slope_deg, walkable in [(30.0, True), (60.0, False)]:
        ramp = geometry.box((-1, -0.05, 0), (1, 0.0, 3))
        ramp.apply_transform(_rotation_x(np.radians(slope_deg)))
        pf = geometry.build(ramp, filter_ledge_spans=False, region_min_size=0.0)
        assert (pf.num_islands > 0) == walkable


def _rotation_x(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def test_build_is_deterministic(geometry):
    vertices, faces = geometry.mesh_arrays(
        geometry.box((0, -0.1, 0), (4, 0, 4)), geometry.box((1, 0, 1), (2, 1, 2))
    )
    a = build_navmesh(vertices, faces, NavMeshSettings())
    b = build_navmesh(vertices, faces, NavMeshSettings())
    for name in ("floor", "navigable", "links", "island"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


@pytest.mark.parametrize(
    ("vertices", "faces", "error", "match"),
    [
        (np.zeros((4, 2)), np.array([[0, 1, 2]]), ValueError, "vertices"),
        (np.full((3, 3), np.nan), np.array([[0, 1, 2]]), ValueError, "NaN"),
        (np.eye(3), np.array([[0, 1, 5]]), ValueError, "faces"),
        (np.eye(3), np.array([[0.0, 1.0, 2.0]]), TypeError, "faces"),
        (np.eye(3), np.zeros((0, 3), int), ValueError, "faces"),
    ],
)
def test_bad_mesh_raises_naming_the_input(vertices, faces, error, match):
    with pytest.raises(error, match=match):
        build_navmesh(vertices, faces, NavMeshSettings())


def test_failed_build_keeps_the_previous_navmesh(geometry):
    pf = geometry.build(geometry.box((0, -0.1, 0), (4, 0, 4)))
    area = pf.navigable_area
    bad = NavMeshSettings()
    bad.cell_size = -1.0
    with pytest.raises(ValueError, match="cell_size"):
        pf.build(*geometry.mesh_arrays(geometry.box((0, 0, 0), (1, 1, 1))), bad)
    assert pf.is_loaded and pf.navigable_area == area


def test_floor_under_a_high_shelf_stays_walkable_in_a_scene_taller_than_deep(geometry):
    # a 4 x 0.6 m floor under a shelf 2.9 m up: the scene is 3 m tall but only 0.6 m deep, so
    # the heights of one column span more than the z extent; the floor keeps its 2.9 m
    # clearance (> 1.5 m agent height) and all of its eroded area
    pf = geometry.build(
        geometry.box((0, -0.1, 0), (4, 0, 0.6)),
        geometry.box((1, 2.9, 0), (3, 3.0, 0.6)),
        filter_ledge_spans=False,
    )
    assert pf.is_navigable([2.0, 0.0, 0.3])  # under the shelf
    np.testing.assert_allclose(pf.navigable_area, 3.8 * 0.4, rtol=1e-9)
    assert pf.num_islands == 1


def test_a_low_steep_ridge_above_the_floor_does_not_cut_the_navmesh(geometry):
    # Recast's low-hanging-obstacle filter: a ridge with 70 degree flanks (not walkable on
    # its own) whose top (0.16 m) lies within max_climb = 0.2 m above the walkable floor
    # below it becomes walkable, so the floor stays one whole region: the 6 x 4 m floor
    # eroded by 0.1 m on every side. (cell_height 0.02 m keeps the ridge, 6 cm above the
    # floor, a separate span.)
    height, half_width = 0.1, 0.1 * np.tan(np.radians(20.0))
    section = [(-half_width, 0.0), (half_width, 0.0), (0.0, height)]
    vertices = np.array([[x, y, z] for z in (0.0, 2.0) for x, y in section]) + (3.0, 0.06, 1.0)
    faces = [[0, 2, 1], [3, 4, 5], [0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [2, 0, 3], [2, 3, 5]]
    ridge = trimesh.Trimesh(vertices, np.array(faces), process=False)
    pf = geometry.build(
        geometry.box((0, -0.1, 0), (6, 0, 4)), ridge, cell_height=0.02, filter_ledge_spans=False
    )
    np.testing.assert_allclose(pf.navigable_area, 5.8 * 3.8, rtol=1e-9)
    assert pf.num_islands == 1
    assert pf.is_navigable([3.0, 0.16, 2.0])  # on the ridge
