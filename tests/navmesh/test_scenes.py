"""Habitat's PathFinder test behaviours on navmeshes built from the shared test scenes.

``simple_room.glb`` is a Z-up asset (world = (x, z, -y)); ``stage_floor1.glb`` is Y-up with
scale 2 (their stage configs). Ported from Habitat-sim ``PathFinderTest.cpp``
(tryStepNoSliding, multiGoalPath) and ``tests/test_snap_point.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from navmesh import MultiGoalShortestPath, NavMeshSettings, PathFinder, ShortestPath


def test_simple_room_navmesh_has_floor_and_furniture_islands(simple_room):
    pf = simple_room
    assert pf.is_loaded and pf.num_islands >= 2
    # the floor (about 10.5 x 10.8 m minus furniture and edges) is the largest island
    assert 90.0 < pf.island_area(0) < 113.0
    lo, hi = pf.get_bounds()
    np.testing.assert_allclose(lo[[0, 2]], [-5.247, -5.449], atol=1e-3)
    np.testing.assert_allclose(hi[[0, 2]], [5.280, 5.398], atol=1e-3)


def test_no_sliding_steps_keep_direction_within_one_degree(simple_room):
    pf = simple_room
    pf.seed(0)
    step = np.array([0.0, 0.0, -1.0])
    n_checked = 0
    for _ in range(30):
        pos = pf.get_random_navigable_point()
        for _ in range(10):
            actual = pf.try_step_no_sliding(pos, pos + step)
            assert pf.is_navigable(actual)
            moved = (actual - pos)[[0, 2]]
            if moved @ moved < 1e-5:  # Habitat: unreliable for tiny moves
                break
            cos_angle = moved @ step[[0, 2]] / np.linalg.norm(moved)
            assert np.degrees(np.arccos(min(1.0, cos_angle))) < 1.0
            n_checked += 1
            pos = actual
    assert n_checked > 30


def test_snapped_points_are_navigable(simple_room):
    pf = simple_room
    pf.seed(1)
    rng = np.random.default_rng(1)
    n_snapped = 0
    for _ in range(300):
        pt = pf.get_random_navigable_point() + rng.uniform([-10, -2.5, -10], [10, 2.5, 10])
        snapped = pf.snap_point(pt)
        if np.isnan(snapped[0]):
            continue
        assert pf.is_navigable(snapped), f"{pt} -> {snapped}"
        n_snapped += 1
    assert n_snapped > 50


def test_multi_goal_distance_is_min_of_single_paths(simple_room):
    pf = simple_room
    pf.seed(0)
    for _ in range(10):
        start = pf.get_random_navigable_point(island_index=0)
        ends = [pf.get_random_navigable_point(island_index=0) for _ in range(5)]
        multi = MultiGoalShortestPath(requested_start=start, requested_ends=ends)
        assert pf.find_path(multi)
        singles = []
        for end in ends:
            path = ShortestPath(requested_start=start, requested_end=end)
            assert pf.find_path(path)
            assert path.geodesic_distance >= np.linalg.norm(end - start) - 1e-9
            singles.append(path.geodesic_distance)
        assert multi.geodesic_distance == pytest.approx(min(singles), rel=1e-9)
        assert multi.closest_end_point_index == int(np.argmin(singles))


def test_unreachable_island_gives_inf_and_false(simple_room):
    pf = simple_room
    pf.seed(2)
    start = pf.get_random_navigable_point(island_index=0)
    end = pf.get_random_navigable_point(island_index=1)
    path = ShortestPath(requested_start=start, requested_end=end)
    assert not pf.find_path(path)
    assert math.isinf(path.geodesic_distance) and path.points == []
    np.testing.assert_array_equal(pf.try_step(start, end), start)


def test_far_target_is_not_reached(simple_room):
    pf = simple_room
    start = pf.snap_point([0.0, 0.15, -3.0])
    outside = start + np.array([0.0, 0.0, -4.0])  # 1.5 m beyond the floor edge
    result = pf.try_step(start, outside)
    assert pf.is_navigable(result) and not np.allclose(result, outside)
    assert result[2] < start[2] and result[2] > -5.45
    very_far = start + np.array([0.0, 0.0, -40.0])  # outside the snap box: no move
    np.testing.assert_array_equal(pf.try_step(start, very_far), start)


def test_islands_partition_the_navigable_cells(simple_room):
    data = simple_room.navmesh_data
    labels = data.island[data.navigable]
    assert labels.min() == 0 and labels.max() == simple_room.num_islands - 1
    assert np.all(data.island[~data.navigable] == -1)
    counts = np.bincount(labels)
    assert np.all(counts[:-1] >= counts[1:])  # ordered by size
    total = sum(simple_room.island_area(i) for i in range(simple_room.num_islands))
    assert total == pytest.approx(simple_room.navigable_area, rel=1e-12)


def test_topdown_view_shape_matches_habitat_formula(simple_room):
    lo, hi = simple_room.get_bounds()
    for mpp in (0.1, 0.05):
        view = simple_room.get_topdown_view(mpp, 0.15)
        assert view.shape == (int((hi[2] - lo[2]) / mpp), int((hi[0] - lo[0]) / mpp))


def test_rebuild_is_deterministic_and_save_load_round_trips(simple_room_mesh, tmp_path):
    a, b = PathFinder(), PathFinder()
    a.build(*simple_room_mesh, NavMeshSettings())
    b.build(*simple_room_mesh, NavMeshSettings())
    np.testing.assert_array_equal(a.navmesh_data.navigable, b.navmesh_data.navigable)
    a.save_nav_mesh(tmp_path / "simple_room.navmesh")
    c = PathFinder()
    assert c.load_nav_mesh(tmp_path / "simple_room.navmesh")
    for finder in (a, c):
        finder.seed(4)
    pa = [a.get_random_navigable_point() for _ in range(5)]
    pc = [c.get_random_navigable_point() for _ in range(5)]
    np.testing.assert_array_equal(pa, pc)


def test_bigger_agent_radius_shrinks_the_navmesh(simple_room_mesh, simple_room):
    settings = NavMeshSettings()
    settings.agent_radius *= 2.0
    wide = PathFinder()
    wide.build(*simple_room_mesh, settings)
    assert wide.navigable_area < simple_room.navigable_area


def test_stage_floor1_terrain_is_one_walkable_island(stage_floor1):
    pf = stage_floor1
    assert pf.num_islands == 1
    lo, hi = pf.get_bounds()
    np.testing.assert_allclose([lo[0], hi[0]], [-20.0, 20.0], atol=0.01)  # scale 2
    pf.seed(0)
    for _ in range(5):
        a, b = pf.get_random_navigable_point(), pf.get_random_navigable_point()
        path = ShortestPath(requested_start=a, requested_end=b)
        assert pf.find_path(path)
        assert path.geodesic_distance >= np.linalg.norm(b - a) - 1e-9
        assert all(pf.is_navigable(p) for p in path.points)
        result = pf.try_step(a, a + [0.25, 0.0, 0.0])
        assert pf.is_navigable(result)
