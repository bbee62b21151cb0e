"""Shortest paths: analytic lengths, unreachable goals, multi-goal (docs/physics.md, validation).

World frame Y up, meters. Tolerances: paths are any-angle on a 0.05 m grid, so the
geodesic must match the analytic shortest path within 2 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from navmesh import MultiGoalShortestPath, ShortestPath
from navmesh.path_query import path_length


def l_corridor(geometry, radius=0.1):
    """L-shaped floor: x in [0, 6] x z in [0, 2] plus x in [4, 6] x z in [0, 6]; no ledge
    filter, so the navigable region is the L shrunk by exactly ``radius``."""
    return geometry.build(
        geometry.box((0, -0.1, 0), (6, 0, 2)),
        geometry.box((4, -0.1, 2), (6, 0, 6)),
        filter_ledge_spans=False,
        agent_radius=radius,
    )


def around_rounded_corner(start, end, corner, radius):
    """Length of the taut string from start to end around a disk (corner, radius): the
    obstacle corner dilated by the agent radius. Two tangents plus the arc between them;
    the path wraps the side of the disk away from the obstacle (the reflex angle)."""
    d1, d2 = np.linalg.norm(start - corner), np.linalg.norm(end - corner)
    cos_between = np.dot(start - corner, end - corner) / (d1 * d2)
    wrap = 2.0 * np.pi - np.arccos(cos_between)  # angle swept on the free side
    arc = wrap - np.arccos(radius / d1) - np.arccos(radius / d2)
    return np.sqrt(d1**2 - radius**2) + np.sqrt(d2**2 - radius**2) + radius * arc


@pytest.mark.parametrize("radius", [0.1, 0.3])
def test_l_corridor_path_matches_analytic_length(geometry, radius):
    pf = l_corridor(geometry, radius)
    start, end = np.array([1.0, 0.0, 1.0]), np.array([5.0, 0.0, 5.0])
    path = ShortestPath(requested_start=start, requested_end=end)
    assert pf.find_path(path)
    assert path.geodesic_distance == pytest.approx(
        around_rounded_corner(start, end, np.array([4.0, 0.0, 2.0]), radius), rel=0.02
    )
    assert path.geodesic_distance >= np.linalg.norm(end - start)
    np.testing.assert_allclose(path.points[0], start, atol=1e-9)
    np.testing.assert_allclose(path.points[-1], end, atol=1e-9)
    for p in path.points:
        assert pf.is_navigable(p)


def test_straight_path_in_open_space_is_the_segment(geometry):
    pf = geometry.build(geometry.box((0, -0.1, 0), (6, 0, 6)))
    path = ShortestPath(requested_start=[1, 0, 1], requested_end=[5, 0, 4])
    assert pf.find_path(path)
    assert path.geodesic_distance == pytest.approx(5.0, abs=1e-9)
    assert len(path.points) == 2


def test_path_around_wall_through_door(geometry):
    """Room split by a wall at x in [2.92, 3.12] with a 1 m door at z in [4.03, 5.03]."""
    floor = geometry.box((0, -0.1, 0), (6, 0, 6))
    wall_a = geometry.box((2.92, 0, 0), (3.12, 2.5, 4.03))
    wall_b = geometry.box((2.92, 0, 5.03), (3.12, 2.5, 6))
    pf = geometry.build(floor, wall_a, wall_b)
    start, end = np.array([1.0, 0, 1.0]), np.array([5.0, 0, 1.0])
    path = ShortestPath(requested_start=start, requested_end=end)
    assert pf.find_path(path)
    # through the door corners offset by the agent radius (upper bound of the rounded path)
    c1, c2 = np.array([2.82, 0, 4.13]), np.array([3.22, 0, 4.13])
    analytic = np.linalg.norm(c1 - start) + np.linalg.norm(c2 - c1) + np.linalg.norm(end - c2)
    assert path.geodesic_distance == pytest.approx(analytic, rel=0.02)


def test_unreachable_goal_gives_inf_and_false(geometry):
    pf = geometry.build(
        geometry.box((0, -0.1, 0), (3, 0, 3)), geometry.box((5, -0.1, 0), (8, 0, 3))
    )
    assert pf.num_islands == 2
    path = ShortestPath(requested_start=[1.5, 0, 1.5], requested_end=[6.5, 0, 1.5])
    assert not pf.find_path(path)
    assert math.isinf(path.geodesic_distance) and path.points == []
    far = ShortestPath(requested_start=[1.5, 0, 1.5], requested_end=[1.5, 0, 30.0])
    assert not pf.find_path(far)  # nothing within the snap box of the end
    assert math.isinf(far.geodesic_distance)


def test_multi_goal_picks_the_geodesically_closest_end(geometry):
    pf = l_corridor(geometry)
    start = [1.0, 0, 1.0]
    ends = [[5.0, 0, 5.0], [5.0, 0, 1.0], [20.0, 0, 20.0]]
    multi = MultiGoalShortestPath(requested_start=start, requested_ends=ends)
    assert pf.find_path(multi)
    assert multi.closest_end_point_index == 1
    single = ShortestPath(requested_start=start, requested_end=ends[1])
    pf.find_path(single)
    assert multi.geodesic_distance == pytest.approx(single.geodesic_distance, rel=1e-12)


def test_find_path_rejects_bad_input(geometry):
    pf = geometry.build(geometry.box((0, -0.1, 0), (4, 0, 4)))
    with pytest.raises(TypeError, match="ShortestPath"):
        pf.find_path("path")
    with pytest.raises(ValueError, match="requested_start"):
        pf.find_path(ShortestPath(requested_start=[np.nan, 0, 0], requested_end=[1, 0, 1]))
    with pytest.raises(ValueError, match="requested_end"):
        pf.find_path(ShortestPath(requested_start=[1, 0, 1], requested_end=[1, 0]))


def test_stairs_connect_two_floors_and_try_step_climbs_them(geometry):
    """Ground floor (y = 0), an upper floor (top y = 3) over x in [6, 10], and 20 steps of
    0.15 m x 0.25 m from x = 1 to x = 6: the cells under the upper floor hold two layers."""
    parts = [geometry.box((0, -0.1, 0), (10, 0, 4)), geometry.box((6, 2.9, 0), (10, 3.0, 4))]
    for k in range(20):
        x0 = 1 + 0.25 * k
        parts.append(geometry.box((x0, 0, 0), (x0 + 0.25, 0.15 * (k + 1), 1.5)))
    pf = geometry.build(*parts)
    below, above = np.array([8.0, 0.0, 3.0]), np.array([8.0, 3.0, 3.0])
    assert pf.navmesh_data.shape[0] == 2
    assert pf.get_island(below) == pf.get_island(above)
    path = ShortestPath(requested_start=below, requested_end=above)
    assert pf.find_path(path)
    # lower bound: walk to the foot of the stairs (x = 1) and back up to x = 8 on top
    assert path.geodesic_distance > (8.0 - 1.0) * 2
    assert path.geodesic_distance < 8.0 * 2 + 2.0
    pos = pf.snap_point(below)
    for _ in range(200):  # follow the path with 0.25 m try_step moves
        follow = ShortestPath(requested_start=pos, requested_end=above)
        assert pf.find_path(follow)
        if follow.geodesic_distance < 1e-6:
            break
        direction = follow.points[1] - pos
        direction[1] = 0.0
        dist = np.linalg.norm(direction)
        pos = pf.try_step(pos, pos + direction / dist * min(0.25, dist))
    np.testing.assert_allclose(pos, above, atol=1e-9)


@pytest.mark.parametrize("mirror", [1.0, -1.0])
def test_l_corridor_length_is_the_same_moved_to_negative_coordinates_or_mirrored(geometry, mirror):
    # the L corridor shifted by (-10, 0, -10) and, for mirror = -1, reflected in z: the
    # shortest path is the same taut string around the dilated corner
    offset = np.array([-10.0, 0.0, -10.0])

    def place(p):
        p = np.asarray(p, float)
        return offset + p * [1.0, 1.0, mirror]

    boxes = [((0, -0.1, 0), (6, 0, 2)), ((4, -0.1, 2), (6, 0, 6))]
    placed = [(place(lo), place(hi)) for lo, hi in boxes]
    pf = geometry.build(
        *(geometry.box(np.minimum(lo, hi), np.maximum(lo, hi)) for lo, hi in placed),
        filter_ledge_spans=False,
    )
    start, end = place([1.0, 0.0, 1.0]), place([5.0, 0.0, 5.0])
    path = ShortestPath(requested_start=start, requested_end=end)
    assert pf.find_path(path)
    expected = around_rounded_corner(start, end, place([4.0, 0.0, 2.0]), 0.1)
    assert path.geodesic_distance == pytest.approx(expected, rel=0.02)
    for p in path.points:
        assert pf.is_navigable(p)


def _mirrored_l(geometry, mx: float, mz: float, corner, radius: float, offset=(0.0, 0.0)):
    """The L corridor with its inner corner at ``corner`` (x, z), reflected by (mx, mz), then
    moved by ``offset`` (x, z)."""

    def place(p):
        return np.array([offset[0] + p[0] * mx, p[1], offset[1] + p[2] * mz])

    cx, cz = corner
    boxes = [((0, -0.1, 0), (6, 0, cz)), ((cx, -0.1, cz), (6, 0, 6))]
    placed = [(place(lo), place(hi)) for lo, hi in boxes]
    pf = geometry.build(
        *(geometry.box(np.minimum(lo, hi), np.maximum(lo, hi)) for lo, hi in placed),
        filter_ledge_spans=False,
        agent_radius=radius,
    )
    return pf, place


@pytest.mark.parametrize(
    "mx, mz, offset",
    [
        (1.0, 1.0, (0.0, 0.0)),
        (1.0, -1.0, (0.0, 0.0)),
        (-1.0, -1.0, (0.0, 0.0)),
        (1.0, 1.0, (-3.0, -1.5)),
    ],
)
def test_path_around_an_l_corner_bends_at_the_walkable_corner(geometry, mx, mz, offset):
    """No agent radius, inner corner of the L at (4.025, 2.025), mid-cell on the 0.05 m grid
    (origin at the mesh's minimum corner). Every cell a floor touches is walkable, so the
    walkable region's inner corner is the grid corner q = (4.00, 2.05) just outside the box
    corner, and the taut string from (1, 1) to (5, 5) bends at q only: its length is
    |s - q| + |q - e| (up to the 0.1 mm INSIDE_EPS back-off into the corner's cell), whatever
    the quadrant the corridor is mirrored into, and with the world origin between the start
    and the corner (offset (-3, -1.5))."""
    pf, place = _mirrored_l(geometry, mx, mz, (4.025, 2.025), radius=0.0, offset=offset)
    start, end, q = place([1.0, 0.0, 1.0]), place([5.0, 0.0, 5.0]), place([4.0, 0.0, 2.05])
    # the walkable region around q: three of its four neighbouring cells
    assert pf.is_navigable(place([3.99, 0.0, 2.04]))
    assert pf.is_navigable(place([4.01, 0.0, 2.06]))
    assert not pf.is_navigable(place([3.99, 0.0, 2.06]))
    path = ShortestPath(requested_start=start, requested_end=end)
    assert pf.find_path(path)
    assert len(path.points) == 3
    np.testing.assert_allclose(path.points[1], q, atol=2e-4)
    taut = np.linalg.norm(q - start) + np.linalg.norm(end - q)
    assert path.geodesic_distance == pytest.approx(taut, abs=1e-3)


@pytest.mark.parametrize("mx, mz", [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)])
def test_every_interior_waypoint_is_needed(geometry, mx, mz):
    """A shortest path has no removable bend: for every interior waypoint, the straight
    segment joining its two neighbours leaves the walkable region (checked every 1 mm), or
    the path could skip it and be shorter (triangle inequality). The L corridor with a
    0.1 m agent radius bends around a staircase of cells, in each of its four mirrorings."""
    pf, place = _mirrored_l(geometry, mx, mz, (4.0, 2.0), radius=0.1)
    path = ShortestPath(requested_start=place([1.0, 0.0, 1.0]), requested_end=place([5, 0, 5]))
    assert pf.find_path(path)
    assert len(path.points) >= 3
    for before, after in zip(path.points[:-2], path.points[2:], strict=True):
        n = int(np.linalg.norm(after - before) / 0.001) + 2
        shortcut = before + (after - before) * np.linspace(0.0, 1.0, n)[:, None]
        assert not all(pf.is_navigable(p) for p in shortcut)


@pytest.mark.parametrize(
    "start, end",
    [([1.0, 0, 4.0], [5.0, 0, 4.0]), ([3.0, 0, 1.0], [3.0, 0, 6.0]), ([1.0, 0, 6.0], [6, 0, 2])],
)
def test_path_around_a_pillar_stays_on_the_walkable_floor(geometry, start, end):
    """A 1 m square pillar (x, z in [2.5, 3.5] x [3.5, 4.5]) stands between start and end
    (start x != z: a line of sight taken from a wrong point shows): every segment of the
    path lies on the walkable floor (checked every 1 mm), and the path goes around the
    pillar dilated by the 0.1 m agent radius, so it is longer than the straight segment."""
    pf = geometry.build(
        geometry.box((0, -0.1, 0), (8, 0, 8)), geometry.box((2.5, 0, 3.5), (3.5, 2, 4.5))
    )
    start, end = np.array(start), np.array(end)
    path = ShortestPath(requested_start=start, requested_end=end)
    assert pf.find_path(path)
    assert path.geodesic_distance > np.linalg.norm(end - start) + 0.01
    for a, b in zip(path.points[:-1], path.points[1:], strict=True):
        n = int(np.linalg.norm(b - a) / 0.001) + 2
        assert all(pf.is_navigable(p) for p in a + (b - a) * np.linspace(0.0, 1.0, n)[:, None])


def test_path_length_sums_the_segment_lengths():
    """Habitat's ``pathLength``: a polyline of fewer than two points has no length; a 3-4-5
    right angle walked along its legs (one leg climbing 4 m) is 3 + 4 = 7 m long."""
    assert path_length([]) == 0.0
    assert path_length([np.array([1.0, 2.0, 3.0])]) == 0.0
    legs = [np.array([0.0, 0.0, 0.0]), np.array([3.0, 0.0, 0.0]), np.array([3.0, 4.0, 0.0])]
    assert path_length(legs) == pytest.approx(7.0, abs=1e-12)
    assert path_length([legs[0], legs[2]]) == pytest.approx(5.0, abs=1e-12)
