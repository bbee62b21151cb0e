"""PathFinder queries on box geometry: snapping, sampling, obstacles, islands, save/load.

World frame Y up, meters; default NavMeshSettings (0.05 m cells, 0.1 m agent radius).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from navmesh import NavMeshSettings, PathFinder, ShortestPath


@pytest.fixture(scope="module")
def two_rooms():
    """A 6 x 4 m floor at y = 0 and a separate 3 x 3 m floor at y = 1 beside it."""
    import trimesh

    floor = trimesh.creation.box(extents=(6, 0.1, 4))
    floor.apply_translation((3, -0.05, 2))
    deck = trimesh.creation.box(extents=(3, 0.1, 3))
    deck.apply_translation((8.5, 0.95, 2))
    mesh = trimesh.util.concatenate([floor, deck])
    pf = PathFinder()
    pf.build(mesh.vertices, mesh.faces.astype(np.int64), NavMeshSettings())
    return pf


def test_islands_are_ordered_by_area_and_partition_the_mesh(two_rooms):
    pf = two_rooms
    assert pf.num_islands == 2
    areas = [pf.island_area(i) for i in range(pf.num_islands)]
    assert areas[0] > areas[1]
    assert sum(areas) == pytest.approx(pf.navigable_area, rel=1e-12)
    data = pf.navmesh_data
    assert np.array_equal(data.island >= 0, data.navigable)
    assert pf.get_island([3, 0, 2]) == 0 and pf.get_island([8.5, 1.0, 2]) == 1
    assert pf.get_island([30, 0, 2]) == -1


def test_snap_point_projects_down_and_returns_nan_when_nothing_is_near(two_rooms):
    pf = two_rooms
    np.testing.assert_allclose(pf.snap_point([2.0, 0.7, 1.0]), [2.0, 0.0, 1.0], atol=1e-12)
    assert np.all(np.isnan(pf.snap_point([30.0, 0.0, 2.0])))
    off_edge = pf.snap_point([3.0, 0.0, -0.5])  # beside the floor: onto its eroded edge
    assert pf.is_navigable(off_edge) and off_edge[2] > 0.0
    on_deck = pf.snap_point([6.5, 0.0, 2.0], island_index=1)
    assert pf.get_island(on_deck) == 1


def test_is_navigable_checks_height_and_horizontal_offset(two_rooms):
    pf = two_rooms
    assert pf.is_navigable([2.0, 0.0, 2.0])
    assert pf.is_navigable([2.0, 0.45, 2.0])
    assert not pf.is_navigable([2.0, 0.6, 2.0])
    assert pf.is_navigable([2.0, 0.6, 2.0], max_y_delta=1.0)
    assert not pf.is_navigable([3.0, 0.0, -0.5])  # snaps, but moves in x-z


def test_random_points_are_navigable_uniform_and_seeded(two_rooms):
    pf = two_rooms
    pf.seed(7)
    points = np.array([pf.get_random_navigable_point() for _ in range(2000)])
    assert all(pf.is_navigable(p) for p in points[:200])
    on_deck = np.mean(points[:, 1] > 0.5)
    expected = pf.island_area(1) / pf.navigable_area
    assert on_deck == pytest.approx(expected, abs=0.03)  # binomial 3 sigma ~ 0.02
    pf.seed(7)
    again = np.array([pf.get_random_navigable_point() for _ in range(2000)])
    np.testing.assert_array_equal(points, again)
    island_points = [pf.get_random_navigable_point(island_index=1) for _ in range(50)]
    assert all(pf.get_island(p) == 1 for p in island_points)


def test_random_point_near_stays_within_radius(two_rooms):
    pf = two_rooms
    pf.seed(3)
    center = np.array([2.0, 0.0, 2.0])
    for _ in range(100):
        p = pf.get_random_navigable_point_near(center, 0.5)
        assert np.linalg.norm(p - center) < 0.5 and pf.is_navigable(p)
    assert np.all(np.isnan(pf.get_random_navigable_point_near([40.0, 0, 0], 0.5)))


def test_distance_to_closest_obstacle_measures_to_the_boundary(two_rooms):
    pf = two_rooms
    # the floor spans z in [0, 4]; eroded by ledge + radius its boundary is near z = 3.85
    hit = pf.closest_obstacle_surface_point([3.0, 0.0, 3.5], max_search_radius=1.0)
    data = pf.navmesh_data
    column = data.navigable[0, :, int(3.0 / data.cell_size)]
    z_b = data.origin_xz[1] + (np.flatnonzero(column).max() + 1) * data.cell_size
    assert hit.hit_dist == pytest.approx(z_b - 3.5, abs=1e-9)
    np.testing.assert_allclose(hit.hit_pos, [3.0, 0.0, z_b], atol=1e-9)
    np.testing.assert_allclose(hit.hit_normal, [0.0, 0.0, -1.0], atol=1e-9)
    assert pf.distance_to_closest_obstacle([3.0, 0.0, 2.0], 0.5) == 0.5  # none in range
    assert math.isinf(pf.distance_to_closest_obstacle([40.0, 0.0, 2.0]))


def test_island_radius_of_a_rectangle_is_half_its_diagonal(two_rooms):
    pf = two_rooms
    data = pf.navmesh_data
    cells = np.argwhere(data.island[0] == 0)
    extent = (cells.max(axis=0) - cells.min(axis=0)) * data.cell_size  # centre to centre
    assert pf.island_radius([3, 0, 2]) == pytest.approx(np.linalg.norm(extent) / 2, rel=1e-6)
    assert pf.island_radius([40, 0, 2]) == 0.0


def test_topdown_view_shape_and_content(two_rooms):
    pf = two_rooms
    lo, hi = pf.get_bounds()
    view = pf.get_topdown_view(0.1, 0.0)
    assert view.dtype == bool
    assert view.shape == (int((hi[2] - lo[2]) / 0.1), int((hi[0] - lo[0]) / 0.1))
    # pixels at floor height cover island 0 (area within a pixel row/column of the edges)
    assert view.sum() * 0.01 == pytest.approx(pf.island_area(0), rel=0.1)
    islands = pf.get_topdown_island_view(0.1, 1.0)
    assert set(np.unique(islands)) == {-1, 1}


def test_save_load_round_trip(two_rooms, tmp_path):
    pf = two_rooms
    path = tmp_path / "rooms.navmesh"
    assert pf.save_nav_mesh(path) and path.is_file()
    loaded = PathFinder()
    assert loaded.load_nav_mesh(path) and loaded.is_loaded
    assert loaded.num_islands == pf.num_islands
    assert loaded.navigable_area == pf.navigable_area
    for a, b in zip(loaded.get_bounds(), pf.get_bounds(), strict=True):
        np.testing.assert_array_equal(a, b)
    assert loaded.nav_mesh_settings == pf.nav_mesh_settings
    for finder in (pf, loaded):
        finder.seed(11)
    np.testing.assert_array_equal(
        pf.get_random_navigable_point(), loaded.get_random_navigable_point()
    )
    query = dict(requested_start=[0.5, 0, 0.5], requested_end=[5.5, 0, 3.5])
    a, b = ShortestPath(**query), ShortestPath(**query)
    assert pf.find_path(a) and loaded.find_path(b)
    assert a.geodesic_distance == b.geodesic_distance


def test_load_errors(tmp_path):
    pf = PathFinder()
    with pytest.raises(FileNotFoundError, match="missing"):
        pf.load_nav_mesh(tmp_path / "missing.navmesh")
    garbage = tmp_path / "garbage.navmesh"
    garbage.write_bytes(b"MSET not a navmesh")
    with pytest.warns(UserWarning, match="load_nav_mesh"):
        assert not pf.load_nav_mesh(garbage) and not pf.is_loaded
    assert not pf.save_nav_mesh(tmp_path / "empty.navmesh")


def test_unloaded_pathfinder_raises():
    pf = PathFinder()
    assert not pf.is_loaded
    with pytest.raises(RuntimeError, match="not loaded"):
        pf.snap_point([0, 0, 0])
    with pytest.raises(RuntimeError, match="not loaded"):
        pf.try_step([0, 0, 0], [1, 0, 0])


def test_bad_query_arguments(two_rooms):
    pf = two_rooms
    with pytest.raises(ValueError, match="point"):
        pf.snap_point([np.nan, 0, 0])
    with pytest.raises(TypeError, match="pt"):
        pf.is_navigable("abc")
    with pytest.raises(ValueError, match="island_index"):
        pf.get_random_navigable_point(island_index=5)
    with pytest.raises(ValueError, match="radius"):
        pf.get_random_navigable_point_near([1, 0, 1], -1.0)
    with pytest.raises(ValueError, match="meters_per_pixel"):
        pf.get_topdown_view(0.0, 0.0)
    with pytest.raises(TypeError, match="seed"):
        pf.seed(1.5)
    with pytest.raises(TypeError, match="settings"):
        pf.build(np.eye(3), np.array([[0, 1, 2]]), settings={"cellSize": 0.1})
