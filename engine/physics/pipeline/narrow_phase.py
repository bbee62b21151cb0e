"""Batched narrow phase: every shape pair of a step to its rule, each rule's jobs at once.

The pair table (:mod:`pair_table`) names, for two shape kinds, the code that makes their
contacts. This module walks the step's body pairs once, turns each shape pair into a
:class:`~pair_rules.PairJob` and files it under its rule; then every rule's batched
function gets all of its jobs together (a box batch, a hull batch grouped by array sizes,
...), in table order, and the jobs a rule declines go to its fallback rule (later in the
table). The only per-pair work is this loop and, for the rules that use it, the fcl query.

The result is flat: ``pair_position (q,)`` (index into the pair list, ascending), world
``point_a, point_b, normal (q, 3)``, normals from A to B, and ``key (q,)``, each contact's
feature key inside its body pair (:data:`pair_rules.RULE_SHIFT`), in the order the per-pair
reference path (:func:`reference_contacts.pair_contacts`) produces them: shape pairs in body
order; within a pair, the order of its rule.
"""

from __future__ import annotations

from itertools import repeat
from operator import itemgetter
from typing import TYPE_CHECKING

import numpy as np

from ..collision.collision_objects import pairs_as_array
from ..collision.pair_rules import ContactBatch, PairContext, PairJob
from .pair_table import PAIR_TABLE

#: the first item of a tuple: a job's sequence number, a one-shape body's only entry
_first = itemgetter(0)

if TYPE_CHECKING:
    from ..collision.collision_objects import CollisionObjects
    from ..collision.contacts import ManifoldStore
    from ..core.bodies import Bodies


def narrow_phase(
    bodies: Bodies,
    objects: CollisionObjects,
    store: ManifoldStore,
    pairs: list,
    rotation: np.ndarray,
):
    """Contacts of body ``pairs`` ``[(a, c), ...]`` (see the module docstring).

    ``rotation (n, 3, 3)``: every body's world_from_body matrix; ``store``: the manifolds
    before this step's update (their normals keep a stage contact on its side). Must agree with
    :func:`reference_contacts.pair_contacts` called on each pair in turn (tested).
    """
    jobs: dict[str, list[PairJob]] = {rule.name: [] for rule in PAIR_TABLE.rules}
    pair_of_seq = np.zeros(0, dtype=np.int64)  # the body pair of every job, by sequence number
    first_seq = None  # the first job of every body pair (None: one job each)
    if pairs:
        pair_of_seq, first_seq = _file_jobs(objects, pairs, jobs)
    context, out = PairContext(bodies, objects, store, rotation), ContactBatch()
    for rule in PAIR_TABLE.rules:  # in order: a fallback rule runs after the rules feeding it
        if jobs[rule.name]:
            out.rule_order = rule.order  # the contacts' keys name their rule
            declined = rule.batched(jobs[rule.name], context, out)
            if declined:
                jobs[rule.fallback or ""] += declined  # the table checked the fallback exists
    return out.sorted(pair_of_seq, first_seq)


def _file_jobs(objects: CollisionObjects, pairs: list, jobs: dict[str, list[PairJob]]):
    """Turn every shape pair of the body ``pairs`` into a :class:`PairJob` filed under its
    rule's name in ``jobs``; returns ``pair_of_seq``, the body pair of each job, and
    ``first_seq``, the first job of each body pair (None when every pair is one job).

    Sequence numbers run over the pairs in order and, within a pair, over A's shapes then
    B's. The pairs are grouped by their bodies' kinds in NumPy (``CollisionObjects.kind_code``:
    a few groups, a box scene has one or two); a group of one-shape bodies becomes its jobs
    by C-level maps and zips (no Python bytecode per pair), the bodies of several shapes
    walk their shape pairs. Each
    rule's list ends in sequence order, as one walk over the pairs would leave it.
    """
    entries = objects.shape_entries  # every body's (shape, fcl object, probe object)
    kinds_of_code = objects.code_kinds
    width = len(kinds_of_code)
    pair_array = pairs_as_array(pairs)  # (p, 2)
    code_a, code_c = objects.kind_code[pair_array].T
    shape_counts = np.array([len(kinds) for kinds in kinds_of_code], dtype=np.int64)
    per_pair = shape_counts[code_a] * shape_counts[code_c]  # jobs of each pair
    first_seq = np.cumsum(per_pair) - per_pair
    pair_code = code_a * width + code_c
    new = tuple.__new__  # PairJob(...) without its Python-level __new__ (3.6 -> 1.6 us)
    filled = set()
    for key in np.unique(pair_code).tolist():
        kinds_a, kinds_c = kinds_of_code[key // width], kinds_of_code[key % width]
        members = np.flatnonzero(pair_code == key)
        if len(kinds_a) == 1 and len(kinds_c) == 1:
            rule = _rule_name(kinds_a[0], kinds_c[0])
            body_a, body_c = pair_array[members].T.tolist()
            # each body's one (shape, fcl object, probe) as columns, all by C-level maps
            shapes_a, objects_a, _ = zip(
                *map(_first, map(entries.__getitem__, body_a)), strict=True
            )
            shapes_c, objects_c, probes_c = zip(
                *map(_first, map(entries.__getitem__, body_c)), strict=True
            )
            columns = (first_seq[members].tolist(), shapes_a, body_a, objects_a, shapes_c, body_c)
            rows = zip(*columns, objects_c, probes_c, repeat(()), strict=False)
            jobs[rule] += map(new, repeat(PairJob), rows)
            filled.add(rule)
            continue
        for seq, position in zip(first_seq[members].tolist(), members.tolist(), strict=True):
            a, c = pairs[position]
            for shape_a, object_a, _ in entries[a]:
                for shape_c, object_c, probe_c in entries[c]:
                    rule = _rule_name(shape_a.kind, shape_c.kind)
                    job = (seq, shape_a, a, object_a, shape_c, c, object_c, probe_c, ())
                    jobs[rule].append(new(PairJob, job))
                    filled.add(rule)
                    seq += 1
    for rule in filled:
        jobs[rule].sort(key=_first)
    pair_of_seq = np.repeat(np.arange(len(pairs), dtype=np.int64), per_pair)
    return pair_of_seq, (None if len(pair_of_seq) == len(pairs) else first_seq)


def _rule_name(kind_a: str, kind_b: str) -> str:
    """The name of the pair table's rule for two shape kinds (KeyError naming them)."""
    return PAIR_TABLE.rule_for(kind_a, kind_b).name
