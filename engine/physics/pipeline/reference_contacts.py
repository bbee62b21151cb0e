"""Reference path of the collision stage: contacts and manifolds one body pair at a time.

This is the plain version of :mod:`narrow_phase` (batched contact generation) and, with
:mod:`reference_manifolds`, of :meth:`contacts.ManifoldStore.merge_fresh` (batched manifold
refresh, merge and reduction), the size of box2d-lite's ``Collide`` + ``Arbiter::Update``:
loops a student can step through in a debugger. :func:`pair_contacts` reads the same pair
table (:mod:`pair_table`) as the batched narrow phase and calls each rule's reference
function (:mod:`reference_pairs`, :mod:`reference_box_box`, :mod:`capsule_contacts`).
``SolverSettings.use_vectorized = False`` routes the world through it, and tests prove that
both paths produce the same contact points, manifolds and trajectories (to rounding).
"""

from __future__ import annotations

import numpy as np

from ..collision.contacts import SLOTS, ManifoldStore
from ..collision.manifold_rows import add_manifold_row
from ..collision.pair_rules import PairContext, PairJob, PairRule, contact_key
from ..core.bodies import STAGE_ID, Bodies
from ..core.reference_geometry import Contact
from ..reference.reference_manifolds import (
    ManifoldPoint,
    keyed_manifold,
    select_support,
    update_manifold,
)
from .pair_table import PAIR_TABLE


# ------------------------------------------------------------------------------------------
# contact generation (mirrors narrow_phase.narrow_phase)
# ------------------------------------------------------------------------------------------
def pair_contacts(
    bodies: Bodies, objects, store: ManifoldStore, a: int, c: int, rotation: np.ndarray
) -> list[Contact]:
    """Contacts of body pair ``(a, c)``, ``a < c``, in the narrow phase's order: shape pairs
    in body order, each by the reference function of its rule in :data:`PAIR_TABLE` (a
    declined job goes to the rule's fallback). ``rotation (n, 3, 3)``: all bodies;
    ``store``: the manifolds before this step's update, whose normals keep a stage contact
    on the side it began on. Each contact's ``feature`` is turned into its key inside the
    body pair (:func:`pair_rules.contact_key`: shape pair, rule, feature number)."""
    context = PairContext(bodies, objects, store, rotation)
    contacts: list[Contact] = []
    seq = 0  # the shape pair's number inside this body pair
    for shape_a, obj_a in zip(bodies.shapes[a], objects.shape_objects[a], strict=True):
        for shape_c, obj_c, probe_c in zip(
            bodies.shapes[c], objects.shape_objects[c], objects.probe_objects[c], strict=True
        ):
            job = PairJob(seq, shape_a, a, obj_a, shape_c, c, obj_c, probe_c)
            seq += 1
            rule: PairRule | None = PAIR_TABLE.rule_for(shape_a.kind, shape_c.kind)
            while rule is not None:
                found = rule.reference(job, context)
                if found is not None:
                    for contact in found:
                        contact.feature = contact_key(job.seq, rule.order, contact.feature)
                    contacts += found
                    break
                rule = PAIR_TABLE.fallback_of(rule)
    return contacts


# ------------------------------------------------------------------------------------------
# manifold update (mirrors ManifoldStore.merge_fresh)
# ------------------------------------------------------------------------------------------
def update_manifolds_reference(
    bodies: Bodies,
    objects,
    store: ManifoldStore,
    pairs: list[tuple[int, int]],
    rotation: np.ndarray,
    feature_manifolds: bool = True,
) -> None:
    """Reference for ``collision_stage.update_manifolds``: per pair, its contacts, then
    its manifold rebuilt from them by feature keys (:func:`keyed_manifold`, a keyable row
    with ``feature_manifolds``) or refreshed, merged and reduced (:func:`update_manifold`)."""
    for key in pairs:
        contacts = pair_contacts(bodies, objects, store, key[0], key[1], rotation)
        row = store.row(key)
        if row is None:
            if not contacts:
                continue
            row = add_manifold_row(bodies, store, key)
        frame_a = (rotation[key[0]], bodies.body_position[key[0]])
        frame_b = (rotation[key[1]], bodies.body_position[key[1]])
        cached = [
            ManifoldPoint(
                store.local_a[row, s].copy(),
                store.local_b[row, s].copy(),
                store.normal_local[row, s].copy(),
                store.impulse[row, s].copy(),
                int(store.point_key[row, s]),
            )
            for s in range(store.count[row])
        ]
        keyed = feature_manifolds and bool(store.keyable[row])
        capacity, feature = int(store.max_points[row]), float(store.feature[row])
        if keyed:  # the stage's rows hold their untaken cached points still touching
            hold = key[0] == STAGE_ID
            points = keyed_manifold(cached, contacts, frame_a, frame_b, capacity, feature, hold)
        else:
            points = update_manifold(cached, contacts, frame_a, frame_b, capacity, feature)
        store.count[row] = len(points)
        for array in (store.local_a, store.local_b, store.normal_local, store.impulse):
            array[row] = 0.0
        store.point_key[row] = 0
        for slot, point in enumerate(points):
            store.local_a[row, slot], store.local_b[row, slot] = point.local_a, point.local_b
            store.normal_local[row, slot], store.impulse[row, slot] = (
                point.normal_local,
                point.impulse,
            )
            store.point_key[row, slot] = point.key if keyed else 0


__all__ = [
    "SLOTS",
    "Contact",
    "ManifoldPoint",
    "pair_contacts",
    "select_support",
    "update_manifold",
    "update_manifolds_reference",
]
