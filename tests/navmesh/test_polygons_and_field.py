"""The navmesh as merged rectangles, the geodesic distance field, and the wall-search skip.

* ``build_navmesh_vertices`` merges equal squares into rectangles: an L-shaped floor is two
  rectangles (8 vertices); the triangles cover exactly the navigable area, +Y up.
* ``PathFinder.geodesic_field(goal).distance(p)`` is ``find_path``'s geodesic (one search over
  the navmesh's visibility graph for both) to 1e-9 m; unreachable is inf.
* ``NavGrid.clearance`` never exceeds a square centre's true distance to the boundary, so the
  wall search it skips would have found nothing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from navmesh import PathFinder, ShortestPath
from navmesh.polygons import MERGE_HEIGHT_TOLERANCE
from navmesh.proximity import nearest_wall_best_first
from navmesh.visibility import find_corners


def triangle_area_and_normals(pathfinder, island: int = -1):
    vertices = np.asarray(pathfinder.build_navmesh_vertices(island))
    triangles = vertices[np.asarray(pathfinder.build_navmesh_vertex_indices(island)).reshape(-1, 3)]
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    return 0.5 * normals[:, 1].sum(), normals, vertices


def test_a_rectangular_floor_is_one_rectangle(geometry):
    pathfinder = geometry.build(geometry.box([0, -0.1, 0], [3, 0, 2]))
    area, normals, vertices = triangle_area_and_normals(pathfinder)
    assert len(vertices) == 4 and len(normals) == 2  # one rectangle, two triangles
    assert np.all(normals[:, 1] > 0)
    assert area == pytest.approx(pathfinder.navigable_area, rel=1e-12)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    assert (hi[0] - lo[0]) * (hi[2] - lo[2]) == pytest.approx(area, rel=1e-12)


def test_an_l_shaped_floor_is_a_few_rectangles(geometry):
    pathfinder = geometry.build(
        geometry.box([0, -0.1, 0], [2, 0, 1]), geometry.box([0, -0.1, 1], [1, 0, 2])
    )
    area, normals, vertices = triangle_area_and_normals(pathfinder)
    assert len(vertices) <= 16  # the L and the rounded inner corner of the eroded floor
    assert np.all(normals[:, 1] > 0)
    assert area == pytest.approx(pathfinder.navigable_area, rel=1e-12)
    np.testing.assert_allclose(vertices[:, 1], 0.0, atol=1e-9)


def test_floors_of_two_heights_never_share_a_rectangle(geometry):
    pathfinder = geometry.build(
        geometry.box([0, -0.1, 0], [1, 0, 2]), geometry.box([1, -0.1, 0], [2, 0.1, 2])
    )
    area, _, vertices = triangle_area_and_normals(pathfinder)
    assert area == pytest.approx(pathfinder.navigable_area, rel=1e-12)
    heights = np.unique(vertices[:, 1].round(6))
    assert len(heights) == 2  # each rectangle is flat: one per floor (the step splits them)
    for rectangle in vertices.reshape(-1, 4, 3):
        assert np.ptp(rectangle[:, 1]) == 0.0


def test_the_demo_apartment_has_hundreds_of_navmesh_vertices(demo_data):
    import engine as habitat_sim

    cfg = habitat_sim.SimulatorConfiguration()
    cfg.scene_id = str(demo_data / "scene_datasets/demo/apartment.glb")
    agents = [habitat_sim.agent.AgentConfiguration()]
    with habitat_sim.Simulator(habitat_sim.Configuration(cfg, agents)) as sim:
        pathfinder = sim.pathfinder
        area, normals, vertices = triangle_area_and_normals(pathfinder)
        assert 40 <= len(vertices) <= 1000  # Habitat's order; one square each would be 55,000
        assert area == pytest.approx(pathfinder.navigable_area, rel=1e-9)
        for island in range(pathfinder.num_islands):
            island_area, _, _ = triangle_area_and_normals(pathfinder, island)
            assert island_area == pytest.approx(pathfinder.island_area(island), rel=1e-9)


def covering_triangles(vertices, triangles, x, z):
    """Indices of the triangles whose XZ projection contains (x, z), and the heights there."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))

    def cross(p, q):  # z-component of (q - p) x (x - p) in the XZ plane
        return (q[:, 0] - p[:, 0]) * (z - p[:, 2]) - (q[:, 2] - p[:, 2]) * (x - p[:, 0])

    w_a, w_b, w_c = cross(b, c), cross(c, a), cross(a, b)
    total = w_a + w_b + w_c
    inside = (np.sign(w_a) * np.sign(total) >= 0) & (np.sign(w_b) * np.sign(total) >= 0)
    inside &= (np.sign(w_c) * np.sign(total) >= 0) & (total != 0)
    found = np.flatnonzero(inside)
    heights = (w_a * a[:, 1] + w_b * b[:, 1] + w_c * c[:, 1])[found] / total[found]
    return found, heights


def test_simple_room_merges_into_a_few_rectangles_that_cover_the_navmesh(simple_room):
    """A rasterized floor's heights jitter below a millimetre (41,425 distinct heights among
    43,128 squares): merging within MERGE_HEIGHT_TOLERANCE gives 72 vertices where one
    rectangle per square gave 166,556 (the demo apartment's shipped navmesh has 376). The
    triangles still cover exactly the navigable squares, at the surface height."""
    area, normals, vertices = triangle_area_and_normals(simple_room)
    assert len(vertices) <= 1000
    assert np.all(normals[:, 1] > 0)
    assert area == pytest.approx(simple_room.navigable_area, rel=1e-9)
    triangles = np.asarray(simple_room.build_navmesh_vertex_indices()).reshape(-1, 3)
    grid = simple_room.nav_grid
    rng = np.random.default_rng(4)
    # inside navigable squares (away from their sides): one triangle of one rectangle, on the
    # surface; a point of a stacked cell may lie under other floors' triangles too
    for node in rng.choice(np.flatnonzero(grid.navigable), size=300, replace=False):
        centre = grid.node_center(int(node))
        x, z = centre[[0, 2]] + rng.uniform(-0.4, 0.4, 2) * grid.cell_size
        found, heights = covering_triangles(vertices, triangles, x, z)
        near = np.abs(heights - centre[1]) <= MERGE_HEIGHT_TOLERANCE
        assert np.count_nonzero(near) == 1
    # centres of squares with no navigable layer: no triangle
    cells_free = ~grid.navigable.reshape(grid.n_layers, -1).any(axis=0)
    for cell in rng.choice(np.flatnonzero(cells_free), size=300, replace=False):
        iz, ix = divmod(int(cell), grid.nx)
        x, z = grid.x0 + (ix + 0.5) * grid.cell_size, grid.z0 + (iz + 0.5) * grid.cell_size
        assert covering_triangles(vertices, triangles, x, z)[0].size == 0


def geodesic(pathfinder, start, end) -> float:
    path = ShortestPath()
    path.requested_start, path.requested_end = start, end
    pathfinder.find_path(path)
    return path.geodesic_distance


def test_the_field_is_exact_in_sight_and_equals_find_path_around_a_wall(geometry):
    # a 6 x 6 m floor with a 4 m wall across its middle: half of the pairs see each other
    pathfinder = geometry.build(
        geometry.box([0, -0.1, 0], [6, 0, 6]), geometry.box([0, 0, 2.9], [4, 1.5, 3.1])
    )
    pathfinder.seed(3)
    goal = pathfinder.get_random_navigable_point()
    field = pathfinder.geodesic_field(goal)
    grid = pathfinder.nav_grid
    goal_node, goal_snapped = grid.nearest_node(goal)
    checked_in_sight = checked_around = 0
    for _ in range(60):
        start = pathfinder.get_random_navigable_point()
        truth = geodesic(pathfinder, start, goal)
        estimate = field.distance(start)
        node, snapped = grid.nearest_node(start)
        if grid.line_of_sight(node, snapped[[0, 2]], goal_snapped[[0, 2]], goal_node):
            assert estimate == pytest.approx(np.linalg.norm(goal_snapped - snapped), rel=1e-12)
            checked_in_sight += 1
        else:
            # around the wall's free end: the path bends at the corners of its eroded end
            assert 3 <= len(field.path_from(start)) <= 4
            checked_around += 1
        assert estimate == pytest.approx(truth, abs=1e-9)
    assert checked_in_sight > 0 and checked_around > 0


def test_a_point_on_a_corners_wall_line_still_finds_its_path(geometry):
    """A point slid along a wall lies INSIDE_EPS off it, on the line of the wall's corner; a
    rounding ulp across that line must not prune the corner (no path was found before)."""
    pathfinder = geometry.build(
        geometry.box([0, -0.1, 0], [6, 0, 6]), geometry.box([0, 0, 2.9], [4, 1.5, 3.1])
    )
    _, points, quadrant = find_corners(pathfinder.nav_grid)
    checked = 0
    for corner, (sx, sz) in zip(points, quadrant, strict=True):
        goal = corner + np.array([-0.5 * sx, 0.0, 2.0 * sz])  # round the corner
        # along the two walls that meet at the corner, nudged one ulp across the wall line
        for along, shared in (((0.3 * sx, 0.0), 2), ((0.0, 0.3 * sz), 0)):
            for nudge in (-np.inf, np.inf):
                start = corner + np.array([along[0], 0.0, along[1]])
                start[shared] = np.nextafter(corner[shared], nudge)
                if not (pathfinder.is_navigable(start) and pathfinder.is_navigable(goal)):
                    continue
                path = ShortestPath(requested_start=start, requested_end=goal)
                assert pathfinder.find_path(path)
                assert pathfinder.geodesic_field(goal).distance(start) == pytest.approx(
                    path.geodesic_distance, abs=1e-9
                )
                checked += 1
    assert checked >= 4


def test_the_field_and_find_path_agree_on_a_thousand_pairs_of_the_demo_apartment(demo_data):
    """One search for both: the field's distance is find_path's geodesic to 1e-9 m on 1000
    pairs (the grid-metric field it replaced was over by 0.24 m on average, 0.93 m at most)."""
    pathfinder = PathFinder()
    assert pathfinder.load_nav_mesh(str(demo_data / "scene_datasets/demo/apartment.navmesh"))
    pathfinder.seed(0)
    errors, bends = [], 0
    for _ in range(40):
        goal = pathfinder.get_random_navigable_point(island_index=0)
        field = pathfinder.geodesic_field(goal)
        for _ in range(25):
            start = pathfinder.get_random_navigable_point(island_index=0)
            path = ShortestPath(requested_start=start, requested_end=goal)
            assert pathfinder.find_path(path)
            errors.append(field.distance(start) - path.geodesic_distance)
            bends += len(path.points) > 2
    assert np.max(np.abs(errors)) <= 1e-9
    assert bends > 300  # most pairs go round corners: the comparison is not all straight lines


def test_an_unreachable_goal_is_infinitely_far(geometry):
    pathfinder = geometry.build(
        geometry.box([0, -0.1, 0], [3, 0, 3]), geometry.box([5, -0.1, 0], [8, 0, 3])
    )
    field = pathfinder.geodesic_field([6.5, 0.0, 1.5])
    assert field.distance([1.5, 0.0, 1.5]) == math.inf
    assert field.distance([6.2, 0.0, 1.5]) == pytest.approx(0.3, abs=1e-9)


def test_clearance_bounds_never_exceed_the_distance_to_a_wall(simple_room):
    grid = simple_room._require_grid()
    nodes = np.flatnonzero(grid.navigable)
    rng = np.random.default_rng(0)
    for node in rng.choice(nodes, size=200, replace=False):
        centre = grid.node_center(int(node))
        found = nearest_wall_best_first(grid, int(node), centre[0], centre[2], 50.0)
        wall = found[1] if found is not None else math.inf
        assert grid.clearance[node] <= wall + 1e-12
    assert grid.clearance.max() > 5 * grid.cell_size  # the bound is not trivially zero


def test_skipped_wall_searches_agree_with_the_search(simple_room):
    grid = simple_room._require_grid()
    simple_room.seed(5)
    skipped = 0
    for _ in range(200):
        point = simple_room.get_random_navigable_point()
        node, snapped = grid.nearest_node(point)
        record = simple_room.closest_obstacle_surface_point(point, 0.3)
        found = nearest_wall_best_first(grid, node, snapped[0], snapped[2], 0.3)
        if found is None:
            assert record.hit_dist == 0.3 and np.all(np.isnan(record.hit_pos))
            skipped += grid.clearance[node] - 0.05 >= 0.3
        else:
            assert record.hit_dist == found[1]
    assert skipped > 0


def test_is_near_obstacle_answers_as_the_distance_query(simple_room):
    simple_room.seed(9)
    near = 0
    for _ in range(300):
        point = simple_room.get_random_navigable_point()
        expected = simple_room.distance_to_closest_obstacle(point, 0.22) < 0.2
        assert simple_room.is_near_obstacle(point, 0.2) == expected
        near += expected
    assert 0 < near < 300
    with pytest.raises(ValueError, match="distance"):
        simple_room.is_near_obstacle([0.0, 0.0, 0.0], 0.0)


def test_growing_snap_windows_find_the_snap_boxs_node(simple_room):
    """nearest_node searches 3- and 10-cell windows before the 2 m snap box: same answers."""
    grid = simple_room._require_grid()
    (x0, y0, z0), (x1, y1, z1) = simple_room.get_bounds()
    rng = np.random.default_rng(4)
    full_window = grid._windows[-1][1]
    compared = 0
    for x, y, z in rng.uniform([x0 - 1, y0 - 0.5, z0 - 1], [x1 + 1, y1 + 0.5, z1 + 1], (400, 3)):
        ix, iz = grid.cell_of(x, z)
        node, snapped = grid._nearest_in_window(x, y, z, ix, iz, -1)
        best = grid._best_in_window(full_window, x, y, z, ix, iz, -1)
        if best is None:
            assert node == -1 and snapped is None
            continue
        assert node == best[0]
        compared += 1
    assert compared > 300
