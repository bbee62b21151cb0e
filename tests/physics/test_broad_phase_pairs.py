"""Broad phase on hand-made boxes: which pairs of world AABBs overlap.

Two boxes overlap iff their intervals overlap on all three axes (touching counts); a pair
is reported once, as ``(a, b)`` with ``a < b``, only if one of the two bodies can move and
both are collision candidates. The brute-force path, the sort-and-sweep path and the switch
between them must all give these pairs.
"""

from __future__ import annotations

import numpy as np
import pytest

from engine.physics.collision.collide import (
    all_pairs_overlaps,
    overlapping_pairs,
    sweep_and_prune_overlaps,
    world_aabbs,
)

# (lo, hi, active) per body
BOXES = [
    ((-5.0, -1.0, -5.0), (5.0, 0.0, 5.0), False),  # 0: a static floor, top at y = 0
    ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), True),  # 1: rests on the floor (faces touch)
    ((0.5, 0.5, 0.5), (1.5, 1.5, 1.5), True),  # 2: overlaps 1, hovers 0.5 m over the floor
    ((3.0, 0.2, 3.0), (4.0, 1.0, 4.0), False),  # 3: static, hovers over the floor
    ((3.0, 0.2, 4.5), (4.0, 1.0, 5.5), True),  # 4: beside 3, 0.5 m apart along z only
    ((4.0, 0.5, 3.5), (4.5, 0.8, 3.8), False),  # 5: static, touches static 3
    ((1.5, 1.5, 1.5), (2.0, 2.0, 2.0), True),  # 6: touches 2 corner to corner
    ((3.5, 0.5, 5.0), (3.8, 0.8, 5.2), False),  # 7: static, inside 4 (higher index)
    ((0.2, 0.2, 0.2), (0.4, 0.4, 0.4), True),  # 8: inside 1, but not a candidate
]
EXPECTED = [[0, 1], [1, 2], [2, 6], [4, 7]]
FINDERS = [all_pairs_overlaps, sweep_and_prune_overlaps, overlapping_pairs]


def scene(order: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(lo, hi, candidates, active)`` with body ``k`` of BOXES stored at index ``order[k]``."""
    lo, hi = np.empty((len(BOXES), 3)), np.empty((len(BOXES), 3))
    active = np.zeros(len(BOXES), dtype=bool)
    for k, (box_lo, box_hi, moves) in enumerate(BOXES):
        lo[order[k]], hi[order[k]], active[order[k]] = box_lo, box_hi, moves
    candidates = np.sort(order[:8])  # body 8 does not collide
    return lo, hi, candidates, active


@pytest.mark.parametrize("find", FINDERS, ids=lambda f: f.__name__)
def test_touching_and_overlapping_boxes_pair_up_once(find):
    lo, hi, candidates, active = scene(np.arange(len(BOXES)))
    np.testing.assert_array_equal(find(lo, hi, candidates, active), EXPECTED)


@pytest.mark.parametrize("find", FINDERS, ids=lambda f: f.__name__)
def test_the_pairs_do_not_depend_on_how_bodies_are_numbered(find):
    rng = np.random.default_rng(26)
    for _ in range(10):
        order = rng.permutation(len(BOXES))
        lo, hi, candidates, active = scene(order)
        renamed = np.sort(order[np.array(EXPECTED)], axis=1)
        expected = renamed[np.lexsort((renamed[:, 1], renamed[:, 0]))]
        np.testing.assert_array_equal(find(lo, hi, candidates, active), expected)


@pytest.mark.parametrize("find", FINDERS, ids=lambda f: f.__name__)
def test_resting_bodies_make_no_pairs(find):
    lo, hi, candidates, active = scene(np.arange(len(BOXES)))
    assert find(lo, hi, candidates, np.zeros_like(active)).shape == (0, 2)


def test_a_row_of_overlapping_boxes_pairs_each_with_its_neighbours_only():
    """1000 unit boxes 0.9 m apart along x (more than the brute-force budget, so the switch
    sorts and sweeps): box i overlaps boxes i - 1 and i + 1 and no other."""
    n = 1000
    center = np.zeros((n, 3))
    center[:, 0] = 0.9 * np.arange(n)
    lo, hi = center - 0.5, center + 0.5
    pairs = overlapping_pairs(lo, hi, np.arange(n), np.ones(n, dtype=bool))
    np.testing.assert_array_equal(pairs, np.stack([np.arange(n - 1), np.arange(1, n)], axis=1))


def test_world_aabb_of_a_turned_and_moved_box():
    """A box of half extents (1, 0.5, 0.25) centred 0.1 m along its own x, turned 90 degrees
    about z (its x now points along world y) and moved to (2, 3, 4)."""
    quarter_turn_z = np.array([[0.0, 0.0, np.sin(np.pi / 4), np.cos(np.pi / 4)]])  # xyzw
    lo, hi = world_aabbs(
        np.array([[0.1, 0.0, 0.0]]),
        np.array([[1.0, 0.5, 0.25]]),
        np.array([[2.0, 3.0, 4.0]]),
        quarter_turn_z,
    )
    np.testing.assert_allclose(lo, [[1.5, 2.1, 3.75]], atol=1e-12)
    np.testing.assert_allclose(hi, [[2.5, 4.1, 4.25]], atol=1e-12)
