"""Analytic box-box contacts (engine/physics/collision/box_box.py) against fcl, hand geometry
and the per-pair reference (engine/physics/reference/reference_box_box.py)."""

from __future__ import annotations

import fcl
import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

from engine.physics import MotionType
from engine.physics.collision.box_box import box_box_contacts, separating_axes
from engine.physics.core import settings
from engine.physics.core.quaternions import quat_to_matrix
from engine.physics.reference.reference_box_box import box_box_contacts_reference


def _random_pairs(count: int, seed: int = 0, reach=(0.1, 0.6), tilt: float | None = None):
    """Boxes of random sizes and orientations (within ``tilt`` of the axes when given), B's
    center at a random distance from A's (``reach=None``: touching, see below)."""
    rng = np.random.default_rng(seed)
    half_a, half_b = rng.uniform(0.05, 0.3, (count, 3)), rng.uniform(0.05, 0.3, (count, 3))
    q = rng.normal(size=(2, count, 4))
    if tilt is not None:  # [x, y, z, w]: small vector part, nearly aligned boxes
        q[..., :3] *= tilt
        q[..., 3] = 1.0
    q /= np.linalg.norm(q, axis=2, keepdims=True)
    rot_a, rot_b = quat_to_matrix(q[0]), quat_to_matrix(q[1])
    direction = rng.normal(size=(count, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    center_a = rng.uniform(-1, 1, (count, 3))
    if reach is None:  # touching: B moved along `direction` until the boxes overlap 0-15 mm
        target = -rng.uniform(-0.002, 0.015, count)  # separation wanted, m
        low, high = np.zeros(count), np.full(count, 2.0)
        for _ in range(40):  # bisection: the separation grows with the distance
            middle = 0.5 * (low + high)
            center_b = center_a + direction * middle[:, None]
            _, separation, _ = separating_axes(center_a, rot_a, half_a, center_b, rot_b, half_b)
            too_far = separation.max(axis=1) > target
            high, low = np.where(too_far, middle, high), np.where(too_far, low, middle)
        return center_a, rot_a, half_a, center_a + direction * low[:, None], rot_b, half_b
    center_b = center_a + direction * rng.uniform(*reach, (count, 1))
    return center_a, rot_a, half_a, center_b, rot_b, half_b


def _fcl_contacts(center_a, rot_a, half_a, center_b, rot_b, half_b):
    objects = [
        fcl.CollisionObject(fcl.Box(*(2 * half)), fcl.Transform(rot, center))
        for center, rot, half in ((center_a, rot_a, half_a), (center_b, rot_b, half_b))
    ]
    request = fcl.CollisionRequest(num_max_contacts=32, enable_contact=True)
    result = fcl.CollisionResult()
    fcl.collide(*objects, request, result)
    return result.contacts


def _per_pair(frames, k):
    """Pair k as the reference path's boxes: (center, axes as rows, half extents)."""
    center_a, rot_a, half_a, center_b, rot_b, half_b = frames
    box_a = (center_a[k], rot_a[k].T.copy(), half_a[k])
    box_b = (center_b[k], rot_b[k].T.copy(), half_b[k])
    return box_a, box_b


def test_normal_depth_and_region_agree_with_fcl():
    """Shallow overlaps (what a solver sees): fcl's deepest normal and depth, and fcl's
    points inside the region of ours."""
    frames = _random_pairs(400, seed=1, reach=None)
    pair, _, point_a, point_b, normal, deep = box_box_contacts(*frames)
    depth = ((point_a - point_b) * normal).sum(axis=1)
    checked = agreeing = 0
    for k in range(len(frames[0])):
        records = _fcl_contacts(*(f[k] for f in frames))
        ours = pair == k
        if not records:
            # apart for fcl: at most speculative points of ours (no overlap)
            assert depth[ours].max(initial=-1.0) <= 1e-9
            continue
        deepest = max(records, key=lambda r: abs(r.penetration_depth))
        if abs(deepest.penetration_depth) > 0.015:
            continue  # deep overlaps: BOX_DEEP_OVERLAP hands them to fcl
        checked += 1
        assert ours.any() and not deep[k]
        cos = float(normal[ours][0] @ np.asarray(deepest.normal))
        if cos < 0.99:
            continue  # an edge/face near-tie resolved the other way
        agreeing += 1
        assert depth[ours].max() == pytest.approx(abs(deepest.penetration_depth), abs=1e-3)
        lo = np.minimum(point_a[ours], point_b[ours]).min(axis=0)
        hi = np.maximum(point_a[ours], point_b[ours]).max(axis=0)
        slack = abs(deepest.penetration_depth) + 3e-3
        for record in records:
            assert np.all(np.asarray(record.pos) >= lo - slack)
            assert np.all(np.asarray(record.pos) <= hi + slack)
    assert checked > 300
    assert agreeing >= 0.97 * checked


def test_reference_path_gives_the_same_contacts():
    groups = (
        _random_pairs(200, seed=2, reach=None),  # touching, any orientation (edges, corners)
        _random_pairs(200, seed=4, reach=None, tilt=0.02),  # nearly aligned: face clipping
        _random_pairs(100, seed=3),  # anywhere: apart, touching or deep
    )
    frames = [np.concatenate(parts) for parts in zip(*groups, strict=True)]
    pair, local, point_a, point_b, normal, deep = box_box_contacts(*frames)
    assert 0 < deep.sum() and len(np.unique(pair)) > 400 and len(pair) > 600
    assert (np.bincount(pair) >= 4).sum() > 20  # face clipping with several points
    for k in range(len(frames[0])):
        expected = box_box_contacts_reference(*_per_pair(frames, k))
        ours = pair == k
        if deep[k]:
            assert expected is None and not ours.any()
            continue
        assert len(expected) == ours.sum()
        for contact, a, b, n in zip(
            expected, point_a[ours], point_b[ours], normal[ours], strict=True
        ):
            np.testing.assert_allclose(contact.point_a, a, atol=1e-12)
            np.testing.assert_allclose(contact.point_b, b, atol=1e-12)
            np.testing.assert_allclose(contact.normal, n, atol=1e-12)


def _one(center_a, rot_a, half_a, center_b, rot_b, half_b):
    frames = [np.asarray(x, dtype=np.float64)[None] for x in (center_a, rot_a, half_a)]
    frames += [np.asarray(x, dtype=np.float64)[None] for x in (center_b, rot_b, half_b)]
    _, _, point_a, point_b, normal, _ = box_box_contacts(*frames)
    return point_a, point_b, normal, ((point_a - point_b) * normal).sum(axis=1)


def _rotation_about(axis: str, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return {
        "x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
        "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
        "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]),
    }[axis]


def test_cube_resting_on_a_slab_gets_its_four_bottom_corners():
    eye = np.eye(3)
    # slab half height 0.05 (top at y = 0.05), cube half 0.1 sunk 1 mm: center y = 0.149
    point_a, point_b, normal, depth = _one(
        [0, 0, 0], eye, [1.0, 0.05, 1.0], [0.3, 0.149, -0.2], eye, [0.1, 0.1, 0.1]
    )
    assert len(depth) == 4
    np.testing.assert_allclose(normal, [[0, 1, 0]] * 4, atol=1e-12)
    np.testing.assert_allclose(depth, 0.001, atol=1e-12)
    np.testing.assert_allclose(point_a[:, 1], 0.05, atol=1e-12)  # on the slab's top
    corners = {(round(x, 9), round(z, 9)) for x, _, z in point_b}
    assert corners == {(0.4, -0.1), (0.2, -0.1), (0.2, -0.3), (0.4, -0.3)}


def test_aligned_stack_gets_four_points_and_an_overhang_the_overlap_corners():
    eye, half = np.eye(3), [0.1, 0.1, 0.1]
    _, point_b, _, depth = _one([0, 0, 0], eye, half, [0, 0.199, 0], eye, half)
    assert len(depth) == 4  # no duplicates where the corners coincide
    np.testing.assert_allclose(depth, 0.001, atol=1e-12)
    # the upper cube 5 cm over the edge along x: the overlap is x in [-0.05, 0.1]
    point_a, point_b, normal, depth = _one([0, 0, 0], eye, half, [0.05, 0.199, 0], eye, half)
    np.testing.assert_allclose(normal, [[0, 1, 0]] * len(depth), atol=1e-12)
    xs = sorted({round(p[0], 9) for p in point_a})
    assert xs == [-0.05, 0.1] and len(depth) == 4


def test_crossed_edges_touch_at_one_point():
    # A: cube rotated 45 deg about z (an edge along z on top, at y = 0.1 sqrt 2);
    # B: cube rotated 45 deg about x (an edge along x at its bottom), 1 mm into A's edge
    top = 0.1 * np.sqrt(2.0)
    rot_a, rot_b = _rotation_about("z", np.pi / 4), _rotation_about("x", np.pi / 4)
    point_a, point_b, normal, depth = _one(
        [0, 0, 0], rot_a, [0.1] * 3, [0, 2 * top - 0.001, 0], rot_b, [0.1] * 3
    )
    assert len(depth) == 1
    np.testing.assert_allclose(normal[0], [0, 1, 0], atol=1e-9)
    np.testing.assert_allclose(depth[0], 0.001, atol=1e-9)
    np.testing.assert_allclose(point_a[0], [0, top, 0], atol=1e-9)


def test_gaps_within_the_speculative_distance_give_speculative_points_only():
    eye, half = np.eye(3), [0.1, 0.1, 0.1]
    gap = 0.5 * settings.SPECULATIVE_DISTANCE
    _, _, _, depth = _one([0, 0, 0], eye, half, [0, 0.2 + gap, 0], eye, half)
    np.testing.assert_allclose(depth, -gap, atol=1e-12)
    _, _, _, depth = _one(
        [0, 0, 0], eye, half, [0, 0.2 + 2 * settings.SPECULATIVE_DISTANCE, 0], eye, half
    )
    assert len(depth) == 0


@pytest.mark.parametrize("vectorized", [True, False])
def test_deep_box_pair_asks_fcl_at_the_current_poses(vectorized):
    """Box pairs do not move their fcl objects (analytic contacts); a pair left to fcl (deeper
    than BOX_DEEP_OVERLAP) moves them first, so its contacts follow the bodies' poses even
    when the fcl objects were last placed far away."""
    from engine.physics.pipeline.collision_stage import collision_stage

    from .helpers import add, make_world, register_primitive

    world, templates = make_world(floor=False, gravity=(0.0, 0.0, 0.0))
    world.settings.use_vectorized = vectorized
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    box_a = add(world, templates, handle, [0.0, 0.0, 0.0])
    box_b = add(world, templates, handle, [5.0, 0.0, 0.0])  # fcl objects placed here
    b, overlap = world.bodies, 0.05
    b.body_position[box_b.object_id] = [0.2 - overlap, 0.0, 0.0]  # no fcl update
    assert overlap > settings.BOX_DEEP_OVERLAP
    collision_stage(b, world.collision_objects, world.manifolds, world.settings)
    row = world.manifolds.row((box_a.object_id, box_b.object_id))
    assert row is not None and world.manifolds.count[row] > 0
    point_a, point_b, normal = world.manifolds.world_points(
        np.array([row]), quat_to_matrix(b.body_rotation[: b.count]), b.body_position[: b.count]
    )
    used = world.manifolds.count[row]
    depth = ((point_a - point_b) * normal).sum(axis=2)[0, :used]
    np.testing.assert_allclose(np.abs(normal[0, :used, 0]), 1.0, atol=1e-9)
    np.testing.assert_allclose(depth, overlap, atol=1e-9)


def test_a_cube_overhanging_a_support_of_its_own_width_stays_put():
    # A 1 m cube on a 1 m wide static box, shifted 0.3 m so it overhangs by 0.3 m with its
    # center of mass over the support. Both contact faces have 1 m edges that cross each
    # other: the manifold must hold the crossing points, or the cube creeps sideways. At
    # rest it only settles into the contact slop (vertical), and drifts < 0.1 mm laterally.
    world, templates = make_world(floor=False)
    support = add(world, templates, register_primitive(templates, half=(0.5, 0.5, 1.0)), [0, 0, 0])
    support.motion_type = MotionType.STATIC
    cube = add(world, templates, register_primitive(templates, half=(0.5, 0.5, 0.5)), [0.3, 1, 0.3])
    run(world, 2.0)
    position = np.asarray(cube.translation)
    np.testing.assert_allclose(position[[0, 2]], [0.3, 0.3], atol=1e-4)
    assert position[1] == pytest.approx(1.0, abs=settings.PENETRATION_SLOP)
    assert not cube.awake


def test_coplanar_thin_plates_are_pushed_apart_along_plus_u_on_both_paths():
    """Two 1 mm plates at the same height, overlapping 5 cm edge to edge: the least overlap
    is their thickness, along y, where the centres coincide (``u . (c_b - c_a) = 0``). The
    rule for that tie is ``n = +u`` (B pushed up), the same on the batched and the reference
    path, with the full thickness as the depth."""
    eye = np.eye(3)
    half = np.array([0.1, 0.0005, 0.1])
    point_a, point_b, normal, depth = _one([0, 0, 0], eye, half, [0.15, 0, 0], eye, half)
    assert len(normal) > 0
    np.testing.assert_allclose(normal, np.tile([0.0, 1.0, 0.0], (len(normal), 1)))
    np.testing.assert_allclose(depth, 2 * half[1], atol=1e-12)
    origin, beside = np.zeros(3), np.array([0.15, 0.0, 0.0])
    expected = box_box_contacts_reference((origin, eye, half), (beside, eye, half))
    assert len(expected) == len(normal)
    for contact, a, b, n in zip(expected, point_a, point_b, normal, strict=True):
        np.testing.assert_allclose(contact.normal, n, atol=1e-12)
        np.testing.assert_allclose(contact.point_a, a, atol=1e-12)
        np.testing.assert_allclose(contact.point_b, b, atol=1e-12)
