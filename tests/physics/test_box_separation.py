"""The oriented-box separating-axis filter of the broad phase never drops a touching pair."""

from __future__ import annotations

import fcl
import numpy as np

from engine.physics.collision.collide import boxes_separated
from engine.physics.core.quaternions import quat_to_matrix


def _random_boxes(rng, count):
    q = rng.normal(size=(count, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return (
        rng.uniform(-0.6, 0.6, size=(count, 3)),
        quat_to_matrix(q),
        rng.uniform(0.05, 0.4, (count, 3)),
    )


def _fcl_touch(center_a, rot_a, half_a, center_b, rot_b, half_b) -> bool:
    objects = [
        fcl.CollisionObject(fcl.Box(*(2 * h)), fcl.Transform(r, c))
        for c, r, h in ((center_a, rot_a, half_a), (center_b, rot_b, half_b))
    ]
    return fcl.collide(*objects, fcl.CollisionRequest(), fcl.CollisionResult()) > 0


def test_boxes_separated_agrees_with_fcl_on_random_box_pairs():
    rng = np.random.default_rng(7)
    count = 400
    a, b = _random_boxes(rng, count), _random_boxes(rng, count)
    apart = boxes_separated(*a, *b)
    touching = np.array([_fcl_touch(*(x[k] for x in a), *(x[k] for x in b)) for k in range(count)])
    # the filter may only skip pairs fcl also finds disjoint (a skipped contact is lost)
    assert not np.any(apart & touching)
    # the test is exact for boxes: apart from fcl's own tolerance, it skips every disjoint pair
    assert np.count_nonzero(~apart & ~touching) <= 2
    assert np.count_nonzero(apart) > count // 4  # the sample holds both cases


def test_boxes_separated_by_a_gap_along_one_axis():
    eye = np.eye(3)[None]
    half = np.full((1, 3), 0.1)
    for gap, expected in ((0.001, True), (-0.001, False)):
        apart = boxes_separated(
            np.zeros((1, 3)), eye, half, np.array([[0.2 + gap, 0.05, 0.0]]), eye, half
        )
        assert apart[0] == expected


def test_a_small_cube_sunk_into_a_turned_slab_is_not_separated():
    """A cube of half size 0.05 m whose centre lies 0.4 m from the centre of a slab of half
    extents (0.5, 0.5, 0.5) turned 30 degrees about y, along the slab's own x axis: it
    reaches 0.05 m into the slab, so no axis separates them (either box as A); moved to
    0.6 m, 0.05 m beyond the slab's face, they are apart."""
    angle = np.radians(30.0)
    c, s = np.cos(angle), np.sin(angle)
    slab_rot = np.array([[[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]])
    slab_half, cube_half = np.full((1, 3), 0.5), np.full((1, 3), 0.05)
    cube_rot = np.eye(3)[None]
    for distance, expected in ((0.4, False), (0.6, True)):
        cube_center = distance * slab_rot[:, :, 0]  # along the slab's x axis
        slab = (np.zeros((1, 3)), slab_rot, slab_half)
        cube = (cube_center, cube_rot, cube_half)
        assert boxes_separated(*slab, *cube)[0] == expected
        assert boxes_separated(*cube, *slab)[0] == expected
