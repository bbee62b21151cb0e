"""try_step / try_step_no_sliding geometry (docs/physics.md, validation; docs/habitat_api.md).

Scene: a 6 x 6 m floor (y = 0) with a 2 m wall across z in [4.02, 4.22]. The navigable
region of the main room ends at z_b (the wall eroded by the agent radius).
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from navmesh import NavMeshSettings, PathFinder

ON_BOUNDARY = 1e-3  # meters: results are pulled 0.1 mm inside the boundary


@pytest.fixture(scope="module")
def walled_room():
    floor = trimesh.creation.box(extents=(6, 0.1, 6))
    floor.apply_translation((3, -0.05, 3))
    wall = trimesh.creation.box(extents=(6, 2.0, 0.2))
    wall.apply_translation((3, 1.0, 4.12))
    mesh = trimesh.util.concatenate([floor, wall])
    pf = PathFinder()
    pf.build(mesh.vertices, mesh.faces.astype(np.int64), NavMeshSettings())
    data = pf.navmesh_data
    column = data.navigable[0, :, int(3.0 / data.cell_size)]  # cells along z at x = 3
    main_room = np.flatnonzero(column[: int(4.0 / data.cell_size)])
    z_b = data.origin_xz[1] + (main_room.max() + 1) * data.cell_size
    return pf, z_b


def step_45_into_wall(z_b):
    start = np.array([3.0, 0.0, z_b - 0.05])
    end = start + 0.25 * np.array([np.sqrt(0.5), 0.0, np.sqrt(0.5)])
    return start, end


def test_wall_boundary_is_agent_radius_from_wall(walled_room):
    _, z_b = walled_room
    assert 4.02 - 0.1 - 0.05 <= z_b <= 4.02 - 0.1 + 1e-9  # within one cell of wall - radius


def test_sliding_step_ends_on_boundary_displaced_along_it(walled_room):
    pf, z_b = walled_room
    start, end = step_45_into_wall(z_b)
    result = pf.try_step(start, end)
    assert isinstance(result, np.ndarray) and result.shape == (3,)
    assert result[2] == pytest.approx(z_b, abs=ON_BOUNDARY)
    # the closest boundary point to the end: the end projected on the wall line
    assert result[0] == pytest.approx(end[0], abs=ON_BOUNDARY)
    assert result[1] == pytest.approx(0.0, abs=1e-9)
    assert not np.allclose(result, end)  # collided
    assert pf.is_navigable(result)


def test_no_sliding_step_stops_where_segment_meets_boundary(walled_room):
    pf, z_b = walled_room
    start, end = step_45_into_wall(z_b)
    result = pf.try_step_no_sliding(start, end)
    assert result[2] == pytest.approx(z_b, abs=ON_BOUNDARY)
    moved, wanted = (result - start)[[0, 2]], (end - start)[[0, 2]]
    cos_angle = moved @ wanted / (np.linalg.norm(moved) * np.linalg.norm(wanted))
    assert np.degrees(np.arccos(min(1.0, cos_angle))) < 1.0
    assert np.linalg.norm(moved) == pytest.approx(0.05 * np.sqrt(2.0), abs=2 * ON_BOUNDARY)
    assert not np.allclose(result, end)
    assert pf.is_navigable(result)


@pytest.mark.parametrize("method", ["try_step", "try_step_no_sliding"])
def test_free_step_reaches_end_exactly(walled_room, method):
    pf, _ = walled_room
    start, end = [2.0, 0.0, 2.0], [2.2, 0.0, 2.1]
    np.testing.assert_allclose(getattr(pf, method)(start, end), end, atol=1e-12)


@pytest.mark.parametrize("method", ["try_step", "try_step_no_sliding"])
def test_end_on_other_island_or_far_off_mesh_returns_start(walled_room, method):
    pf, _ = walled_room
    start = np.array([3.0, 0.0, 3.0])
    other_room = [3.0, 0.0, 5.2]
    assert pf.get_island(other_room) != pf.get_island(start)
    np.testing.assert_array_equal(getattr(pf, method)(start, other_room), start)
    far = [30.0, 0.0, 3.0]  # farther than the 2 m snap box from any navigable cell
    np.testing.assert_array_equal(getattr(pf, method)(start, far), start)
    off_start = [3.0, 0.0, -10.0]
    np.testing.assert_array_equal(getattr(pf, method)(off_start, start), off_start)


def test_end_just_off_the_floor_edge_slides_to_the_edge(walled_room):
    pf, _ = walled_room
    start, end = np.array([5.5, 0.0, 2.0]), np.array([6.3, 0.0, 2.0])  # floor ends at x = 6
    result = pf.try_step(start, end)
    assert 5.5 < result[0] < 6.0 and pf.is_navigable(result)
    assert result[2] == pytest.approx(2.0, abs=ON_BOUNDARY)


def test_result_height_is_surface_height(geometry):
    pf = geometry.build(
        geometry.box((0, -0.1, 0), (3, 0, 4)), geometry.box((3, -0.1, 0), (6, 0.15, 4))
    )
    result = pf.try_step([2.9, 0.0, 2.0], [3.1, 0.0, 2.0])
    np.testing.assert_allclose(result, [3.1, 0.15, 2.0], atol=1e-12)


def test_try_step_rejects_bad_points(walled_room):
    pf, _ = walled_room
    with pytest.raises(ValueError, match="start"):
        pf.try_step([np.inf, 0, 0], [1, 0, 1])
    with pytest.raises(ValueError, match="end"):
        pf.try_step_no_sliding([1, 0, 1], [1, 0])
    with pytest.raises(TypeError, match="start"):
        pf.try_step(None, [1, 0, 1])


@pytest.mark.parametrize("method", ["try_step", "try_step_no_sliding"])
def test_blocked_step_result_is_a_point_of_the_navmesh(walled_room, method):
    # Snapping a navmesh point does not move it; a result left on (or 1e-4 m beyond) the
    # boundary would be pulled back in by the snap.
    pf, z_b = walled_room
    for angle in (0.0, 20.0, 45.0, 70.0):
        start = np.array([3.0, 0.0, z_b - 0.05])
        rad = np.radians(angle)
        end = start + 0.25 * np.array([np.sin(rad), 0.0, np.cos(rad)])
        result = getattr(pf, method)(start, end)
        assert result[2] < z_b, (angle, result)
        np.testing.assert_allclose(pf.snap_point(result), result, rtol=0, atol=1e-12)


def test_sliding_step_keeps_the_tangential_component(walled_room):
    # Sliding removes the motion into the wall and keeps the motion along it: from 0.05 m
    # before the boundary a step (dx, dz) ends at x + dx on the boundary line z = z_b (the
    # ends stay in front of the wall's face z = 4.02, so they snap to this room).
    pf, z_b = walled_room
    start = np.array([2.0, 0.0, z_b - 0.05])
    for dx, dz in ((0.3, 0.1), (-0.3, 0.12), (0.05, 0.1), (-0.01, 0.11)):
        result = pf.try_step(start, start + [dx, 0.0, dz])
        assert result[0] == pytest.approx(start[0] + dx, abs=ON_BOUNDARY)
        assert result[2] == pytest.approx(z_b, abs=ON_BOUNDARY)


def test_sliding_step_near_a_wall_end_does_not_pass_through_the_wall(geometry):
    # A 0.2 m wall across z in [2.9, 3.1] that ends at x = 3 (the navmesh goes around its
    # end, eroded by the 0.1 m agent radius). A 0.7 m step straight across it 0.4 m from
    # its end is blocked: the search disk (radius = half the step, Detour) does not reach
    # around the end, so the agent stops in front of the wall and never appears behind it.
    pf = geometry.build(
        geometry.box((0, -0.1, 0), (6, 0, 6)), geometry.box((0, 0, 2.9), (3, 2, 3.1))
    )
    start, end = np.array([2.6, 0.0, 2.6]), np.array([2.6, 0.0, 3.3])
    assert pf.is_navigable(end) and pf.get_island(end) == pf.get_island(start)
    for method in ("try_step", "try_step_no_sliding"):
        result = getattr(pf, method)(start, end)
        assert result[2] < 2.9 - 0.05, (method, result)  # in front of the wall, radius off
        assert result[0] == pytest.approx(2.6, abs=ON_BOUNDARY)  # no sideways motion to slide


@pytest.mark.parametrize("angle", [0.0, 30.0, 60.0])
def test_no_sliding_stops_a_tenth_of_a_millimeter_before_the_boundary(walled_room, angle):
    # the segment meets the boundary z = z_b at c; the result is pulled back along the
    # segment by INSIDE_EPS = 1e-4 m so that it lies inside the last navigable square
    pf, z_b = walled_room
    start = np.array([3.0, 0.0, z_b - 0.05])
    direction = np.array([np.sin(np.radians(angle)), 0.0, np.cos(np.radians(angle))])
    result = pf.try_step_no_sliding(start, start + 0.25 * direction)
    crossing = start + (0.05 / direction[2]) * direction
    np.testing.assert_allclose(result, crossing - 1e-4 * direction, rtol=0, atol=1e-9)


def test_sliding_around_the_end_of_a_wall_reaches_an_end_behind_it(geometry):
    # A step that crosses the wall right at its end: the search disk covers the way around
    # the end (eroded by the 0.1 m radius to x = 3.1), so the agent ends exactly at ``end``.
    pf = geometry.build(
        geometry.box((0, -0.1, 0), (6, 0, 6)), geometry.box((0, 0, 2.9), (3, 2, 3.1))
    )
    start, end = np.array([3.2, 0.0, 2.7]), np.array([2.9, 0.0, 3.3])
    assert not np.allclose(pf.try_step_no_sliding(start, end), end)  # the straight way is shut
    np.testing.assert_array_equal(pf.try_step(start, end), end)
