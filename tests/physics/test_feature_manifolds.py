"""Fresh manifolds (:mod:`keyed_manifolds`): each step's contacts are the manifold, cut to
four with last step's feature keys winning near-ties, warm-started from the cached point
at the same anchor in B's frame.

* the batched rows against the plain twin :func:`reference_manifolds.keyed_manifold` on
  random histories (points, keys, impulses, reduction to four);
* the warm start follows B's anchor (Jolt's): a fresh point near a cached one in B's
  frame takes its impulses, whatever its key; the keys decide near-ties of the support;
* the keys name features: a box resting on a turned box keeps the same keys step after
  step; a cube sliding on the floor carries its full normal load over (m g h a step);
* the switch: ``feature_manifolds = False`` merges (no keys stored) and both stand a stack.
"""

from __future__ import annotations

import numpy as np
from helpers import add, make_world, register_primitive, run

from engine import mn
from engine.physics.collision.contacts import FreshPoints, ManifoldStore
from engine.physics.core import settings
from engine.physics.pipeline.reference_contacts import Contact, ManifoldPoint
from engine.physics.reference.reference_manifolds import keyed_manifold

IDENTITY = (np.eye(3), np.zeros(3))
UP = np.array([0.0, 1.0, 0.0])


def store_with_row(max_points: int = 4, pair=(1, 2)):
    """A store of one keyable row for ``pair`` (body 0 is the stage: a holding row)."""
    store = ManifoldStore()
    store.add(pair, max_points, keyable=True)
    rotation, position = np.tile(np.eye(3), (3, 1, 1)), np.zeros((3, 3))
    return store, rotation, position


def fresh_of(points_b, depth, keys):
    points_b = np.asarray(points_b, dtype=np.float64)
    point_a = points_b + np.asarray(depth)[:, None] * UP
    normal = np.tile(UP, (len(points_b), 1))
    row = np.zeros(len(points_b), dtype=np.int64)
    return FreshPoints(1, row, point_a, points_b, normal, np.asarray(keys, dtype=np.int64))


def contacts_of(fresh: FreshPoints, n: int) -> list[Contact]:
    return [
        Contact(fresh.point_a[0, k], fresh.point_b[0, k], fresh.normal[0, k], int(fresh.key[0, k]))
        for k in range(n)
    ]


def test_fresh_points_take_the_impulses_of_the_cached_point_at_their_anchor_in_b():
    store, rotation, position = store_with_row()
    fresh = fresh_of([[0.0, 0, 0], [0.1, 0, 0]], [0.001, 0.001], [7, 9])
    store.replace_fresh(np.array([0]), rotation, position, fresh)
    store.impulse[0, :2] = [[1.0, 0.1, 0.2], [2.0, 0.3, 0.4]]
    # a point 5 mm from the second cached anchor takes its impulses (whatever its key); a
    # point 5 cm from both starts from zero; the first cached point is not kept
    fresh = fresh_of([[0.105, 0, 0], [0.0, 0, 0.05]], [0.001, 0.002], [8, 9])
    store.replace_fresh(np.array([0]), rotation, position, fresh)
    assert store.count[0] == 2
    np.testing.assert_array_equal(store.point_key[0, :2], [8, 9])
    np.testing.assert_array_equal(store.impulse[0, :2], [[2.0, 0.3, 0.4], [0.0, 0.0, 0.0]])
    np.testing.assert_array_equal(store.local_b[0, 0], [0.105, 0.0, 0.0])
    # no fresh points: the manifold is empty (nothing is kept from last step)
    store.replace_fresh(np.array([0]), rotation, position, fresh_of(np.zeros((0, 3)), [], []))
    assert store.count[0] == 0


def test_points_at_last_steps_features_win_near_ties_of_the_support():
    # a 20 cm square's corners (keys 1-4) and a point 5 % beyond corner 3 on the diagonal
    # (key 5), all equally deep: without history the far point spans more; with corners
    # 1-4 cached, their keys win (10 % size bonus), and the manifold keeps its four points
    corners = [[-0.1, 0, -0.1], [0.1, 0, -0.1], [0.1, 0, 0.1], [-0.1, 0, 0.1]]
    points = corners + [[0.105, 0, 0.105]]
    for history, expected in ((False, {1, 2, 4, 5}), (True, {1, 2, 3, 4})):
        store, rotation, position = store_with_row()
        if history:
            store.replace_fresh(
                np.array([0]), rotation, position, fresh_of(corners, [0.001] * 4, [1, 2, 3, 4])
            )
        fresh = fresh_of(points, [0.001] * 5, [1, 2, 3, 4, 5])
        store.replace_fresh(np.array([0]), rotation, position, fresh)
        assert set(store.point_key[0, : store.count[0]].tolist()) == expected
        twin = keyed_manifold(
            [ManifoldPoint(np.zeros(3), np.zeros(3), UP, np.zeros(3), k) for k in (1, 2, 3, 4)]
            if history
            else [],
            contacts_of(fresh, 5),
            IDENTITY,
            IDENTITY,
            4,
        )
        assert {p.key for p in twin} == expected


def test_a_rolling_point_keeps_the_cached_impulse_whatever_its_key():
    store, rotation, position = store_with_row(max_points=1)
    store.replace_fresh(np.array([0]), rotation, position, fresh_of([[0, 0, 0]], [0.001], [3]))
    store.impulse[0, 0] = [1.5, 0.2, -0.1]
    store.replace_fresh(np.array([0]), rotation, position, fresh_of([[0.01, 0, 0]], [0.001], [4]))
    np.testing.assert_array_equal(store.impulse[0, 0], [1.5, 0.2, -0.1])


def test_nine_keyed_coplanar_points_keep_the_four_corners():
    grid = [[x, 0.0, z] for x in (-0.1, 0.0, 0.1) for z in (-0.1, 0.0, 0.1)]
    store, rotation, position = store_with_row()
    store.replace_fresh(
        np.array([0]), rotation, position, fresh_of(grid, [0.001] * 9, np.arange(1, 10))
    )
    corners = {(x, z) for x in (-0.1, 0.1) for z in (-0.1, 0.1)}
    kept = {(round(p[0], 9), round(p[2], 9)) for p in store.local_b[0, : store.count[0]]}
    assert store.count[0] == 4 and kept == corners


def test_batched_rows_match_the_plain_twin_on_a_random_history():
    # a stage row (holding: fewer than three fresh points keep their untaken cached
    # points still touching) and a row of two bodies, a box row and a rolling one
    rng = np.random.default_rng(3)
    held = 0
    for max_points, pair in ((4, (0, 1)), (1, (0, 1)), (4, (1, 2))):
        store, rotation, position = store_with_row(max_points, pair)
        turn = mn.Quaternion.rotation(mn.Rad(0.3), mn.Vector3(0.3, 1.0, -0.2).normalized())
        rotation[pair[1]] = np.array(turn.to_matrix())
        position[pair[1]] = [0.02, 0.1, -0.03]
        frame_a, frame_b = IDENTITY, (rotation[pair[1]], position[pair[1]])
        cached: list[ManifoldPoint] = []
        for step in range(40):
            n = int(rng.integers(0, 9))
            points = rng.uniform(-0.1, 0.1, size=(n, 3)) * [1, 0, 1]
            keys = rng.choice(np.arange(1, 13), size=n, replace=False)  # unique in the row
            fresh = fresh_of(points, rng.uniform(-0.003, 0.004, size=n), keys)
            store.replace_fresh(np.array([0]), rotation, position, fresh)
            hold = pair[0] == 0
            cached = keyed_manifold(
                cached, contacts_of(fresh, n), frame_a, frame_b, max_points, hold=hold
            )
            count = int(store.count[0])
            assert count == len(cached), step
            held += count > n  # cached points kept beside the fresh ones
            assert hold or count <= n
            # the inherited impulses (warm start), then the solver's, tagged per step and slot
            inherited = np.array([p.impulse for p in cached]).reshape(count, 3)
            np.testing.assert_array_equal(store.impulse[0, :count], inherited)
            tags = np.arange(count)[:, None] + [step, 0.5, -0.25]
            store.impulse[0, :count] = tags
            for point, tag in zip(cached, tags, strict=True):
                point.impulse = tag.copy()
            np.testing.assert_array_equal(store.point_key[0, :count], [p.key for p in cached])
            for name in ("local_a", "local_b", "normal_local"):
                twin = np.array([getattr(p, name) for p in cached]).reshape(count, 3)
                np.testing.assert_allclose(getattr(store, name)[0, :count], twin, atol=1e-12)
    assert held > 5  # the holding rule ran


def test_the_step_keeps_keys_of_a_resting_turned_box_and_carries_its_load(monkeypatch):
    monkeypatch.setattr(settings, "TIME_TO_SLEEP", float("inf"))  # stepped to the end
    world, templates = make_world()
    world.settings.feature_manifolds = True
    world.settings.contact_cache = False  # ask the narrow phase every step
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    lower = add(world, templates, handle, [0.0, 0.1, 0.0])
    upper = add(world, templates, handle, [0.0, 0.3, 0.0])
    upper.rotation = mn.Quaternion.rotation(mn.Deg(30.0), mn.Vector3(0.0, 1.0, 0.0))
    run(world, 1.0)
    store = world.manifolds
    row = store.row((lower.object_id, upper.object_id))
    keys_before = sorted(store.point_key[row, : store.count[row]].tolist())
    run(world, 0.1)
    keys_after = sorted(store.point_key[row, : store.count[row]].tolist())
    assert store.count[row] == 4 and keys_before == keys_after and all(keys_after)
    # the normal impulses of the last step carry the upper cube's weight: m g h
    weight_impulse = upper.mass * 9.8 * 0.008
    assert abs(store.impulse[row, :4, 0].sum() / weight_impulse - 1.0) < 0.02


def test_the_switch_merges_without_keys_and_both_stand_a_stack():
    for keyed in (True, False):
        world, templates = make_world()
        world.settings.feature_manifolds = keyed
        handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
        boxes = [add(world, templates, handle, [0.0, 0.1 + 0.2 * k, 0.0]) for k in range(5)]
        run(world, 3.0)
        rows = world.manifolds.rows_with_points()
        assert (world.manifolds.point_key[rows] != 0).any() == keyed
        # the floor's row is fresh too (keyed), or merged (no keys)
        floor = rows[world.manifolds.bodies[rows, 0] == 0]
        assert len(floor) == 1 and (world.manifolds.point_key[floor] != 0).any() == keyed
        top = np.asarray(boxes[-1].translation)
        assert abs(top[0]) < 1e-3 and abs(top[2]) < 1e-3 and abs(top[1] - 0.9) < 0.01
