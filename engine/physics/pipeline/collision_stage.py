"""Collision stage of ``World.step``: which bodies touch, and where.

Inputs => outputs (``n`` bodies, ``p`` broad-phase pairs, ``q`` contact points)::

    Bodies (poses, AABBs, shapes), CollisionObjects (fcl objects), ManifoldStore
        => Bodies.body_aabb_min/max (n, 3) updated, fcl objects of the pairs asking fcl moved,
           ManifoldStore rows refreshed / created / deleted,
           returns the number of broad-phase pairs p (Habitat's "active overlapping pairs")

Sub-stages, in order:

1. broad phase (:func:`broad_phase`): world AABBs of all bodies, inflated by
   ``AABB_MARGIN`` (the stage also by ``STAGE_SPECULATIVE_DISTANCE``), then the overlapping
   pairs ``(p, 2)`` with at least one moving body and at least one dynamic body;
2. box pre-test (:func:`separated_box_pairs`): pairs with no manifold whose body-frame boxes
   (oriented, exact) are disjoint skip the narrow phase; pairs of two one-box bodies skip
   the test (their analytic contacts run the same separating-axis test anyway);
3. contact cache (:func:`changed_pairs`, ``settings.contact_cache``): a pair with a
   manifold whose relative pose moved less than ``CONTACT_CACHE_DISTANCE`` since its last
   narrow-phase query, and whose points overlap by at most ``SLEEP_MAX_PENETRATION``,
   keeps its manifold unchanged (its points stay attached to the bodies,
   the solver measures their depths from the current poses): a resting pile costs no
   narrow phase. The same pairs are skipped on both paths;
4. narrow phase and manifold update: contact points ``(q, 3)`` of the touching pairs, with
   their feature keys, become each pair's manifold (``settings.feature_manifolds``,
   :meth:`ManifoldStore.replace_fresh`) or are merged into it (capsule pairs, or
   the switch off: :meth:`ManifoldStore.merge_fresh`). ``settings.use_vectorized``
   chooses the batched path (:func:`narrow_phase.narrow_phase` + the store) or the per-pair
   reference path (:mod:`reference_contacts`); tests prove both give the same manifolds;
5. stale manifolds (:func:`drop_stale_manifolds`): pairs that left the broad phase while
   one of their bodies moved lose their manifold; a sleeping pair keeps it for waking.
"""

from __future__ import annotations

from itertools import compress, filterfalse

import numpy as np

from ..collision.collide import boxes_separated, overlapping_pairs, world_aabbs
from ..collision.collision_groups import filter_pairs
from ..collision.collision_objects import CollisionObjects, pairs_as_array
from ..collision.contacts import FreshPoints, ManifoldStore
from ..collision.manifold_rows import add_manifold_row
from ..core.bodies import DYNAMIC, STAGE_ID, Bodies
from ..core.profiling import StageTimer
from ..core.quaternions import live_rotations
from ..core.settings import (
    AABB_MARGIN,
    CONTACT_CACHE_DISTANCE,
    MIN_PAIRS_FOR_BOX_TEST,
    SLEEP_MAX_PENETRATION,
    STAGE_SPECULATIVE_DISTANCE,
    SolverSettings,
)
from ..core.vectors import dot
from ..solver.sleeping import moving_kinematic_mask
from .narrow_phase import narrow_phase
from .pair_table import PAIR_TABLE
from .reference_contacts import update_manifolds_reference


def collision_stage(
    bodies: Bodies,
    objects: CollisionObjects,
    store: ManifoldStore,
    settings: SolverSettings,
    timer: StageTimer | None = None,
) -> int:
    """Run the four sub-stages of the module docstring; returns the broad-phase pair count."""
    timer = timer or StageTimer()
    rotation = live_rotations(bodies)  # (n, 3, 3) world_from_body (identity: freed slots)
    # ---- 1. broad phase: AABB pairs with a moving, dynamic member -------------------------
    pairs, active = timer.run("broad phase", broad_phase, bodies, rotation)
    # ---- 2. box pre-test: skip pairs without a manifold whose oriented boxes are apart ----
    touching = timer.run(
        "broad phase",
        touching_candidates,
        bodies,
        store,
        pairs,
        rotation,
        objects.single_box,
    )
    # ---- 3. contact cache: pairs that barely moved relative to each other keep their
    #         manifold as it is (no narrow phase, no manifold update) -----------------------
    if settings.contact_cache:
        touching = timer.run("manifolds", changed_pairs, bodies, store, touching, rotation)
    # ---- 4. narrow phase + manifold update (batched or reference) -------------------------
    #         (fcl objects move only for the pairs that ask fcl: box pairs are analytic, and
    #         the few box pairs left to fcl move their own objects in the narrow phase)
    timer.run("fcl update", move_fcl_users, bodies, objects, touching, rotation)
    keyed = settings.feature_manifolds
    if settings.use_vectorized:
        update_manifolds(bodies, objects, store, touching, rotation, timer, keyed)
    else:
        timer.run(
            "narrow phase",
            update_manifolds_reference,
            bodies,
            objects,
            store,
            touching,
            rotation,
            keyed,
        )
    if touching:
        queried = np.array(store.rows_of(touching, -1), dtype=np.int64)
        store.remember_queries(queried[queried >= 0], rotation, bodies.body_position)
    # ---- 5. stale manifolds: pairs that separated lose their points -----------------------
    timer.run("manifolds", drop_stale_manifolds, bodies, store, pairs, active)
    return len(pairs)


def move_fcl_users(
    bodies: Bodies,
    objects: CollisionObjects,
    pairs: list[tuple[int, int]],
    rotation: np.ndarray,
) -> None:
    """Move the fcl objects of the bodies in ``pairs`` that the narrow phase will ask fcl
    about: both bodies of every pair whose shape kinds need a rule that uses fcl
    (:meth:`pair_rules.PairTable.needs_fcl`; two boxes, say, have analytic contacts); the
    probes (grown shapes) of the bodies paired with the stage by such a rule (hulls find
    their stage triangles in the stage grid). The stage never moves.

    A job that an analytic rule declines to an fcl rule after all (coincident or deep box
    pairs) moves its two bodies itself (:meth:`CollisionObjects.move_shapes`)."""
    if not pairs:
        return
    # each distinct pair of body kinds asked once (a few), not each body pair (hundreds):
    # the pairs' kind codes as one integer each, c_a K + c_c, looked up in NumPy
    codes = objects.kind_code[pairs_as_array(pairs)]  # (p, 2)
    width = len(objects.code_kinds)
    pair_code = codes[:, 0] * width + codes[:, 1]
    distinct = np.unique(pair_code).tolist()
    kinds = objects.code_kinds
    asking = [
        key for key in distinct if PAIR_TABLE.needs_fcl(kinds[key // width], kinds[key % width])
    ]
    if not asking:  # two boxes, say; hulls on the stage use the stage grid
        return
    users: set[int] = set()
    near_stage: set[int] = set()
    for k in np.flatnonzero(np.isin(pair_code, asking)).tolist():
        a, c = pairs[k]
        if a == STAGE_ID:
            near_stage.add(c)
        else:
            users.update((a, c))
    if users or near_stage:
        involved = np.array(sorted(users | near_stage), dtype=np.int64)
        probes = np.array([index in near_stage for index in involved.tolist()], dtype=bool)
        objects.move(bodies, involved, rotation[involved], probes)


def broad_phase(
    bodies: Bodies, rotation: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """World AABBs (written to ``body_aabb_min/max``) and the overlapping pairs
    (``rotation (n, 3, 3)``: every body's matrix, if known).

    Returns ``pairs (p, 2)`` sorted, ``a < c``, each with a dynamic body, and ``active
    (n,)`` bool: the bodies that can move this step (awake dynamic, moving kinematic).
    """
    b, n = bodies, bodies.count
    # every live object has shapes; the stage without shapes is not collidable
    candidates = np.nonzero(b.body_alive[:n] & b.body_collidable[:n])[0]
    update_world_aabbs(bodies, rotation)
    dynamic = b.body_motion_type[:n] == DYNAMIC
    active = (dynamic & b.body_awake[:n]) | moving_kinematic_mask(b, n)
    pairs = overlapping_pairs(b.body_aabb_min[:n], b.body_aabb_max[:n], candidates, active)
    pairs = pairs[dynamic[pairs[:, 0]] | dynamic[pairs[:, 1]]]
    pairs = filter_pairs(b, pairs)  # collision groups and masks (collision_groups.py)
    return pairs, active


def update_world_aabbs(bodies: Bodies, rotation: np.ndarray | None = None) -> None:
    """Write every live body's world AABB (all its shapes, plus ``AABB_MARGIN``; the
    stage's also covers its speculative contact distance) to ``body_aabb_min/max``."""
    b, n = bodies, bodies.count
    live = np.flatnonzero(b.body_alive[:n])  # freed slots cost nothing
    lo, hi = world_aabbs(
        b.body_shape_center[live],
        b.body_shape_half[live],
        b.body_position[live],
        b.body_rotation[live],
        None if rotation is None else rotation[live],
    )
    b.body_aabb_min[live] = lo - AABB_MARGIN
    b.body_aabb_max[live] = hi + AABB_MARGIN
    b.body_aabb_min[STAGE_ID] -= STAGE_SPECULATIVE_DISTANCE
    b.body_aabb_max[STAGE_ID] += STAGE_SPECULATIVE_DISTANCE


def touching_candidates(
    bodies: Bodies,
    store: ManifoldStore,
    pairs: np.ndarray,
    rotation: np.ndarray,
    single_box: np.ndarray | None = None,
) -> list[tuple[int, int]]:
    """The pairs ``[(a, c), ...]`` for the narrow phase: ``pairs`` minus those without a
    manifold whose body-frame boxes are disjoint (:func:`separated_box_pairs`).

    The box test costs a fixed ~40 NumPy calls, so it runs only when at least
    ``MIN_PAIRS_FOR_BOX_TEST`` pairs could be skipped. ``single_box (n,)``: the bodies of
    one box shape (``CollisionObjects.single_box``); a pair of two is not tested: its
    analytic contacts (:mod:`box_box`) run the exact separating-axis test anyway, and a
    pair this test finds apart (boxes grown by ``AABB_MARGIN``: more than 10 mm apart on
    some axis) has no contact there either (``SPECULATIVE_DISTANCE``, 4 mm), so the
    manifolds are the same, without the test's calls.
    """
    first = pairs[:, 0].tolist()
    pair_list = list(zip(first, pairs[:, 1].tolist(), strict=True))  # (a, c), built in C
    known = np.array(store.rows_of(pair_list, -1), dtype=np.int64)  # -1: no manifold
    testable = (known < 0) & (pairs[:, 0] != STAGE_ID)
    if single_box is not None:
        testable &= ~(single_box[pairs[:, 0]] & single_box[pairs[:, 1]])
    check = np.flatnonzero(testable)
    if len(check) < MIN_PAIRS_FOR_BOX_TEST:
        return pair_list
    keep = np.ones(len(pair_list), dtype=bool)
    keep[check[separated_box_pairs(bodies, pairs[check], rotation)]] = False
    return list(compress(pair_list, keep.tolist()))  # in order, without the apart pairs


def changed_pairs(
    bodies: Bodies, store: ManifoldStore, pairs: list[tuple[int, int]], rotation: np.ndarray
) -> list[tuple[int, int]]:
    """``pairs`` minus those with a manifold whose relative pose moved less than
    ``CONTACT_CACHE_DISTANCE`` since their last narrow-phase query and whose points overlap
    by at most ``SLEEP_MAX_PENETRATION`` (their manifold stays as it is)."""
    rows = np.array(store.rows_of(pairs, -1), dtype=np.int64)
    known = np.flatnonzero(rows >= 0)
    if len(known) == 0:
        return pairs
    b = bodies
    body_b = store.bodies[rows[known], 1]
    # radius of B's body-frame box around its center of mass: |c| + |h|
    radius_b = np.linalg.norm(b.body_shape_center[body_b], axis=1) + np.linalg.norm(
        b.body_shape_half[body_b], axis=1
    )
    unchanged = store.unchanged_rows(
        rows[known], rotation, b.body_position, radius_b, CONTACT_CACHE_DISTANCE
    )
    known = known[unchanged]  # a moving scene stops here: every pair is asked again
    if len(known) == 0:
        return pairs
    # only resting contacts are kept: a pair overlapping deeper than SLEEP_MAX_PENETRATION
    # is still being pushed apart, and its contacts must follow that (asked every step)
    point_a, point_b, normal = store.world_points(rows[known], rotation, b.body_position)
    depth = dot(point_a - point_b, normal)  # (p_a - p_b) . n per slot
    used = np.arange(depth.shape[1]) < store.count[rows[known], None]
    shallow = np.where(used, depth, -np.inf).max(axis=1) <= SLEEP_MAX_PENETRATION
    keep = np.ones(len(pairs), dtype=bool)
    keep[known[shallow]] = False
    return list(compress(pairs, keep.tolist()))


def separated_box_pairs(bodies: Bodies, pairs: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """(p,) bool: body pairs (stage excluded) whose body-frame AABBs cannot touch.

    Every body's shapes lie inside its body-frame AABB (center ``c``, half extents ``h``),
    an oriented box in the world. Rotated boxes' world AABBs overlap long before the
    boxes touch, so this exact oriented-box test skips many narrow-phase calls that could
    only answer "no contact".
    """
    b = bodies
    a, c = pairs[:, 0], pairs[:, 1]
    # box center in the world: x + R c
    center_a = b.body_position[a] + (rotation[a] @ b.body_shape_center[a][:, :, None])[..., 0]
    center_c = b.body_position[c] + (rotation[c] @ b.body_shape_center[c][:, :, None])[..., 0]
    margin = AABB_MARGIN
    apart = boxes_separated(
        center_a,
        rotation[a],
        b.body_shape_half[a] + margin,
        center_c,
        rotation[c],
        b.body_shape_half[c] + margin,
    )
    return apart & (a != STAGE_ID)


def update_manifolds(
    bodies: Bodies,
    objects: CollisionObjects,
    store: ManifoldStore,
    pairs: list[tuple[int, int]],
    rotation: np.ndarray,
    timer: StageTimer | None = None,
    feature_manifolds: bool = True,
) -> None:
    """Batched: narrow phase for ``pairs``, then their manifolds rebuilt from the fresh
    points by feature keys (``feature_manifolds`` and a keyable row) or refreshed, merged
    and reduced.

    Must agree with :func:`reference_contacts.update_manifolds_reference` (tested). A pair
    gets a manifold row when it first has contact points; pairs with a sphere keep a single
    (rolling) point.
    """
    if not pairs:  # a resting scene: the contact cache kept every manifold
        return
    timer = timer or StageTimer()
    pair_position, point_a, point_b, normal, key = timer.run(
        "narrow phase", narrow_phase, bodies, objects, store, pairs, rotation
    )
    timer.run(
        "manifolds",
        _merge_into_store,
        bodies,
        store,
        pairs,
        rotation,
        pair_position,
        point_a,
        point_b,
        normal,
        key,
        feature_manifolds,
    )


def _merge_into_store(
    bodies: Bodies,
    store: ManifoldStore,
    pairs: list[tuple[int, int]],
    rotation: np.ndarray,
    pair_position: np.ndarray,
    point_a: np.ndarray,
    point_b: np.ndarray,
    normal: np.ndarray,
    key: np.ndarray,
    feature_manifolds: bool,
) -> None:
    """Rows for the pairs that have points, then one batched :meth:`ManifoldStore.replace_fresh`
    for the keyed rows (with ``feature_manifolds``) and one :meth:`ManifoldStore.merge_fresh`
    for the others."""
    has_points = np.bincount(pair_position, minlength=len(pairs)) > 0
    row_of_pair = np.array(store.rows_of(pairs, -1), dtype=np.int64)  # -1: no manifold yet
    for k in ((row_of_pair < 0) & has_points).nonzero()[0].tolist():  # first touch
        row_of_pair[k] = add_manifold_row(bodies, store, pairs[k])
    # the manifolds to update: every pair with points, and the others' non-empty manifolds
    # (an empty manifold without fresh points stays empty: skipping it changes nothing)
    updated = (row_of_pair >= 0) & (has_points | (store.count[row_of_pair] > 0))  # -1: masked
    row_position = np.cumsum(updated) - 1  # pair position -> row position (updated pairs)
    fresh = FreshPoints(
        int(updated.sum()), row_position[pair_position], point_a, point_b, normal, key
    )
    rows, position = row_of_pair[updated], bodies.body_position
    keyed = store.keyable[rows] if feature_manifolds else np.zeros(len(rows), dtype=bool)
    if keyed.all():  # a scene of boxes and hulls: no merge
        store.replace_fresh(rows, rotation, position, fresh)
    elif not keyed.any():
        store.merge_fresh(rows, rotation, position, fresh)
    else:
        store.replace_fresh(rows[keyed], rotation, position, fresh.rows(keyed))
        store.merge_fresh(rows[~keyed], rotation, position, fresh.rows(~keyed))


def drop_stale_manifolds(
    bodies: Bodies, store: ManifoldStore, pairs: np.ndarray, active: np.ndarray
) -> None:
    """Delete the manifolds of pairs that left the broad phase while one of them moved
    (or died); a sleeping pair keeps its manifold for when it wakes."""
    # the manifolds whose pair is not among the broad phase's (a set of (a, c) tuples,
    # built and searched in C: a hash lookup per manifold, no NumPy call per step)
    listed = set(zip(pairs[:, 0].tolist(), pairs[:, 1].tolist(), strict=True))
    unlisted = list(filterfalse(listed.__contains__, store))  # in insertion order
    if not unlisted:
        return
    ends = np.array(unlisted, dtype=np.int64)  # (k, 2)
    moved = active[ends].any(axis=1) | ~bodies.body_alive[ends].all(axis=1)
    for k in np.flatnonzero(moved).tolist():
        del store[unlisted[k]]
