r"""Analytic contacts of capsules with capsules and spheres (rules ``capsule-capsule`` and
``sphere-capsule`` of :mod:`pair_table`), batched and in plain loops.

A capsule is the set of points within ``r`` of its axis segment ``p + s d``, ``s in [0, 1]``
(fcl builds it along its local Z axis, ``lz`` long); a sphere is a capsule whose segment is
one point. Two such shapes touch where their segments come closest (Ericson, Real-Time
Collision Detection, 5.1.9): with ``d_1, d_2`` the segments' directions, ``r = p_1 - p_2``,
``a = d_1 . d_1``, ``e = d_2 . d_2``, ``b = d_1 . d_2``, ``c = d_1 . r``, ``f = d_2 . r``,

.. math::

    s = \mathrm{clamp}\left(\frac{b f - c e}{a e - b^2}\right), \qquad
    t = \frac{b s + f}{e},

and when ``t`` leaves ``[0, 1]`` it is clamped and ``s`` recomputed for it (``s = clamp(-c /
a)`` at ``t = 0``, ``clamp((b - c) / a)`` at ``t = 1``). With the closest points ``c_1 = p_1 +
s d_1`` and ``c_2 = p_2 + t d_2``, distance :math:`\delta = |c_2 - c_1|` and normal
:math:`n = (c_2 - c_1) / \delta` (A to B), the contact is

.. math::

    p_A = c_1 + r_1 n, \qquad p_B = c_2 - r_2 n, \qquad
    \mathrm{depth} = (p_A - p_B) \cdot n = r_1 + r_2 - \delta,

kept while ``depth > -SPECULATIVE_DISTANCE``. Parallel axes
(:math:`a e - b^2 < (\sin\epsilon)^2 a e`, :math:`\epsilon` = ``CAPSULE_PARALLEL_SINE``)
touch along a line: the two ends of the overlap of B's axis projected on A's,
``s in [lo, hi]``, each make a contact (a capsule lying on another rests on two points, not
one). Crossing axes (:math:`\delta = 0`) push apart along ``d_1 x d_2``, coincident ones
along the pair's spread direction.
"""

from __future__ import annotations

import numpy as np

from ..core import settings
from ..core.quaternions import cross
from ..core.reference_geometry import Contact, cross3, dot, rotate
from ..core.shapes import Shape
from .contact_helpers import segment_in_body, spread_direction
from .pair_rules import ContactBatch, PairContext, PairJob


# ------------------------------------------------------------------------------------------
# batched: all jobs of the two rules at once
# ------------------------------------------------------------------------------------------
def capsule_pair_batch(
    jobs: list[PairJob], context: PairContext, out: ContactBatch
) -> list[PairJob]:
    """Contacts of capsule-capsule and sphere-capsule jobs (module docstring), arrays over
    the ``g`` jobs, up to two contacts each. Reference: :func:`capsule_pair`."""
    p1, d1, r1 = _world_segments(
        [job.shape_a for job in jobs], [job.body_a for job in jobs], context
    )
    p2, d2, r2 = _world_segments(
        [job.shape_b for job in jobs], [job.body_b for job in jobs], context
    )
    s, t, valid = _closest_parameters(p1, d1, p2, d2)  # (g, 2) each
    c1 = p1[:, None] + s[..., None] * d1[:, None]  # (g, 2, 3)
    c2 = p2[:, None] + t[..., None] * d2[:, None]
    delta = c2 - c1
    distance = np.sqrt((delta * delta).sum(axis=2))
    body_a = np.array([job.body_a for job in jobs])
    body_b = np.array([job.body_b for job in jobs])
    crossing = cross(d1, d2)
    sine = np.sqrt((crossing * crossing).sum(axis=1))
    apart = np.where(
        (sine > settings.TINY)[:, None],
        crossing / np.maximum(sine, settings.TINY)[:, None],
        spread_direction(body_a, body_b),
    )  # (g, 3): the direction of touching or crossing axes
    on_axis = distance <= settings.SPHERE_CENTER_ON_SURFACE
    n = np.where(
        on_axis[..., None], apart[:, None], delta / np.maximum(distance, settings.TINY)[..., None]
    )
    keep = valid & (distance < (r1 + r2)[:, None] + settings.SPECULATIVE_DISTANCE)
    g, k = np.nonzero(keep)
    seq = np.array([job.seq for job in jobs], dtype=np.int64)
    point_a = c1[g, k] + r1[g, None] * n[g, k]
    point_b = c2[g, k] - r2[g, None] * n[g, k]
    out.add(seq[g], k, point_a, point_b, n[g, k])
    return []


def _world_segments(shapes: list, bodies: list, context: PairContext):
    """World segment start ``(g, 3)``, direction ``d = q - p (g, 3)`` and radius ``(g,)``."""
    segments = [segment_in_body(shape) for shape in shapes]
    start = np.array([p for p, _, _ in segments])
    end = np.array([q for _, q, _ in segments])
    index = np.array(bodies, dtype=np.int64)
    rotation, position = context.rotation[index], context.bodies.body_position[index]
    world_start = np.einsum("gij,gj->gi", rotation, start) + position
    world_end = np.einsum("gij,gj->gi", rotation, end) + position
    radius = np.array([radius for _, _, radius in segments])
    return world_start, world_end - world_start, radius


def _closest_parameters(p1, d1, p2, d2):
    """Segment parameters ``s, t (g, 2)`` of up to two closest-point pairs, ``valid (g, 2)``."""
    r = p1 - p2
    a, e, b = (d1 * d1).sum(1), (d2 * d2).sum(1), (d1 * d2).sum(1)
    c, f = (d1 * r).sum(1), (d2 * r).sum(1)
    denom = a * e - b * b
    safe_a, safe_e = np.maximum(a, settings.TINY), np.maximum(e, settings.TINY)
    s = np.where(
        denom > 0.0, np.clip((b * f - c * e) / np.maximum(denom, settings.TINY), 0, 1), 0.0
    )
    t = (b * s + f) / safe_e
    s = np.where(
        t < 0, np.clip(-c / safe_a, 0, 1), np.where(t > 1, np.clip((b - c) / safe_a, 0, 1), s)
    )
    t = np.clip(t, 0, 1)
    # a sphere (a segment of length 0): its one point, the other segment's closest point
    s = np.where(a > 0, np.where(e > 0, s, np.clip(-c / safe_a, 0, 1)), 0.0)
    t = np.where(e > 0, np.where(a > 0, t, np.clip(f / safe_e, 0, 1)), 0.0)
    # parallel axes: the ends of B's axis projected on A's, clamped to A's, if they overlap
    lo = np.clip(np.minimum(-c, b - c) / safe_a, 0, 1)
    hi = np.clip(np.maximum(-c, b - c) / safe_a, 0, 1)
    sine_squared = settings.CAPSULE_PARALLEL_SINE**2
    line = (a > 0) & (e > 0) & (denom < sine_squared * a * e) & (hi > lo)
    s_pair = np.stack([np.where(line, lo, s), np.where(line, hi, 0.0)], axis=1)
    t_line = np.clip((b[:, None] * s_pair + f[:, None]) / safe_e[:, None], 0, 1)
    t_pair = np.where(line[:, None], t_line, np.stack([t, np.zeros_like(t)], axis=1))
    valid = np.stack([np.ones_like(line), line], axis=1)
    return s_pair, t_pair, valid


# ------------------------------------------------------------------------------------------
# reference: one job, plain floats
# ------------------------------------------------------------------------------------------
def capsule_pair(job: PairJob, context: PairContext) -> list[Contact] | None:
    """Contacts of one capsule-capsule or sphere-capsule job, in plain scalar code
    (mirrors :func:`capsule_pair_batch`)."""
    p1, d1, r1 = _world_segment(job.shape_a, context.pose(job.body_a))
    p2, d2, r2 = _world_segment(job.shape_b, context.pose(job.body_b))
    crossing = cross3(d1, d2)
    sine = float(np.sqrt(dot(crossing, crossing)))
    apart = crossing / sine if sine > settings.TINY else spread_direction(job.body_a, job.body_b)
    contacts = []
    for k, (s, t) in enumerate(_closest_parameter_pairs(p1, d1, p2, d2)):
        c1, c2 = p1 + s * d1, p2 + t * d2
        delta = c2 - c1
        distance = float(np.sqrt(dot(delta, delta)))
        n = apart if distance <= settings.SPHERE_CENTER_ON_SURFACE else delta / distance
        if distance < r1 + r2 + settings.SPECULATIVE_DISTANCE:
            contacts.append(Contact(c1 + r1 * n, c2 - r2 * n, n, k))
    return contacts


def _world_segment(shape: Shape, pose) -> tuple[np.ndarray, np.ndarray, float]:
    """World segment start, direction ``q - p`` and radius of one shape."""
    rotation, position = pose
    start, end, radius = segment_in_body(shape)
    world_start = rotate(rotation, start) + position
    return world_start, rotate(rotation, end) + position - world_start, radius


def _closest_parameter_pairs(p1, d1, p2, d2) -> list[tuple[float, float]]:
    """``[(s, t)]``: one closest-point pair, or the two ends of parallel axes' overlap."""
    r = p1 - p2
    a, e, b = dot(d1, d1), dot(d2, d2), dot(d1, d2)
    c, f = dot(d1, r), dot(d2, r)
    denom = a * e - b * b
    safe_a, safe_e = max(a, settings.TINY), max(e, settings.TINY)
    lo = _clamp(min(-c, b - c) / safe_a)
    hi = _clamp(max(-c, b - c) / safe_a)
    if a > 0 and e > 0 and denom < settings.CAPSULE_PARALLEL_SINE**2 * a * e and hi > lo:
        return [(s, _clamp((b * s + f) / safe_e)) for s in (lo, hi)]
    if a == 0.0 or e == 0.0:  # a sphere: its one point, the other's closest point
        return [(_clamp(-c / safe_a) if e == 0.0 else 0.0, _clamp(f / safe_e) if a == 0.0 else 0.0)]
    s = _clamp((b * f - c * e) / denom) if denom > 0.0 else 0.0
    t = (b * s + f) / safe_e
    if t < 0:
        s, t = _clamp(-c / safe_a), 0.0
    elif t > 1:
        s, t = _clamp((b - c) / safe_a), 1.0
    return [(s, t)]


def _clamp(value: float) -> float:
    """``value`` clamped to ``[0, 1]``."""
    return min(max(value, 0.0), 1.0)
