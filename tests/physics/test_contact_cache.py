"""Contact cache (``SolverSettings.contact_cache``): pairs that barely moved keep their manifold.

Truths checked: a resting stack stops asking the narrow phase (and stays as it is), a pair
that starts sliding is asked again, the cache changes trajectories by less than the cache
distance allows, both paths skip the same pairs, and the greedy coloring is the textbook one.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

import engine.physics.pipeline.collision_stage as collision_stage
from engine.physics.core import settings as physics_settings
from engine.physics.solver.coloring import color_manifolds


@pytest.fixture
def no_sleep(monkeypatch):
    """Bodies never fall asleep, so resting pairs stay in the broad phase."""
    monkeypatch.setattr(physics_settings, "TIME_TO_SLEEP", float("inf"))


@pytest.fixture
def queried(monkeypatch):
    """Counts the pairs the narrow phase is asked about, step by step."""
    counts: list[int] = []
    original = collision_stage.narrow_phase

    def counting(bodies, objects, store, pairs, rotation):
        counts.append(len(pairs))
        return original(bodies, objects, store, pairs, rotation)

    monkeypatch.setattr(collision_stage, "narrow_phase", counting)
    return counts


def _stack(cache: bool, n: int = 3, vectorized: bool = True):
    world, templates = make_world()
    world.settings.contact_cache = cache
    world.settings.use_vectorized = vectorized
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    boxes = [add(world, templates, handle, [0.0, 0.1 + 0.2 * i, 0.0]) for i in range(n)]
    return world, templates, boxes


def test_resting_stack_stops_querying_and_stays(no_sleep, queried):
    world, _, boxes = _stack(cache=True)
    run(world, 1.0)
    queried.clear()
    start = np.array([np.asarray(b.translation) for b in boxes])
    run(world, 1.0)
    # 3 pairs touch (floor-box, box-box, box-box); after settling none needs a new query
    assert sum(queried[-60:]) == 0
    final = np.array([np.asarray(b.translation) for b in boxes])
    assert np.abs(final - start).max() < 1e-3
    assert len(world.manifolds) == 3


def test_sliding_pair_is_queried_again(no_sleep, queried):
    world, _, boxes = _stack(cache=True, n=1)
    run(world, 1.0)
    row = world.manifolds.row((0, boxes[0].object_id))
    anchors_before = world.manifolds.local_a[row].copy()
    queried.clear()
    boxes[0].linear_velocity = [1.0, 0.0, 0.0]
    run(world, 0.1)
    assert sum(queried) > 0
    # the floor anchors follow the sliding box (the manifold was rebuilt, not frozen)
    row = world.manifolds.row((0, boxes[0].object_id))
    shift = world.manifolds.local_a[row, :, 0].mean() - anchors_before[:, 0].mean()
    assert shift > 0.02


def test_cache_changes_a_pile_by_little(no_sleep):
    finals = []
    for cache in (False, True):
        world, templates = make_world()
        world.settings.contact_cache = cache
        handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
        boxes = [
            add(world, templates, handle, [0.05 * (i % 2), 0.1 + 0.21 * i, 0.0]) for i in range(4)
        ]
        run(world, 2.0)
        finals.append(np.array([np.asarray(b.translation) for b in boxes]))
        # nothing sank into the floor deeper than the slop allows
        assert finals[-1][:, 1].min() > 0.1 - 0.005
    assert np.abs(finals[0] - finals[1]).max() < 0.01


def test_both_paths_skip_the_same_pairs(no_sleep, monkeypatch):
    asked: list[list] = []
    original = collision_stage.changed_pairs

    def recording(bodies, store, pairs, rotation):
        out = original(bodies, store, pairs, rotation)
        asked[-1].append(list(out))
        return out

    monkeypatch.setattr(collision_stage, "changed_pairs", recording)
    for vectorized in (True, False):
        world, _, boxes = _stack(cache=True, vectorized=vectorized)
        boxes[-1].linear_velocity = [0.3, 0.0, 0.0]
        asked.append([])
        run(world, 0.8)
    assert asked[0] == asked[1]
    assert any(len(step) < 3 for step in asked[0])  # some pairs were skipped


def test_reference_path_with_cache_matches(no_sleep):
    finals = []
    for vectorized in (True, False):
        world, _, boxes = _stack(cache=True, vectorized=vectorized)
        boxes[-1].linear_velocity = [0.3, 0.0, 0.0]
        run(world, 0.8)
        finals.append(np.array([np.asarray(b.translation) for b in boxes]))
    assert np.abs(finals[0] - finals[1]).max() < 1e-9


def _textbook_coloring(body_a, body_b, is_dynamic):
    """Plain greedy: the first color whose set holds neither dynamic body."""
    colors, used = [], []
    for index, (a, b) in enumerate(zip(body_a.tolist(), body_b.tolist(), strict=True)):
        color = next(
            (
                c
                for c, bodies in enumerate(used)
                if not ((is_dynamic[a] and a in bodies) or (is_dynamic[b] and b in bodies))
            ),
            len(used),
        )
        if color == len(used):
            colors.append([])
            used.append(set())
        colors[color].append(index)
        used[color].update(x for x in (a, b) if is_dynamic[x])
    return colors


def test_bitmask_coloring_is_the_textbook_greedy():
    rng = np.random.default_rng(3)
    for _ in range(20):
        n = int(rng.integers(2, 40))
        body_a = rng.integers(0, n, size=60)
        body_b = rng.integers(0, n, size=60)
        is_dynamic = rng.random(n) < 0.8
        fast = color_manifolds(body_a, body_b, is_dynamic)
        assert [c.tolist() for c in fast] == _textbook_coloring(body_a, body_b, is_dynamic)


def test_sweep_and_prune_finds_the_brute_force_pairs():
    from engine.physics.collision.collide import all_pairs_overlaps, sweep_and_prune_overlaps

    rng = np.random.default_rng(5)
    for trial in range(30):
        n = int(rng.integers(1, 300))
        center = rng.uniform(-3, 3, size=(n, 3)) * [1.0, 0.3 + trial % 3, 1.0]
        half = rng.uniform(0.05, 0.4, size=(n, 3))
        lo, hi = center - half, center + half
        if trial % 4 == 0:  # touching boxes and equal bounds: the comparisons are inclusive
            lo[1::2] = np.round(lo[1::2], 1)
            hi[::2] = np.round(lo[1::2].repeat(2, axis=0)[: len(hi[::2])], 1)
            hi = np.maximum(hi, lo)
        lo[0], hi[0] = [-50, -1, -50], [50, 0, 50]  # a stage-like floor under everything
        candidates = np.flatnonzero(rng.random(n) < 0.9)
        active = rng.random(n) < [0.0, 0.1, 0.7, 1.0][trial % 4]
        brute = all_pairs_overlaps(lo, hi, candidates, active)
        swept = sweep_and_prune_overlaps(lo, hi, candidates, active)
        assert np.array_equal(brute, swept)


def test_deepest_record_matches_the_numpy_tie_rule():
    from types import SimpleNamespace

    from engine.physics.collision.contact_helpers import deepest_record
    from engine.physics.collision.contacts import tie_key

    rng = np.random.default_rng(7)
    for _ in range(200):
        depths = rng.choice(
            [0.01, 0.01 + 4e-10, 0.01 + 6e-10, 0.02, -0.02, 1.5e-9, 2.5e-9],
            size=int(rng.integers(1, 8)),
        )
        records = [SimpleNamespace(penetration_depth=float(d)) for d in depths]
        expected = records[int(np.argmax(tie_key(np.abs(depths))))]
        assert deepest_record(records) is expected
