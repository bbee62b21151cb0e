"""A step never leaves its island (Habitat's ``try_step``: an end that snaps to another island,
or to nothing, returns the start unchanged).

Scene: a 6 x 6 m floor (y = 0) split by a thin 2 m wall across x at z in [2.97, 3.03],
agent radius 3 cm: island A (z < 2.97 minus the radius) and island B beyond the wall. Ends
are drawn all around starts near the wall on either side, some on the other island, some
off the grid, some far above the floor; whatever the end, the result lies on the start's
island, and it is the start itself exactly when the end snaps to another island or to no
navmesh at all.
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.navmesh.conftest import box, build

FLOOR_Y = 0.0


@pytest.fixture(scope="module")
def split_room():
    floor = box((0.0, -0.1, 0.0), (6.0, 0.0, 6.0))
    wall = box((0.0, 0.0, 2.97), (6.0, 2.0, 3.03))
    return build(floor, wall, agent_radius=0.03)


def random_steps(seed: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Starts within 0.25 m of the wall on either island, ends up to 0.5 m away in any
    direction (so many lie just across the wall), a quarter of them lifted 1-3 m above the
    floor, some beyond the floor's edge."""
    rng = np.random.default_rng(seed)
    start_z = rng.uniform(2.7, 2.9, count) + np.where(rng.random(count) < 0.5, 0.0, 0.4)
    starts = np.column_stack([rng.uniform(0.05, 5.95, count), np.full(count, FLOOR_Y), start_z])
    offsets = rng.uniform(-0.5, 0.5, (count, 3))
    offsets[:, 1] = np.where(rng.random(count) < 0.25, rng.uniform(1.0, 3.0, count), 0.0)
    return starts, starts + offsets


@pytest.mark.parametrize("method", ["try_step", "try_step_no_sliding"])
def test_steps_stay_on_the_start_island_and_stop_dead_at_another(split_room, method):
    pf = split_room
    starts, ends = random_steps(seed=7, count=400)
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
