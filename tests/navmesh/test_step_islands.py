"""A step never leaves its island (Habitat's ``try_step``: an end that snaps to another island,
or to nothing, returns the start unchanged).

Scene: a 6 x 6 m floor split by a thin 2 m wall across x at z in [2.97, 3.03], agent radius
3 cm: island A (z < 2.97 minus the radius) and island B beyond the wall. Ends are drawn all
around starts near the wall on either side, some on the other island, some off the grid,
some far above the floor; whatever the end, the result lies on the start's island, and it
is the start itself exactly when the end snaps to another island or to no navmesh at all.
The rule does not depend on the floor's height: the same room is also lifted 2.85 m, so
its floor height equals the z of the starts next to the wall (a height read as a z would
then look at island A's side of the wall).
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.navmesh.conftest import box, build

FLOOR_Y = 0.0
LIFTED_Y = 2.85  # a floor height equal to the z of island A's squares next to the wall


def split_room_at(floor_y: float):
    """The split room with its floor's top at height ``floor_y``."""
    floor = box((0.0, floor_y - 0.1, 0.0), (6.0, floor_y, 6.0))
    wall = box((0.0, floor_y, 2.97), (6.0, floor_y + 2.0, 3.03))
    return build(floor, wall, agent_radius=0.03)


@pytest.fixture(scope="module")
def split_room():
    return split_room_at(FLOOR_Y)


@pytest.fixture(scope="module")
def lifted_split_room():
    return split_room_at(LIFTED_Y)


def random_steps(seed: int, count: int, floor_y: float = FLOOR_Y) -> tuple[np.ndarray, np.ndarray]:
    """Starts within 0.25 m of the wall on either island, ends up to 0.5 m away in any
    direction (so many lie just across the wall), a quarter of them lifted 1-3 m above the
    floor, some beyond the floor's edge."""
    rng = np.random.default_rng(seed)
    start_z = rng.uniform(2.7, 2.9, count) + np.where(rng.random(count) < 0.5, 0.0, 0.4)
    starts = np.column_stack([rng.uniform(0.05, 5.95, count), np.full(count, floor_y), start_z])
    offsets = rng.uniform(-0.5, 0.5, (count, 3))
    offsets[:, 1] = np.where(rng.random(count) < 0.25, rng.uniform(1.0, 3.0, count), 0.0)
    return starts, starts + offsets


@pytest.mark.parametrize("lifted", [False, True], ids=["floor_at_0", "floor_at_2.85"])
@pytest.mark.parametrize("method", ["try_step", "try_step_no_sliding"])
def test_steps_stay_on_the_start_island_and_stop_dead_at_another(
    split_room, lifted_split_room, method, lifted
):
    pf = lifted_split_room if lifted else split_room
    starts, ends = random_steps(seed=7, count=400, floor_y=LIFTED_Y if lifted else FLOOR_Y)
    assert steps_to_another_island(pf, method, starts, ends) > 20  # the sample really tries


def steps_to_another_island(pf, method: str, starts, ends) -> int:
    """Check every step's island rule; return how many ends snap to another island or none."""
    other_island_ends = 0
    for start, end in zip(starts, ends, strict=True):
        start_island = pf.get_island(start)
        assert start_island >= 0
        result = getattr(pf, method)(start, end)
        assert pf.get_island(result) == start_island, (start, end, result)
        snapped = pf.snap_point(end)  # NaN when no square lies in the snap box
        if not np.all(np.isfinite(snapped)) or pf.get_island(snapped) != start_island:
            other_island_ends += 1
            assert np.array_equal(result, start), (start, end, result)
    return other_island_ends


def test_a_long_step_reaches_the_first_square_of_the_navmesh(split_room):
    """A step ending on the navmesh's first navigable square (lowest row, then column) from
    the far side of island A, farther than any shortcut window, arrives there."""
    pf = split_room
    data = pf.navmesh_data
    rows, columns = np.nonzero(data.navigable[0])
    first = np.lexsort((columns, rows))[0]
    x = data.origin_xz[0] + (columns[first] + 0.5) * data.cell_size
    z = data.origin_xz[1] + (rows[first] + 0.5) * data.cell_size
    end = np.array([x, FLOOR_Y, z])
    start = np.array([5.5, FLOOR_Y, 2.5])
    assert np.hypot(*(end - start)[[0, 2]]) > 9 * data.cell_size
    for method in ("try_step", "try_step_no_sliding"):
        result = getattr(pf, method)(start, end)
        assert np.allclose(result, end, atol=1e-9), (method, result)


def test_a_step_reaches_the_grid_corner_square():
    """Node 0 is the square in the grid's corner; it is navigable when nothing erodes the
    floor's edge (no agent radius, no ledge filter). A step across the open floor to it,
    farther than any shortcut window, arrives there like a step to any other square."""
    pf = build(box((0.0, -0.1, 0.0), (3.0, 0.0, 3.0)), agent_radius=0.0, filter_ledge_spans=False)
    grid = pf.nav_grid
    corner = np.array([grid.x0 + 0.5 * grid.cell_size, FLOOR_Y, grid.z0 + 0.5 * grid.cell_size])
    assert grid.nearest_node(corner)[0] == 0
    start = np.array([2.5, FLOOR_Y, 2.5])
    for method in ("try_step", "try_step_no_sliding"):
        result = getattr(pf, method)(start, corner)
        assert np.allclose(result, corner, atol=1e-12), (method, result)


@pytest.mark.parametrize("method", ["try_step", "try_step_no_sliding"])
def test_steps_over_the_grid_edge_keep_the_island_rule(method):
    """A 3 x 3 m floor whose squares reach the grid's edge (no agent radius, no ledge filter),
    with a walled pocket in its low-z corner (x > 1.5, z < 1: its own island) and the rest
    one L-shaped island that spans the whole far edge. Steps start within 0.1 m of the low-z
    or the high-z edge and end up to 0.3 m away, many beyond the grid: an end off the grid
    snaps to the nearest square (in the pocket for ends beyond the pocket's edge) or to none,
    and the island rule holds as inside the grid."""
    floor = box((0.0, -0.1, 0.0), (3.0, 0.0, 3.0))
    walls = (box((1.47, 0.0, 0.0), (1.53, 1.0, 1.03)), box((1.47, 0.0, 0.97), (3.0, 1.0, 1.03)))
    pf = build(floor, *walls, agent_radius=0.0, filter_ledge_spans=False)
    rng = np.random.default_rng(3)
    count = 300
    near_low = rng.random(count) < 0.7
    start_z = np.where(near_low, rng.uniform(0.0, 0.1, count), rng.uniform(2.9, 3.0, count))
    start_x = np.where(near_low, rng.uniform(0.0, 1.45, count), rng.uniform(0.0, 3.0, count))
    starts = np.column_stack([start_x, np.full(count, FLOOR_Y), start_z])
    ends = starts + rng.uniform(-0.3, 0.3, (count, 3)) * [1.0, 0.0, 1.0]
    assert np.mean((ends[:, 2] < 0.0) | (ends[:, 2] > 3.0)) > 0.3  # many ends off the grid
    assert steps_to_another_island(pf, method, starts, ends) > 10


@pytest.mark.parametrize("method", ["try_step", "try_step_no_sliding"])
def test_on_coarse_cells_a_step_far_above_the_floor_and_across_a_wall_goes_nowhere(method):
    """The island rule on 0.6 m cells (a few cells per room): a wall at z = 6 splits a
    12 x 12 m floor (no smallest-island filter). Ends more than the snap box's half height
    (4 m) above the floor snap to nothing; ends across the wall snap to the other island.
    Both leave the agent where it stands; ends on the floor of its own side are reached or
    slid to, on the same island."""
    floor = box((0.0, -0.6, 0.0), (12.0, 0.0, 12.0))
    wall = box((0.0, 0.0, 5.7), (12.0, 2.0, 6.3))
    pf = build(floor, wall, cell_size=0.6, cell_height=0.2, agent_radius=0.1, region_min_size=0)
    assert pf.num_islands == 2
    rng = np.random.default_rng(4)
    count = 200
    starts = np.array([pf.get_random_navigable_point() for _ in range(count)])
    ends = starts + rng.uniform(-1.5, 1.5, (count, 3)) * [1.0, 0.0, 1.0]
    lifted = rng.random(count) < 0.4
    ends[lifted, 1] += rng.uniform(4.05, 4.5, lifted.sum())
    assert steps_to_another_island(pf, method, starts, ends) > 0.4 * count
