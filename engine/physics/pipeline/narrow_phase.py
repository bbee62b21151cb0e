"""Batched narrow phase: every shape pair of a step to its rule, each rule's jobs at once.

The pair table (:mod:`pair_table`) names, for two shape kinds, the code that makes their
contacts. This module walks the step's body pairs once, turns each shape pair into a
:class:`~pair_rules.PairJob` and files it under its rule; then every rule's batched
function gets all of its jobs together (a box batch, a hull batch grouped by array sizes,
...), in table order, and the jobs a rule declines go to its fallback rule (later in the
table). The only per-pair work is this loop and, for the rules that use it, the fcl query.

The result is flat: ``pair_position (q,)`` (index into the pair list, ascending) and world
``point_a, point_b, normal (q, 3)``, normals from A to B, in the order the per-pair
reference path (:func:`reference_contacts.pair_contacts`) produces them: shape pairs in body
order; within a pair, the order of its rule.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..collision.pair_rules import ContactBatch, PairContext, PairJob
from .pair_table import PAIR_TABLE

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
    # the job list of every kind pair's rule, looked up once per shape pair
    jobs_of_kinds = {kinds: jobs[rule.name] for kinds, rule in PAIR_TABLE.by_kinds.items()}
    pair_of_seq: list[int] = []  # the body pair of every job, by sequence number
    entries = objects.shape_entries  # every body's (shape, fcl object, probe object)
    for position, (a, c) in enumerate(pairs):
        for shape_a, object_a, _ in entries[a]:
            for shape_c, object_c, probe_c in entries[c]:
                kinds = (shape_a.kind, shape_c.kind)
                if kinds not in jobs_of_kinds:
                    PAIR_TABLE.rule_for(*kinds)  # raises the KeyError naming them
                # PairJob(seq, shape_a, a, ...) without its Python-level __new__: a C-level
                # tuple of the same type and fields (measured: 3.6 -> 1.6 us per job)
                job = (len(pair_of_seq), shape_a, a, object_a, shape_c, c, object_c, probe_c, ())
                jobs_of_kinds[kinds].append(tuple.__new__(PairJob, job))
                pair_of_seq.append(position)
    context, out = PairContext(bodies, objects, store, rotation), ContactBatch()
    for rule in PAIR_TABLE.rules:  # in order: a fallback rule runs after the rules feeding it
        if jobs[rule.name]:
            declined = rule.batched(jobs[rule.name], context, out)
            if declined:
                jobs[rule.fallback or ""] += declined  # the table checked the fallback exists
    return out.sorted(np.array(pair_of_seq, dtype=np.int64))
