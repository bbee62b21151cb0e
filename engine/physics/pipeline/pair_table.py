"""The contact pair table: which code makes the contacts of two shape kinds.

One row per rule (:class:`~pair_rules.PairRule`): the shape kinds it handles, its batched
function (all of a step's jobs at once), its reference twin (one job, plain loops), whether
it asks python-fcl, its order (the first matching rule wins) and the rule taking the jobs
it declines. :func:`narrow_phase.narrow_phase` and :func:`reference_contacts.pair_contacts`
both read :data:`PAIR_TABLE`, so the two paths cannot dispatch differently. Adding a
contact pair is one row here and one pair of functions (see ``docs/contacts.md``).

A is the shape of the lower body index; the stage (body 0, the only ``mesh`` shape) is
therefore always A. Rules marked ``either_order`` also match with A and B swapped.
"""

from __future__ import annotations

from ..collision.batched_pairs import (
    box_pair_batch,
    fcl_pair_batch,
    hull_pair_batch,
    sphere_pair_batch,
    stage_round_batch,
)
from ..collision.batched_stage import stage_hull_batch
from ..collision.capsule_contacts import capsule_pair, capsule_pair_batch
from ..collision.pair_rules import PairRule, PairTable
from ..core.shapes import POLYHEDRA, ROUND, ShapeKind
from ..reference.reference_pairs import (
    box_pair,
    fcl_pair,
    hull_pair,
    sphere_pair,
    stage_hull_pair,
    stage_round_pair,
)

MESH: frozenset[ShapeKind] = frozenset({ShapeKind.MESH})
BOX: frozenset[ShapeKind] = frozenset({ShapeKind.BOX})
SPHERE: frozenset[ShapeKind] = frozenset({ShapeKind.SPHERE})
CAPSULE: frozenset[ShapeKind] = frozenset({ShapeKind.CAPSULE})

PAIR_TABLE = PairTable(
    [
        PairRule(10, "stage-hull", MESH, POLYHEDRA, stage_hull_batch, stage_hull_pair, False),
        PairRule(20, "stage-round", MESH, ROUND, stage_round_batch, stage_round_pair, True),
        PairRule(30, "box-box", BOX, BOX, box_pair_batch, box_pair, False, fallback="hull-hull"),
        PairRule(40, "hull-hull", POLYHEDRA, POLYHEDRA, hull_pair_batch, hull_pair, True),
        PairRule(50, "sphere-sphere", SPHERE, SPHERE, sphere_pair_batch, sphere_pair, True),
        PairRule(60, "capsule-capsule", CAPSULE, CAPSULE, capsule_pair_batch, capsule_pair, False),
        PairRule(
            70,
            "sphere-capsule",
            SPHERE,
            CAPSULE,
            capsule_pair_batch,
            capsule_pair,
            False,
            either_order=True,
        ),
        PairRule(
            90,
            "fcl",
            POLYHEDRA | ROUND,
            POLYHEDRA | ROUND,
            fcl_pair_batch,
            fcl_pair,
            True,
            either_order=True,
        ),
    ]
)
