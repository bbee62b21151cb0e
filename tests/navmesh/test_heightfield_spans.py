"""Heightfield stages on hand-made spans: grid cover, span merging, climb and clearance filters.

Each test builds a few samples or spans whose walkable surfaces are known by hand (heights
in meters, Y up; column = iz * nx + ix) and checks Recast's rules as documented in
``navmesh/heightfield.py``: spans per column sorted by height, a low-hanging unwalkable span
becomes walkable only within ``max_climb`` above a walkable span of the *same* column, and a
clearance of exactly ``agent_height`` is enough.
"""

from __future__ import annotations

import numpy as np

from navmesh.heightfield import (
    GridSpec,
    SolidSpans,
    filter_low_hanging_obstacles,
    filter_walkable_low_height_spans,
    make_grid,
    merge_samples_into_spans,
    solid_overlaps,
)


def _spans(column, ymin, ymax, walkable) -> SolidSpans:
    return SolidSpans(
        np.array(column, dtype=np.int64),
        np.array(ymin, dtype=np.float64),
        np.array(ymax, dtype=np.float64),
        np.array(walkable, dtype=bool),
    )


def _grid(nx: int, y_min: float, y_max: float) -> GridSpec:
    return GridSpec(np.zeros(2), 0.1, nx, 1, y_min, y_max)


def test_the_grid_covers_every_vertex_even_of_a_flat_wall():
    # a wall in the plane x = 3 (zero x extent) far from the z origin: at least one cell
    # along x, and every vertex inside [origin, origin + n * cell_size] on both axes
    for vertices in (
        np.array([[3.0, 0.0, 5.0], [3.0, 1.0, 5.0], [3.0, 0.0, 5.7]]),
        np.array([[0.0, 0.0, 5.0], [1.0, 0.0, 5.0], [0.0, 0.0, 5.5]]),
    ):
        grid = make_grid(vertices, 0.1)
        assert grid.nx >= 1 and grid.nz >= 1
        upper = grid.origin_xz + np.array([grid.nx, grid.nz]) * grid.cell_size
        assert np.all(vertices[:, [0, 2]] >= grid.origin_xz)
        assert np.all(vertices[:, [0, 2]] <= upper + 1e-12)


def test_samples_of_two_columns_more_than_a_meter_apart_in_height_merge_per_column():
    # column 0 holds a floor at 0 m and a shelf at 1.5 m, column 1 a floor at 0 m: the
    # spans come out sorted by (column, height), three of them, the 1.5 m gap kept
    grid = _grid(2, 0.0, 1.5)
    spans = merge_samples_into_spans(
        np.array([1, 0, 0]), np.array([0.0, 0.0, 1.5]), np.ones(3, bool), grid, 0.2, 0.2
    )
    np.testing.assert_array_equal(spans.column, [0, 0, 1])
    np.testing.assert_array_equal(spans.ymin, [0.0, 1.5, 0.0])
    np.testing.assert_array_equal(spans.ymax, [0.0, 1.5, 0.0])


def test_a_low_obstacle_next_door_does_not_become_walkable():
    # column 0: a walkable floor (top 0 m); column 1: an unwalkable block 0.1 m high. The
    # climb rule looks only at the span below in the same column: column 1 stays unwalkable
    spans = _spans([0, 1], [0.0, 0.0], [0.0, 0.1], [True, False])
    filter_low_hanging_obstacles(spans, max_climb=0.2)
    np.testing.assert_array_equal(spans.walkable, [True, False])


def test_a_hanging_obstacle_is_walkable_up_to_max_climb_above_a_floor_and_not_higher():
    # one column each: a floor (top 0 m) with an unwalkable span on it whose top is 0.25 m
    # (exactly max_climb above: a curb, walkable) or 1.0 m (a table: not walkable)
    spans = _spans([0, 0, 1, 1], [0.0, 0.1, 0.0, 0.9], [0.0, 0.25, 0.0, 1.0], [1, 0, 1, 0])
    filter_low_hanging_obstacles(spans, max_climb=0.25)
    np.testing.assert_array_equal(spans.walkable, [True, True, True, False])


def test_a_clearance_of_exactly_the_agent_height_is_enough():
    # floors at 0 m under ceilings at 1.5 m (clearance 1.5 m, walkable for a 1.5 m agent)
    # and at 1.4 m (too low)
    spans = _spans([0, 0, 1, 1], [0.0, 1.5, 0.0, 1.4], [0.0, 1.6, 0.0, 1.6], [1, 0, 1, 0])
    filter_walkable_low_height_spans(spans, agent_height=1.5)
    np.testing.assert_array_equal(spans.walkable, [True, False, False, False])


def test_solid_overlap_sees_only_the_queried_column():
    # column 0: a floor [0, 0.1]; column 1: a floor [0, 0.1]. Above the floor of column 0
    # ([0.5, 1.0]) is free; the floor of column 1 below that interval does not count
    spans = _spans([0, 1], [0.0, 0.0], [0.1, 0.1], [True, True])
    grid = _grid(2, 0.0, 0.1)
    hit = solid_overlaps(
        spans, grid, np.array([0, 0, 1]), np.array([0.5, 0.05, 0.0]), np.array([1.0, 1.0, 0.05])
    )
    np.testing.assert_array_equal(hit, [False, True, True])
