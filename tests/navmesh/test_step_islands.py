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
    other_island_ends = 0
    for start, end in zip(starts, ends, strict=True):
        start_island = pf.get_island(start)
        assert start_island >= 0
        result = getattr(pf, method)(start, end)
        assert pf.get_island(result) == start_island, (start, end, result)
        end_island = pf.get_island(pf.snap_point(end))
        if not np.all(np.isfinite(pf.snap_point(end))) or end_island != start_island:
            other_island_ends += 1
            assert np.array_equal(result, start), (start, end, result)
    assert other_island_ends > 20  # the sample really tries the other island and the void


def test_a_long_step_reaches_the_first_square_of_the_navmesh(split_room):
    """A step ending on the navmesh's first square (node 0: the lowest row and column) from
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
