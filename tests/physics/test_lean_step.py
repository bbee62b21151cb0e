"""The lean step's Python-loop removals change no number: each against its plain definition.

* the greedy coloring (one set of color bits per body, solved in NumPy-prepared slots)
  against the first-fit greedy coloring written out manifold by manifold;
* the narrow phase's job filing (pairs grouped by their bodies' kinds in NumPy) against one
  walk over the pairs and their shape pairs;
* the solver order kept while the contact graph is unchanged, and the stage rows swept as
  one batch, against recomputing the order every step and sweeping color by color: the
  same trajectories bit for bit;
* the shock levels (one breadth-first search over Python lists) against growing the
  reached set level by level over all pairs.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from helpers import add, make_world, register_primitive

from engine import mn
from engine.physics.collision.contacts import GraphMemo
from engine.physics.pipeline.narrow_phase import _file_jobs
from engine.physics.pipeline.pair_table import PAIR_TABLE
from engine.physics.pipeline.solve_stage import lower_bodies
from engine.physics.solver import stage_priority
from engine.physics.solver.coloring import color_manifolds


def first_fit_colors(body_a, body_b, is_dynamic) -> list[list[int]]:
    """The definition: manifold by manifold, the lowest color none of its dynamic bodies
    has yet."""
    colors: list[list[int]] = []
    taken: dict[int, set[int]] = {}
    for index, (a, b) in enumerate(zip(body_a.tolist(), body_b.tolist(), strict=True)):
        used = set()
        for body in (a, b):
            if is_dynamic[body]:
                used |= taken.setdefault(body, set())
        color = next(c for c in range(len(colors) + 1) if c not in used)
        if color == len(colors):
            colors.append([])
        colors[color].append(index)
        for body in (a, b):
            if is_dynamic[body]:
                taken[body].add(color)
    return colors


@pytest.mark.parametrize("seed", range(20))
def test_coloring_is_the_first_fit_greedy_coloring(seed):
    rng = np.random.default_rng(seed)
    n, m = int(rng.integers(2, 30)), int(rng.integers(0, 120))
    body_a = rng.integers(0, n, size=m)
    body_b = (body_a + rng.integers(1, n, size=m)) % n
    is_dynamic = rng.random(n) < 0.8
    colors = color_manifolds(body_a, body_b, is_dynamic)
    assert [c.tolist() for c in colors] == first_fit_colors(body_a, body_b, is_dynamic)
    assert all(c.dtype == np.int64 for c in colors)


def test_coloring_of_a_body_with_more_manifolds_than_a_machine_word_has_bits():
    body_a = np.zeros(100, dtype=np.int64)  # one dynamic plank under 100 cubes
    body_b = np.arange(1, 101)
    colors = color_manifolds(body_a, body_b, np.ones(101, dtype=bool))
    assert [c.tolist() for c in colors] == [[k] for k in range(100)]


def shape(kind: str, name: str) -> SimpleNamespace:
    return SimpleNamespace(kind=kind, name=name)


def test_job_filing_matches_one_walk_over_the_pairs():
    # body 0 the stage mesh, bodies 1-4 boxes, 5 a hull and a box, 6 a sphere
    kinds = {0: ("mesh",), 5: ("convex", "box"), 6: ("sphere",)}
    kinds.update({k: ("box",) for k in range(1, 5)})
    entries = {
        body: [
            (shape(kind, f"{body}.{k}"), f"obj{body}.{k}", f"probe{body}.{k}")
            for k, kind in enumerate(ks)
        ]
        for body, ks in kinds.items()
    }
    code_kinds = sorted(set(kinds.values()))
    objects = SimpleNamespace(
        shape_entries=entries,
        code_kinds=code_kinds,
        kind_code=np.array([code_kinds.index(kinds[b]) for b in range(7)], dtype=np.int64),
    )
    pairs = [(0, 1), (0, 5), (1, 2), (1, 5), (2, 3), (0, 6), (3, 4), (5, 6), (4, 5), (0, 2)]
    jobs = {rule.name: [] for rule in PAIR_TABLE.rules}
    pair_of_seq, first_seq = _file_jobs(objects, pairs, jobs)
    # the plain walk: pairs in order, A's shapes, then B's
    expected = {rule.name: [] for rule in PAIR_TABLE.rules}
    expected_pairs = []
    for position, (a, c) in enumerate(pairs):
        for shape_a, object_a, _ in entries[a]:
            for shape_c, object_c, probe_c in entries[c]:
                job = (len(expected_pairs), shape_a, a, object_a, shape_c, c, object_c, probe_c)
                expected[PAIR_TABLE.rule_for(shape_a.kind, shape_c.kind).name].append(job)
                expected_pairs.append(position)
    assert pair_of_seq.tolist() == expected_pairs
    # each pair's first job (the contact keys count shape pairs from it)
    assert first_seq.tolist() == [expected_pairs.index(k) for k in range(len(pairs))]
    assert {k: [tuple(j)[:8] for j in v] for k, v in jobs.items()} == expected


def pile(memo_every_step: bool, per_color_stage: bool, monkeypatch) -> list[str]:
    """State hashes of a pile of 12 cubes falling on the floor and coming to rest, with the
    solver order recomputed every step and / or the stage rows swept color by color."""
    if per_color_stage:

        def color_by_color(batch):
            if "stage" not in batch.cache.sweeps:
                ranges = [
                    (start, stop)
                    for (_, stop), start in zip(
                        batch.color_slices, batch.priority_starts, strict=True
                    )
                ]
                stage_priority._sweep_blocks(batch, "stage", ranges, stage_priority._lumped(batch))
            return batch.cache.sweeps["stage"]

        monkeypatch.setattr(stage_priority, "_stage_blocks", color_by_color)
    world, templates = make_world()
    handle = register_primitive(templates, "cubeSolid", (0.1, 0.1, 0.1))
    rng = np.random.default_rng(3)
    for k in range(12):
        box = add(world, templates, handle, [0.22 * (k % 3), 0.15 + 0.25 * (k // 3), 0.0])
        q = rng.normal(size=4)
        box.rotation = mn.Quaternion.from_xyzw(q / np.linalg.norm(q))
    hashes = []
    for _ in range(90):
        if memo_every_step:
            world.manifolds.solver_order = GraphMemo()
        world.step_physics(1 / 60)
        hashes.append(world.state_hash())
    monkeypatch.undo()
    return hashes


def test_kept_solver_order_and_single_stage_batch_change_no_bit(monkeypatch):
    calls = {"single": 0}
    original = stage_priority._stage_blocks

    def counting(batch):
        blocks = original(batch)
        calls["single"] += len(blocks) == 1 and not isinstance(blocks[0][0], slice)
        return blocks

    monkeypatch.setattr(stage_priority, "_stage_blocks", counting)
    lean = pile(memo_every_step=False, per_color_stage=False, monkeypatch=monkeypatch)
    assert calls["single"] > 0  # the single batch was taken
    plain = pile(memo_every_step=True, per_color_stage=True, monkeypatch=monkeypatch)
    assert lean == plain


def level_by_level(body_a, body_b, solvable) -> np.ndarray:
    """The definition: unmoved bodies are level 0; each round, every body not reached yet
    that shares a pair with a reached one gets the next level; then the lower body of each
    pair of moving bodies."""
    level = np.where(solvable, np.inf, 0.0)
    for next_level in range(1, len(body_a) + 1):
        reached_a, reached_b = level[body_a] < np.inf, level[body_b] < np.inf
        grow_b, grow_a = reached_a & ~reached_b, reached_b & ~reached_a
        if not (grow_a.any() or grow_b.any()):
            break
        level[body_b[grow_b]] = next_level
        level[body_a[grow_a]] = next_level
    both = solvable[body_a] & solvable[body_b]
    la, lb = level[body_a], level[body_b]
    return np.stack([both & (la < lb), both & (lb < la)], axis=1)


@pytest.mark.parametrize("seed", range(4))
def test_shock_levels_are_the_level_by_level_growth(seed):
    rng = np.random.default_rng(seed)
    lower_seen = 0
    for _ in range(200):
        n, m = int(rng.integers(2, 30)), int(rng.integers(1, 60))
        body_a, body_b = rng.integers(0, n, m), rng.integers(0, n, m)
        keep = body_a != body_b
        solvable = rng.random(n) < 0.8
        expected = level_by_level(body_a[keep], body_b[keep], solvable)
        np.testing.assert_array_equal(lower_bodies(body_a[keep], body_b[keep], solvable), expected)
        lower_seen += int(expected.sum())
    assert lower_seen > 100  # the graphs have levels to order
