"""Reference path of the manifold update: one manifold at a time, in plain loops.

The plain version of :meth:`contacts.ManifoldStore.merge_fresh` (the batched refresh, merge and
reduction of :mod:`manifold_merge`), box2d-lite's ``Arbiter::Update`` size: a persistent
:class:`ManifoldPoint` list per body pair, refreshed (:func:`still_touching`), merged with
this step's contacts (:func:`update_manifold`) and cut to the supporting polygon
(:func:`select_support`). ``SolverSettings.use_vectorized = False`` routes the world
through it (via :func:`reference_contacts.update_manifolds_reference`); tests prove both
paths keep the same manifolds. :func:`keyed_manifold` is the plain version of the
feature-keyed rows (:mod:`keyed_manifolds`): the fresh points are the manifold, their
impulses from the cached point with the same key.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..collision.contacts import tie_key
from ..core import settings
from ..core.reference_geometry import Contact, cross3, dot, rotate, unrotate


@dataclass
class ManifoldPoint:
    """A persistent point: anchors in the body frames, normal in A's frame, the solver's
    accumulated impulse ``[normal, tangent1, tangent2]`` in N s and its feature key (0:
    none, a merged point)."""

    local_a: np.ndarray
    local_b: np.ndarray
    normal_local: np.ndarray
    impulse: np.ndarray = field(default_factory=lambda: np.zeros(3))
    key: int = 0

    def world(self, frame_a, frame_b) -> Contact:
        (ra, xa), (rb, xb) = frame_a, frame_b
        return Contact(
            rotate(ra, self.local_a) + xa,
            rotate(rb, self.local_b) + xb,
            rotate(ra, self.normal_local),
        )


def update_manifold(
    cached: list[ManifoldPoint],
    fresh: list[Contact],
    frame_a,
    frame_b,
    max_points: int,
    feature: float = settings.CONTACT_MATCH_DISTANCE,
) -> list[ManifoldPoint]:
    """One manifold's step (box2d-lite's ``Arbiter::Update``, with Bullet's persistence).

    ``feature`` (m) is the pair's feature length (``contacts.feature_length``): the match,
    drift and support-band distances are capped at it, so a small body keeps distinct points.

    1. keep the cached points still in contact (:func:`still_touching`);
    2. too many fresh points: keep the supporting polygon, preferring points that match
       kept ones; drop fresh points within ``feature`` of a deeper one;
    3. fresh points inherit the impulse of the nearest unused cached point closer than
       ``feature`` in B's frame (warm starting), kept or not: the anchor in B's frame is
       B's feature (a box corner), which keeps its load while it slides; a rolling point
       always inherits;
    4. three or more fresh points replace the cache, fewer join its unmatched points;
    5. more than ``max_points``: the supporting polygon's points.
    """
    touching = [still_touching(p, frame_a, frame_b, feature) for p in cached]
    kept = [p for p, is_touching in zip(cached, touching, strict=True) if is_touching]
    (ra, xa), (rb, xb) = frame_a, frame_b
    band = min(settings.SUPPORT_DEPTH_BAND, feature)
    if len(fresh) > max_points:
        fresh = _support_of_fresh(fresh, kept, rb, xb, max_points, feature, band)
    fresh = _distinct(fresh, feature)
    points = [
        ManifoldPoint(
            unrotate(ra, c.point_a - xa), unrotate(rb, c.point_b - xb), unrotate(ra, c.normal)
        )
        for c in fresh
    ]
    # every cached point may pass its impulse on, also one that slid out of contact: the
    # anchor in B's frame names B's feature (a box corner sliding on the floor keeps it)
    used = _inherit_impulses(points, cached, max_points, feature)
    if len(points) >= 3:
        merged = points
    else:
        unused = zip(cached, touching, used, strict=True)
        merged = [p for p, is_touching, is_used in unused if is_touching and not is_used] + points
    merged = _reduce(merged, frame_a, frame_b, max_points, feature)
    return merged


def keyed_manifold(
    cached: list[ManifoldPoint],
    fresh: list[Contact],
    frame_a,
    frame_b,
    max_points: int,
    feature: float = settings.CONTACT_MATCH_DISTANCE,
    hold: bool = False,
) -> list[ManifoldPoint]:
    """One fresh manifold's step (Box2D v3's ``b2UpdateContact``, Jolt's warm start): the
    fresh contacts (``Contact.feature`` holding each one's key) become the manifold.

    Mirrors :func:`keyed_manifolds.keyed_points` for one row:

    1. more than ``max_points``: the supporting polygon (:func:`select_with_corners`),
       points with a cached point's key winning near-ties;
    2. each fresh point, in order, takes the impulses of the nearest unused cached point
       closer than ``feature`` in B's frame; a rolling point (``max_points == 1``) the
       cached point's (:func:`_inherit_impulses`, the merge's rule);
    3. ``hold`` (a stage row) and fewer than three fresh points: the cached points no fresh
       point took that are still touching join them, first (:func:`still_touching`), cut to
       ``max_points`` as the merge does (:func:`_reduce`).
    """
    cached_keys = {point.key for point in cached}
    matched = [contact.feature in cached_keys for contact in fresh]
    chosen = list(range(len(fresh)))
    if len(fresh) > max_points:
        band = min(settings.SUPPORT_DEPTH_BAND, feature)
        keep = _select_fresh(fresh, max_points, matched, band)
        chosen = [i for i in chosen if keep[i]]
    (ra, xa), (rb, xb) = frame_a, frame_b
    points = []
    for i in chosen:
        c = fresh[i]
        local = (unrotate(ra, c.point_a - xa), unrotate(rb, c.point_b - xb), unrotate(ra, c.normal))
        points.append(ManifoldPoint(*local, np.zeros(3), c.feature))
    used = _inherit_impulses(points, cached, max_points, feature)
    if not hold or len(points) >= 3:
        return points
    held = [
        p
        for p, is_used in zip(cached, used, strict=True)
        if not is_used and still_touching(p, frame_a, frame_b, feature)
    ]
    return _reduce(held + points, frame_a, frame_b, max_points, feature)


def _reduce(merged: list[ManifoldPoint], frame_a, frame_b, max_points: int, feature: float):
    """``merged`` cut to ``max_points``: the corner slot choice around the first point's
    normal (:func:`select_with_corners`)."""
    if len(merged) <= max_points:
        return merged
    world = [p.world(frame_a, frame_b) for p in merged]
    chosen = select_with_corners(
        [c.point_b for c in world],
        [c.depth for c in world],
        [c.normal for c in world],
        world[0].normal,
        max_points,
        band=min(settings.SUPPORT_DEPTH_BAND, feature),
    )
    return [p for p, keep in zip(merged, chosen, strict=True) if keep]


def still_touching(
    point: ManifoldPoint, frame_a, frame_b, feature: float = settings.CONTACT_DRIFT_DISTANCE
) -> bool:
    """A cached point persists while its bodies separate less than
    ``CONTACT_BREAKING_DISTANCE`` along the normal and its anchors drift apart less than
    ``CONTACT_DRIFT_DISTANCE`` (capped at the feature length) tangentially."""
    contact = point.world(frame_a, frame_b)
    gap = contact.point_a - contact.point_b
    depth = dot(gap, contact.normal)
    drift_sq = dot(gap, gap) - depth**2  # |tangential part of the gap|^2
    return bool(
        depth > -settings.CONTACT_BREAKING_DISTANCE
        and drift_sq < min(settings.CONTACT_DRIFT_DISTANCE, feature) ** 2
    )


def _support_of_fresh(
    fresh: list[Contact],
    cached: list[ManifoldPoint],
    rb,
    xb,
    max_points: int,
    feature: float,
    band: float,
) -> list[Contact]:
    """The fresh points spanning the supporting polygon; near-ties go to points matching a
    cached one within ``feature`` (hysteresis: a face on many coplanar vertices keeps the
    same four)."""
    limit = feature**2
    preferred = []
    for contact in fresh:
        local_b = unrotate(rb, contact.point_b - xb)
        preferred.append(any(dot(local_b - p.local_b, local_b - p.local_b) < limit for p in cached))
    chosen = _select_fresh(fresh, max_points, preferred, band)
    return [c for c, keep in zip(fresh, chosen, strict=True) if keep]


def _select_fresh(fresh: list[Contact], max_points: int, preferred: list[bool], band: float):
    """Which of the fresh points a manifold keeps (:func:`select_with_corners` around the
    deepest point's normal, the first of equal depths); near-ties go to ``preferred``."""
    depths = [c.depth for c in fresh]
    deepest = int(np.argmax(tie_key(np.array(depths))))
    return select_with_corners(
        [c.point_b for c in fresh],
        depths,
        [c.normal for c in fresh],
        fresh[deepest].normal,
        max_points,
        preferred,
        band,
    )


def _distinct(fresh: list[Contact], radius: float) -> list[Contact]:
    """Deepest first, drop any point within ``radius`` of a kept one (B's world anchors)
    pushing the same way (``n . n_kept >= STAGE_CORNER_COSINE``: a vertex in a corner keeps
    its wall and its floor contact)."""
    # stable sort, deepest first: equal depths (to TIE_QUANTUM) keep their order
    by_depth = sorted(fresh, key=lambda c: -tie_key(c.depth))
    kept: list[Contact] = []
    for contact in by_depth:
        if all(
            dot(contact.point_b - k.point_b, contact.point_b - k.point_b) >= radius * radius
            or dot(contact.normal, k.normal) < settings.STAGE_CORNER_COSINE
            for k in kept
        ):
            kept.append(contact)
    return kept


def _inherit_impulses(
    points: list[ManifoldPoint], cached: list[ManifoldPoint], max_points: int, feature: float
) -> list[bool]:
    """Greedy one-to-one matching in B's frame; returns which cached points were used."""
    used = [False] * len(cached)
    if max_points == 1:  # a rolling point keeps the impulse of the cached one
        for point in points:
            point.impulse = cached[0].impulse.copy() if cached else np.zeros(3)
        return [True] * len(cached)
    limit = feature**2
    for point in points:
        best, best_sq = None, np.inf
        for i, old in enumerate(cached):
            gap = point.local_b - old.local_b
            if not used[i] and dot(gap, gap) < best_sq:
                best, best_sq = i, dot(gap, gap)
        if best is not None and best_sq < limit:
            point.impulse = cached[best].impulse.copy()
            used[best] = True
    return used


def select_with_corners(
    points: list,
    depths: list,
    normals: list,
    normal: np.ndarray,
    count: int,
    preferred: list | None = None,
    band: float = settings.SUPPORT_DEPTH_BAND,
) -> list[bool]:
    """:func:`select_support` of the floor's points after keeping the deepest point of each
    other direction (a corner of the stage: a deep wall contact must take neither the
    floor's slots nor all but one); mirrors ``manifold_merge.select_with_corners`` for one
    row.

    A point (speculative ones too) is in another direction when ``n . normal <
    STAGE_CORNER_COSINE``; only a row keeping at least 4 points with such a point is a
    corner. There ``normal`` becomes the deepest touching floor-like point's
    (``n_y >= FLOOR_NORMAL_Y``), if any; the deepest point turned from it is kept, then the
    deepest turned that far from both; the points along ``normal`` span the polygon, and
    slots still free take the deepest of the rest."""
    corner = _corner_points(depths, normals, normal, count)
    if corner is None:
        return select_support(points, depths, normal, count, preferred, band)
    reserved, normal = corner
    cosine = settings.STAGE_CORNER_COSINE
    own = [i for i in range(len(points)) if i not in reserved and dot(normals[i], normal) >= cosine]
    chosen = [i in reserved for i in range(len(points))]
    if own:
        chosen_own = select_support(
            [points[i] for i in own],
            [depths[i] for i in own],
            normal,
            count - len(reserved),
            None if preferred is None else [preferred[i] for i in own],
            band,
        )
        for i, keep in zip(own, chosen_own, strict=True):
            chosen[i] = keep
    # slots still free (the floor holds fewer points than its share): the deepest others
    rest = sorted(
        (i for i in range(len(points)) if not chosen[i]), key=lambda i: -tie_key(depths[i])
    )
    for i in rest[: max(count - sum(chosen), 0)]:
        chosen[i] = True
    return chosen


def _corner_points(
    depths: list, normals: list, normal: np.ndarray, count: int
) -> tuple[list[int], np.ndarray] | None:
    """The indices of the deepest point of each extra direction (at most two) and the
    row's reference normal (the deepest touching floor-like point's, if any), or None when
    the row is no corner."""
    if count < 4:
        return None
    cosine = settings.STAGE_CORNER_COSINE
    every = range(len(depths))
    if not any(dot(normals[i], normal) < cosine for i in every):
        return None
    floor = [i for i in every if depths[i] >= 0.0 and normals[i][1] >= settings.FLOOR_NORMAL_Y]
    if floor:
        normal = normals[max(floor, key=lambda i: (tie_key(depths[i]), -i))]  # first deepest
    turned = [i for i in every if dot(normals[i], normal) < cosine]
    if not turned:
        return [], normal
    second = max(turned, key=lambda i: (tie_key(depths[i]), -i))  # first of the deepest
    third = [i for i in turned if dot(normals[i], normals[second]) < cosine]
    if not third:
        return [second], normal
    return [second, max(third, key=lambda i: (tie_key(depths[i]), -i))], normal


def select_support(
    points: list,
    depths: list,
    normal: np.ndarray,
    count: int,
    preferred: list | None = None,
    band: float = settings.SUPPORT_DEPTH_BAND,
) -> list[bool]:
    """Up to ``count`` of the points spanning the largest supporting area (mirrors
    ``contacts.select_support`` for one row).

    Supporting points lie within ``band`` (m) of the deepest. Among them: the
    deepest (``p0``), the farthest from it (``p1``), the one spanning the largest triangle
    with those two, then the largest on the other side of edge p0-p1. Preferred points win
    near-ties (1 mm of depth, 10 % of distance or area). Slots left over take the remaining
    points, deepest first.
    """
    k = len(points)
    lowest = max(depths) - band
    supporting = [d >= lowest for d in depths]
    bonus = [float(p) for p in preferred] if preferred is not None else [0.0] * k
    scale = [1.0 + settings.PREFERRED_SIZE_BONUS * b for b in bonus]
    chosen = [False] * k

    def best_of(values):  # the first supporting slot holding the largest value
        masked = [tie_key(v) if s else -np.inf for v, s in zip(values, supporting, strict=True)]
        return int(np.argmax(masked))

    first = best_of(
        [d + settings.PREFERRED_DEPTH_BONUS * b for d, b in zip(depths, bonus, strict=True)]
    )
    chosen[first] = True
    p0 = points[first]
    second = best_of([dot(p - p0, p - p0) * s for p, s in zip(points, scale, strict=True)])
    chosen[second] |= count >= 2
    edge = points[second] - p0
    # signed area of triangle (p0, p1, p) about the normal: ((p1 - p0) x (p - p0)) . n / 2
    area = [dot(cross3(edge, p - p0), normal) * s for p, s in zip(points, scale, strict=True)]
    third = best_of([abs(a) for a in area])
    chosen[third] |= count >= 3
    side = -np.sign(area[third])
    opposite = [
        side * a if s and not c else -np.inf
        for a, s, c in zip(area, supporting, chosen, strict=True)
    ]
    fourth = int(np.argmax(tie_key(np.array(opposite))))
    chosen[fourth] |= count >= 4 and bool(np.isfinite(opposite[fourth]))
    remaining = count - sum(chosen)
    rest = sorted((i for i in range(k) if not chosen[i]), key=lambda i: -tie_key(depths[i]))
    for i in rest[: max(remaining, 0)]:
        chosen[i] = True
    return chosen
