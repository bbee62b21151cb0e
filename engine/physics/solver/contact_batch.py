"""Contact rows of the solver: the arrays one step's sequential impulses work on.

For a contact point with normal ``n`` (from A to B), anchors ``r_a = p - x_a`` and
``r_b = p - x_b``, and body velocities ``V = (v_a, w_a, v_b, w_b)``, the relative velocity
along a direction ``d`` (the normal or one of two tangents, :func:`tangent_basis`) is the
Jacobian row times V (Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005)::

    J = [-d, -(r_a x d), d, r_b x d],     v_d = J V   (> 0 separating)

An impulse ``lambda`` along d changes the velocities by ``W lambda`` with ``W = M^-1 J^T``
(:func:`_rows`); the effective mass is ``m_eff = 1 / (J M^-1 J^T)``. With *mass splitting*
(Tonge et al. 2012) each of a manifold's ``n`` touching points sees ``n x`` the inverse mass,
``m_eff / n``, so its points can be solved together as one Jacobi block.

The block normal solve (``SolverSettings.block_normal_sweeps``) also needs, per manifold, the
matrix ``K = J_n M^-1 J_n^T`` of its touching points' normal rows and a smooth
pseudo-inverse ``B = (K + d I)^-1 K (K + d I)^-1`` (:func:`normal_blocks`):
``d_lambda = -B (J V + b)`` makes every touching point's ``v_n + b`` zero at once. K is
singular for a box face (four coplanar points: rank 3); ``d = BLOCK_REGULARIZATION`` times
K's largest diagonal entry keeps the directions K barely sees from huge impulses (Box2D
``b2_contact_solver.cpp`` solves its two-point block exactly and guards its condition
number instead).

:func:`build_batch` makes all rows of a step at once from padded per-manifold arrays
(``S = 4`` point slots): the normal rows ``(m, S, 12)``, the tangent rows ``(m, 2S, 12)``,
their ``W`` and effective masses, depths, the approach speeds ``J V`` before the solve
(restitution's input) and the cached impulses (warm starting). The plain version, one point
at a time, is :func:`reference_solver.build_rows` (tests check both agree). :mod:`solver`
runs the iterations on a :class:`ContactBatch`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.quaternions import vector_length
from ..core.settings import (
    BLOCK_REGULARIZATION,
    MAX_MANIFOLD_POINTS,
    PENETRATION_SLOP,
    SPLIT_TOUCH_DISTANCE,
    TANGENT_AXIS_SWITCH,
    TINY,
)
from .lumped_rows import LumpedRows

#: point slots per manifold
SLOTS = MAX_MANIFOLD_POINTS


@dataclass
class ContactBatch:
    """Solver arrays for ``m`` manifolds sorted by color, ``S = 4`` point slots each.

    Shapes: ``body_a, body_b (m,)``; ``normal_jac (m, S, 12)``; ``normal_w (m, 12, S)``
    (``W^T`` for matmul); ``normal_mass (m, S)`` (split effective mass, 0 in empty slots);
    ``tangent_jac (m, 2S, 12)``, ``tangent_w (m, 12, 2S)``, ``tangent_mass (m, 2S)``;
    ``friction (m, 1)``, ``restitution (m, 1)``; ``depth``, ``approach_speed (m, S)``;
    ``impulse (m, S, 3)`` accumulated (normal, t1, t2) in N s; ``color_slices`` list of
    ``(start, stop)`` into the manifold axis, ``color_points`` the most points of a manifold
    in each color; ``pair_bodies (m, 2)`` [body_a, body_b]; ``mask (m, S)`` slots holding a
    point; ``split (m, 1)`` the mass-splitting count of each manifold; ``priority_starts``
    per color, the first of its stage rows; ``lower (m, 2)`` the body nearer the stage (shock
    propagation, None: no shock pass); ``slop`` (m, 1) m, penetration left by the position
    solve. ``touching (m, S)`` the slots closer than ``SPLIT_TOUCH_DISTANCE`` (the points
    mass splitting counts), ``normal_block (m, S, S)`` their ``B`` (zero rows and
    columns for the other slots; None: no block normal solve, :func:`normal_blocks`).
    ``cache``: the loop's per-batch views (:class:`SolverCache`, filled on first use).
    """

    body_a: np.ndarray
    body_b: np.ndarray
    mask: np.ndarray
    normal_jac: np.ndarray
    normal_w: np.ndarray
    normal_mass: np.ndarray
    tangent_jac: np.ndarray
    tangent_w: np.ndarray
    tangent_mass: np.ndarray
    friction: np.ndarray
    restitution: np.ndarray
    depth: np.ndarray
    approach_speed: np.ndarray
    impulse: np.ndarray
    color_slices: list
    color_points: list
    pair_bodies: np.ndarray
    split: np.ndarray
    priority_starts: list = field(default_factory=list)
    lower: np.ndarray | None = None
    slop: np.ndarray | float = PENETRATION_SLOP
    touching: np.ndarray | None = None
    normal_block: np.ndarray | None = None
    cache: SolverCache = field(default_factory=lambda: SolverCache())


@dataclass
class SolverCache:
    """What the solver loops derive from a :class:`ContactBatch` once and reuse in every
    sweep: ``rows``, the quantity-major impulses, the :class:`color_rows.RowMatrices` and
    each color's :class:`color_rows.ColorRows` (``(state, matrices, colors)``), every
    manifold's velocity
    indices (``gathers``, :func:`batch_gathers`), and the stage-priority
    pass's lumped rows (``lumped``) and shock rows (``shock``; ``shock_ready`` tells a
    computed None, no shock pass, from one not computed yet) and their per-color sweep
    blocks (``sweeps``, ``{"stage" | "shock": blocks}``). None: not made yet."""

    rows: tuple | None = None
    gathers: np.ndarray | None = None
    lumped: LumpedRows | None = None
    shock: LumpedRows | None = None
    shock_ready: bool = False
    sweeps: dict[str, list[tuple]] = field(default_factory=dict)


def velocity_gather(pair_bodies: np.ndarray) -> np.ndarray:
    """``(k, 12, 1)`` indices of [v_a, w_a, v_b, w_b] of the pairs ``pair_bodies (k, 2)`` into
    the flattened ``(n * 6,)`` velocities: component c of body b is entry ``6 b + c``."""
    return (6 * pair_bodies[:, :, None] + np.arange(6)).reshape(-1, 12, 1)


def batch_gathers(batch: ContactBatch) -> np.ndarray:
    """:func:`velocity_gather` of all the batch's manifolds ``(m, 12, 1)``, made once and
    kept on the batch (the sweeps slice it per color)."""
    if batch.cache.gathers is None:
        batch.cache.gathers = velocity_gather(batch.pair_bodies)
    return batch.cache.gathers


def tangent_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents ``(..., 3)`` orthogonal to unit normals ``(..., 3)``."""
    # pick the world axis least aligned with n, t1 = normalize(n x axis), t2 = n x t1;
    # written out: n x e_x = (0, n_z, -n_y), n x e_y = (-n_z, 0, n_x)
    n_x, n_y, n_z = normal[..., 0], normal[..., 1], normal[..., 2]
    use_x = np.abs(n_x) < TANGENT_AXIS_SWITCH
    t1 = np.zeros_like(normal)
    t1[..., 0] = np.where(use_x, 0.0, -n_z)
    t1[..., 1] = np.where(use_x, n_z, 0.0)
    t1[..., 2] = np.where(use_x, -n_y, n_x)
    t1 /= np.maximum(vector_length(t1), TINY)
    return t1, cross3(normal, t1)


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross products of ``(..., 3)`` float arrays from their component slices: nine large
    NumPy calls (on thousands of rows, several times faster than ``quaternions.cross``),
    written into one output (``np.stack`` would cost a dozen Python-level calls more)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast(a, b).shape)
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def _rows(direction, arms, inv_mass_a, inv_mass_b, inv_inertia_a, inv_inertia_b):
    """Jacobian rows ``(m, R, 12)`` and ``W = M^-1 J^T`` rows for directions ``(m, R, 3)``
    and arms ``(m, R, 2, 3)`` (``r_a``, ``r_b`` of each row)."""
    arm_x_d = cross3(arms, direction[:, :, None])  # r_a x d and r_b x d in one call
    ra_x_d, rb_x_d = arm_x_d[:, :, 0], arm_x_d[:, :, 1]
    minus_d, minus_ra_x_d = -direction, -ra_x_d
    jac = np.concatenate([minus_d, minus_ra_x_d, direction, rb_x_d], axis=-1)
    # W = [-d / m_a, -I_a^-1 (r_a x d), d / m_b, I_b^-1 (r_b x d)]
    # (I^-1 x)^T = x^T I^-T for the R rows of each manifold: one stacked matmul
    w = np.concatenate(
        [
            minus_d * inv_mass_a[:, None, None],
            minus_ra_x_d @ inv_inertia_a.swapaxes(1, 2),
            direction * inv_mass_b[:, None, None],
            rb_x_d @ inv_inertia_b.swapaxes(1, 2),
        ],
        axis=-1,
    )
    return jac, w


@dataclass
class ManifoldPoints:
    """Padded contact points of ``m`` manifolds, ``S = 4`` slots each: world anchors
    ``points_a, points_b (m, S, 3)``, unit ``normals (m, S, 3)`` from A to B (anything in
    the empty slots: :func:`build_batch` puts a unit normal there), used slots ``counts
    (m,)`` and the bodies ``body_a, body_b (m,)`` of each pair."""

    points_a: np.ndarray
    points_b: np.ndarray
    normals: np.ndarray
    counts: np.ndarray
    body_a: np.ndarray
    body_b: np.ndarray


@dataclass
class SolverBodies:
    """What the solver reads of the ``n`` bodies: ``position (n, 3)`` m, ``inv_mass (n,)``
    1/kg and ``inv_inertia (n, 3, 3)`` world frame (zero for bodies the solver does not
    move), ``velocity (n, 6)`` [v, w] at the start of the step (the approach speed)."""

    position: np.ndarray
    inv_mass: np.ndarray
    inv_inertia: np.ndarray
    velocity: np.ndarray


@dataclass
class PairCoefficients:
    """Per manifold: ``friction, restitution (m,)`` pair values, cached ``impulse (m, S,
    3)`` (normal, t1, t2) in N s, and ``slop (m,)`` m, the penetration its position solve
    leaves (None: ``PENETRATION_SLOP``; small bodies get less, see ``ManifoldStore.feature``)."""

    friction: np.ndarray
    restitution: np.ndarray
    impulse: np.ndarray
    slop: np.ndarray | None = None


@dataclass
class ColorOrder:
    """How the manifolds are ordered: ``color_slices`` ``(start, stop)`` per graph color;
    ``priority_starts`` per color, the first of its stage rows (they end each color; None:
    no stage rows); ``lower (m, 2)`` bool, which body of a dynamic pair is nearer the stage
    through contacts (shock propagation; None: no shock pass)."""

    color_slices: list[tuple[int, int]]
    priority_starts: list[int] | None = None
    lower: np.ndarray | None = None


def build_batch(
    contacts: ManifoldPoints,
    bodies: SolverBodies,
    pairs: PairCoefficients,
    order: ColorOrder,
    split_mass: bool = False,
    block_normal: bool = False,
) -> ContactBatch:
    """Assemble a :class:`ContactBatch` from padded per-manifold contact arrays; with
    ``split_mass`` each point's effective mass is divided by its manifold's touching points;
    with ``block_normal`` the batch carries each manifold's ``B`` (:func:`normal_blocks`).

    Reference: :func:`reference_solver.build_rows` (one point at a time).
    """
    points_a, points_b, normals = contacts.points_a, contacts.points_b, contacts.normals
    counts, body_a, body_b = contacts.counts, contacts.body_a, contacts.body_b
    position, inv_mass, inv_inertia = bodies.position, bodies.inv_mass, bodies.inv_inertia
    mask = np.arange(SLOTS)[None, :] < counts[:, None]
    slot_used = mask[..., None]  # (m, S, 1)
    normals = np.where(slot_used, normals, [0.0, 1.0, 0.0])  # a harmless unit when empty
    point = 0.5 * (points_a + points_b)
    pair_bodies = np.stack([body_a, body_b], axis=1)  # (m, 2)
    # r_a = p - x_a and r_b = p - x_b of every slot: (m, S, 2, 3)
    r_ab = point[:, :, None] - position[pair_bodies][:, None]
    args = (inv_mass[body_a], inv_mass[body_b], inv_inertia[body_a], inv_inertia[body_b])
    t1, t2 = tangent_basis(normals)
    m = len(counts)
    # the rows of n, t1 and t2 of every slot at once: (m, S * 3, ...) in that order
    directions = np.stack([normals, t1, t2], axis=2).reshape(m, 3 * SLOTS, 3)
    arms = r_ab.repeat(3, axis=1)  # (m, 3S, 2, 3)
    jac, w = _rows(directions, arms, *args)
    jac, w = jac.reshape(m, SLOTS, 3, 12), w.reshape(m, SLOTS, 3, 12)
    normal_jac, normal_w = jac[:, :, 0], w[:, :, 0]
    tangent_jac = jac[:, :, 1:].reshape(m, 2 * SLOTS, 12)
    tangent_w = w[:, :, 1:].reshape(m, 2 * SLOTS, 12)
    depth = ((points_a - points_b) * normals).sum(axis=-1)
    # n_split = touching points (gap < SPLIT_TOUCH_DISTANCE) with mass splitting, else 1
    touching = mask & (depth > -SPLIT_TOUCH_DISTANCE)
    n_touching = np.maximum(touching.sum(axis=1), 1)[:, None]
    split = n_touching if split_mass else np.ones((len(counts), 1))
    # m_eff = 1 / (n_split J M^-1 J^T), for the rows (n, t1, t2) of each slot
    k_rows = (jac * w).sum(axis=-1)  # (m, S, 3)
    split_rows = split[:, :, None]
    mass = np.where(slot_used, 1.0 / (split_rows * np.maximum(k_rows, TINY)), 0.0)
    normal_mass, tangent_mass = mass[:, :, 0], mass[:, :, 1:].reshape(m, 2 * SLOTS)
    vab = bodies.velocity[pair_bodies].reshape(m, 12, 1)  # [v_a, w_a, v_b, w_b] of each pair
    approach = (normal_jac @ vab)[..., 0]
    starts = [start for start, _ in order.color_slices]  # colors are never empty
    return ContactBatch(
        body_a,
        body_b,
        mask,
        normal_jac,
        normal_w.swapaxes(1, 2),
        normal_mass,
        tangent_jac,
        tangent_w.swapaxes(1, 2),
        tangent_mass,
        pairs.friction[:, None],
        pairs.restitution[:, None],
        np.where(mask, depth, 0.0),
        approach,
        np.where(slot_used, pairs.impulse, 0.0),
        order.color_slices,
        np.maximum.reduceat(counts, starts).tolist(),  # the most points in each color
        pair_bodies,
        split,
        [stop for _, stop in order.color_slices]
        if order.priority_starts is None
        else list(order.priority_starts),
        order.lower,
        PENETRATION_SLOP if pairs.slop is None else pairs.slop[:, None],
        touching,
        normal_blocks(normal_jac, normal_w, touching) if block_normal else None,
    )


def normal_blocks(normal_jac: np.ndarray, normal_w: np.ndarray, touching: np.ndarray):
    """``B (m, S, S)``: a smooth pseudo-inverse ``(K + d I)^-1 K (K + d I)^-1`` of each
    manifold's ``K = J_n M^-1 J_n^T`` over its ``touching (m, S)`` slots, zero in the rows
    and columns of the other slots; ``d = eps s``, ``s`` K's largest touching diagonal entry
    and ``eps`` ``BLOCK_REGULARIZATION``.

    On an eigenvalue ``w`` of K, B is ``w / (w + d)^2``: ``1 / w`` where ``w >> d``, 0 on
    K's null space (a box face: four coplanar points, rank 3) and never more than
    ``1 / (4 d)`` in between, so a direction K barely sees gets no large impulse.
    ``normal_w (m, S, 12)`` holds the rows of ``W = M^-1 J^T``. The other slots are filled
    with ``s`` on the diagonal (one batched ``np.linalg.inv`` of the padded stack) and
    masked out after. Reference: :func:`reference_solver.normal_block`.
    """
    k = np.where(
        touching[:, :, None] & touching[:, None, :], normal_jac @ normal_w.swapaxes(1, 2), 0.0
    )
    scale = np.maximum(np.diagonal(k, axis1=1, axis2=2).max(axis=1), TINY)[:, None]  # s, (m, 1)
    fill = np.where(touching, BLOCK_REGULARIZATION * scale, scale)  # d, or s where not touching
    inverse = np.linalg.inv(k + fill[:, :, None] * np.eye(SLOTS))  # (K + d I)^-1
    return inverse @ k @ inverse  # zero rows and columns where k has them
