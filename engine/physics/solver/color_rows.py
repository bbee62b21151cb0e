"""The fused color update: the normal and friction rows of one graph color in one pass.

Box2D v3's ``b2SolveContact`` in structure-of-arrays form. Each manifold keeps one column
vector, its *row state* (``S = 4`` point slots; ``rho`` the radius of a slot's friction
circle, ``mu lambda_n``)::

    x = [V = (v_a, w_a, v_b, w_b) (12) | 1 | lambda_n (S) | (lambda_t1, lambda_t2, .) x S
         | lambda_n' (S) | (lambda_t1', lambda_t2', rho) x S]

The accumulated impulses ``lambda`` stay in ``x`` for the whole solve; only the 12
velocities are gathered from the bodies and scattered back, once per color and sweep.
Every step of sequential impulses (Catto 2005, see :mod:`sequential_impulses`) is a matrix
times ``x`` followed by a clamp:

* normal rows, the accumulated impulse clamped ``>= 0``::

      lambda_n' = max(lambda_n - m_n (J_n V + b), 0) = max(P_n x, 0),
      P_n = [-m_n J_n | -m_n b | I]

* friction rows, which see the velocities after the normal impulses, ``V + W_n (lambda_n'
  - lambda_n)``, and the circle's radius::

      lambda_t* = lambda_t - m_t J_t (V + W_n (lambda_n' - lambda_n))      = P_t x
      rho       = mu lambda_n'

  then each slot's 2-D impulse is scaled back onto the Coulomb circle ``|lambda_t'| <= rho``;
* the velocities once, ``V += W_n (lambda_n' - lambda_n) + W_t (lambda_t' - lambda_t) =
  [-W  W] [lambda; lambda']``, and ``lambda = lambda'``.

This is the order of the plain solver (a manifold's normal rows, then its friction rows
reading the new velocities: :func:`reference_solver._normal_impulses` and
``_friction_impulses``); only the sums run in another order. A color and sweep costs 13
NumPy calls (the separate normal and friction updates with their own gathers took 24).
The velocity change is not folded into one more matrix (``[I 0 -W W] x``, one call
fewer): its identity block made the matrices a third larger, and on 500 cubes the step
spent more time reading them than the call saved.
Without accumulated impulses (box2d-lite's toggle, ``accumulate_impulses=False``) the
primed entries are increments: ``P_n`` and ``P_t`` have no ``I`` columns, ``rho = mu
(lambda_n + dl_n)``, ``V += W dl`` and ``lambda += dl``. The first
``block_normal_sweeps`` replace ``lambda_n'`` by the block candidates where they keep every
impulse non-negative (:func:`block_matrix`).

Gauss-Seidel over the slots (``block_jacobi=False``) gives each slot of a color its own
:class:`ColorRows` (its rows of ``P_n`` and ``P_t``, its own gather and scatter): the other
slots' primed entries equal their unprimed ones, so ``P_t`` and ``[-W W]`` see no stale change.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.settings import BLOCK_FEASIBILITY_TOLERANCE, MAX_MANIFOLD_POINTS

#: point slots per manifold
SLOTS = MAX_MANIFOLD_POINTS
S = SLOTS
#: the row state's columns (module docstring): the constant 1, the impulses lambda (normal,
#: then (t1, t2, unused) per slot), the primed impulses (normal, then (t1, t2, rho) per
#: slot), the new velocities
ONE = 12
LAMBDA = slice(13, 13 + 4 * S)
LAMBDA_N = slice(13, 13 + S)
PRIMED = slice(13 + 4 * S, 13 + 8 * S)
PRIMED_N = slice(13 + 4 * S, 13 + 5 * S)
PRIMED_T = slice(13 + 5 * S, 13 + 8 * S)
WIDTH = PRIMED.stop
#: the inputs of P_n ([V, 1, lambda_n]) and P_t (up to lambda_n'); [-W W] reads
#: [lambda, lambda']
NORMAL_INPUT, FRICTION_INPUT = LAMBDA_N.stop, PRIMED_N.stop
CHANGES = slice(LAMBDA.start, PRIMED.stop)


@dataclass
class RowMatrices:
    """The matrices of all ``m`` manifolds of a step (module docstring): ``normal (m, S,
    NORMAL_INPUT)`` ``P_n``, ``friction (m, 3S, FRICTION_INPUT)`` ``P_t`` (rows t1, t2, rho
    of each slot), ``update (m, 12, 8S)`` ``[-W W]`` of the velocity sweeps and
    ``normal_update`` the one of the normal-only passes (the same array when impulses are
    accumulated); with the block normal solve ``block (m, 2S, NORMAL_INPUT)`` ``[P_B;
    P_B']`` and ``touching (m, S, 1)``."""

    normal: np.ndarray
    friction: np.ndarray
    update: np.ndarray
    normal_update: np.ndarray
    block: np.ndarray | None = None
    touching: np.ndarray | None = None


@dataclass
class ColorRows:
    """Views of one color's ``manifolds`` (all their slots, or one of them: ``slots``) into
    the work array and the matrices, made once per step so that a sweep only does algebra.

    ``gather (k, 12, 1)`` flat velocity indices of [v_a, w_a, v_b, w_b]; ``v``, ``lam``,
    ``primed`` the row state's parts; ``x_normal``, ``x_friction``, ``x_changes`` the
    inputs of the matrices; ``primed_n (k, r, 1)`` and ``primed_t (k, r, 3)`` the
    entries this block computes (``r``: 1 slot or all), ``friction_out (k, 3r, 1)`` the
    latter as ``P_t``'s output and ``t1``, ``t2``, ``rho``, ``pairs`` views of them; the
    matrices' rows ``normal``, ``friction``, ``update``, ``normal_update``, ``block``,
    ``touching``.
    """

    manifolds: slice
    slots: slice
    gather: np.ndarray
    v: np.ndarray
    lam: np.ndarray
    primed: np.ndarray
    x_normal: np.ndarray
    x_friction: np.ndarray
    x_changes: np.ndarray
    primed_n: np.ndarray
    primed_t: np.ndarray
    friction_out: np.ndarray
    t1: np.ndarray
    t2: np.ndarray
    rho: np.ndarray
    pairs: np.ndarray
    normal: np.ndarray
    friction: np.ndarray
    update: np.ndarray
    normal_update: np.ndarray
    block: np.ndarray | None
    touching: np.ndarray | None


def new_work(impulse: np.ndarray) -> np.ndarray:
    """The work array ``(m, WIDTH, 1)``: row states holding the constant 1 and the cached
    ``impulse (m, S, 3)`` (normal, t1, t2) as lambda and lambda'."""
    work = np.zeros((len(impulse), WIDTH, 1))
    work[:, ONE] = 1.0
    work[:, LAMBDA_N, 0] = impulse[:, :, 0]
    work[:, LAMBDA_N.stop : LAMBDA.stop, 0].reshape(-1, S, 3)[:, :, :2] = impulse[:, :, 1:]
    work[:, PRIMED] = work[:, LAMBDA]
    return work


def impulses(work: np.ndarray) -> np.ndarray:
    """The accumulated impulses ``(m, S, 3)`` (normal, t1, t2) of a work array."""
    out = np.empty((len(work), S, 3))
    out[:, :, 0] = work[:, LAMBDA_N, 0]
    out[:, :, 1:] = work[:, LAMBDA_N.stop : LAMBDA.stop, 0].reshape(-1, S, 3)[:, :, :2]
    return out


def normal_matrix(scaled_jac: np.ndarray, mass_bias: np.ndarray, identity: bool) -> np.ndarray:
    """``P_n (m, S, NORMAL_INPUT) = [-m_n J_n | -m_n b | I]`` from ``scaled_jac (m, S, 12)``
    (``-m_n J_n``) and ``mass_bias (m, S, 1)`` (``m_n b``); without ``identity`` the ``I``
    is 0 (the candidates are increments)."""
    matrix = np.zeros((len(scaled_jac), S, NORMAL_INPUT))
    matrix[:, :, :ONE] = scaled_jac
    matrix[:, :, ONE : ONE + 1] = -mass_bias
    if identity:
        matrix[:, :, LAMBDA_N] = np.eye(S)
    return matrix


def row_matrices(batch, bias: np.ndarray, accumulate: bool) -> RowMatrices:
    """The :class:`RowMatrices` of a :class:`contact_batch.ContactBatch` with the velocity
    bias ``bias (m, S, 1)`` (``b``: a gap may close by ``gap / h`` this step)."""
    m = len(bias)
    scaled_normal = -batch.normal_mass[..., None] * batch.normal_jac  # -m_n J_n
    scaled_tangent = -batch.tangent_mass[..., None] * batch.tangent_jac  # -m_t J_t
    coupling = scaled_tangent @ batch.normal_w  # -m_t J_t W_n, (m, 2S, S)
    friction = np.zeros((m, S, 3, FRICTION_INPUT))  # rows (t1, t2, rho) of each slot
    friction[:, :, :2, :ONE] = scaled_tangent.reshape(m, S, 2, ONE)
    friction[:, :, :2, PRIMED_N] = coupling.reshape(m, S, 2, S)
    mu_eye = batch.friction[:, :, None] * np.eye(S)  # (m, S, S)
    friction[:, :, 2, PRIMED_N] = mu_eye  # rho = mu lambda_n'
    if accumulate:
        friction[:, :, :2, LAMBDA_N] = -coupling.reshape(m, S, 2, S)
        lam_t = friction[:, :, :2, LAMBDA_N.stop : LAMBDA.stop].reshape(m, S, 2, S, 3)
        lam_t[:, :, :2, :, :2] = np.eye(S)[:, None, :, None] * np.eye(2)[None, :, None, :]
    else:
        friction[:, :, 2, LAMBDA_N] = mu_eye  # rho = mu (lambda_n + dl_n)
    w = _w_columns(batch)
    update = _update_matrix(w, accumulate)
    return RowMatrices(
        normal_matrix(scaled_normal, batch.normal_mass[..., None] * bias, accumulate),
        friction.reshape(m, 3 * S, FRICTION_INPUT),
        update,
        update if accumulate else _update_matrix(w, True),
        block_matrix(batch, bias) if batch.normal_block is not None and accumulate else None,
        batch.touching[..., None] if batch.normal_block is not None else None,
    )


def _w_columns(batch) -> np.ndarray:
    """``[W_n W_t] (m, 12, 4S)`` in the order of lambda (normal, then (t1, t2, 0) per slot)."""
    m = len(batch.normal_w)
    w = np.zeros((m, 12, 4 * S))
    w[:, :, :S] = batch.normal_w
    w[:, :, S:].reshape(m, 12, S, 3)[..., :2] = batch.tangent_w.reshape(m, 12, S, 2)
    return w


def _update_matrix(w: np.ndarray, accumulate: bool) -> np.ndarray:
    """``(m, 12, 8S)``: ``[-W W]``, the velocity change ``W (lambda' - lambda)`` from
    ``[lambda; lambda']`` (accumulated), or ``[0 W]``, ``W dl``."""
    return np.concatenate([-w if accumulate else np.zeros_like(w), w], axis=2)


def block_matrix(batch, bias: np.ndarray) -> np.ndarray:
    """``[P_B; P_B'] (m, 2S, NORMAL_INPUT)`` of the block normal sweeps: the block candidates
    ``P_B x = lambda_n - B (J V + b)`` and the feasibility test ``P_B' x = (1 + tol)
    lambda_n - B (J V + b)`` (``>= 0``: the block keeps this impulse non-negative but for
    round-off, tol = ``BLOCK_FEASIBILITY_TOLERANCE``); ``bias (m, S, 1)`` is ``b``."""
    matrix = np.empty((len(bias), 2 * S, NORMAL_INPUT))
    matrix[:, :S, :ONE] = -batch.normal_block @ batch.normal_jac  # -B J
    matrix[:, :S, ONE : ONE + 1] = -batch.normal_block @ bias  # -B b
    matrix[:, :S, LAMBDA_N] = np.eye(S)
    matrix[:, S:] = matrix[:, :S]
    matrix[:, S:, LAMBDA_N] = (1.0 + BLOCK_FEASIBILITY_TOLERANCE) * np.eye(S)
    return matrix


def color_rows(
    work: np.ndarray,
    matrices: RowMatrices,
    gathers: np.ndarray,
    colors: list[tuple[slice, int]],
    block_jacobi: bool,
) -> list[list[ColorRows]]:
    """Each color's :class:`ColorRows`: ``colors`` holds ``(manifolds, used slots)`` per
    color, ``gathers (m, 12, 1)`` the flat velocity indices of each manifold. Block Jacobi:
    one block of all slots per color; otherwise one per used slot, in slot order."""
    out = []
    for s, used in colors:
        groups = [slice(0, S)] if block_jacobi else [slice(k, k + 1) for k in range(used)]
        out.append([_rows(work[s], matrices, gathers[s], s, rows) for rows in groups])
    return out


def _rows(z: np.ndarray, matrices: RowMatrices, gather, s: slice, rows: slice) -> ColorRows:
    """The :class:`ColorRows` of the manifolds ``s`` (row states ``z``), point slots ``rows``
    (the block normal solve, made only with block Jacobi, takes all slots)."""
    n0, t0 = PRIMED_N.start, PRIMED_T.start
    friction_out = z[:, t0 + 3 * rows.start : t0 + 3 * rows.stop]
    primed_t = friction_out.reshape(len(z), -1, 3)  # a view
    every_slot = rows.stop - rows.start == S
    with_block = matrices.block is not None and every_slot
    update = matrices.update[s]
    return ColorRows(
        s,
        rows,
        gather,
        z[:, :ONE],
        z[:, LAMBDA],
        z[:, PRIMED],
        z[:, :NORMAL_INPUT],
        z[:, :FRICTION_INPUT],
        z[:, CHANGES],
        z[:, n0 + rows.start : n0 + rows.stop],
        primed_t,
        friction_out,
        primed_t[:, :, 0:1],
        primed_t[:, :, 1:2],
        primed_t[:, :, 2:3],
        primed_t[:, :, 0:2],
        matrices.normal[s, rows],
        matrices.friction[s, 3 * rows.start : 3 * rows.stop],
        update,
        update if matrices.normal_update is matrices.update else matrices.normal_update[s],
        matrices.block[s] if with_block else None,  # type: ignore[index]
        matrices.touching[s] if with_block else None,  # type: ignore[index]
    )


def fused_update(rows: ColorRows, flat: np.ndarray, accumulate: bool, block: bool) -> None:
    """One sweep of a color's normal and friction rows (module docstring) on the flat body
    velocities ``flat (6 n,)``; ``block``: take the block normal candidates where they keep
    every impulse non-negative (needs ``rows.block``). Call inside
    ``np.errstate(divide="ignore", invalid="ignore")`` (the circle's 0 / 0).

    Reference: :func:`reference_solver._normal_impulses` then ``_friction_impulses``."""
    rows.v[...] = flat[rows.gather]
    if not accumulate:  # increments: the slots this block does not update add nothing
        rows.primed[...] = 0.0
    np.matmul(rows.normal, rows.x_normal, out=rows.primed_n)
    if block and rows.block is not None:
        _block_candidates(rows)
    np.maximum(rows.primed_n, 0.0, out=rows.primed_n)  # lambda_n' >= 0 (or dl_n >= 0)
    np.matmul(rows.friction, rows.x_friction, out=rows.friction_out)  # (t1, t2, rho) per slot
    # back onto the circle: scale = min(1, rho / |lambda_t|) for t1 and t2 of each slot;
    # fmin ignores the NaN of 0 / 0 (no friction impulse and no limit: scale 1)
    scale = np.hypot(rows.t1, rows.t2)
    np.divide(rows.rho, scale, out=scale)
    np.fmin(scale, 1.0, out=scale)
    rows.pairs *= scale
    rows.v += rows.update @ rows.x_changes  # V += W (lambda' - lambda)
    if accumulate:
        rows.lam[...] = rows.primed
    else:
        rows.lam += rows.primed
    flat[rows.gather] = rows.v


def _block_candidates(rows: ColorRows) -> None:
    """The block sweep: ``lambda_n' = P_B x`` for the manifolds where every slot's
    feasibility test ``P_B' x >= 0`` holds (the rows of B of the slots that do not touch are
    zero: they keep their Jacobi candidates ``P_n x``, written before)."""
    both = rows.block @ rows.x_normal  # (k, 2S, 1): block candidates, test
    feasible = (both[:, S:] >= 0.0).all(axis=1, keepdims=True)  # (k, 1, 1)
    np.copyto(rows.primed_n, both[:, :S], where=feasible & rows.touching)


def normal_update(rows: ColorRows, flat: np.ndarray, normal: np.ndarray) -> None:
    """One sweep of a color's normal rows alone with the matrix rows ``normal (k, r,
    NORMAL_INPUT)`` (the position solve's ``P_n``, or the restitution pass's): ``lambda_n'
    = max(P x, 0)``, ``V += W_n (lambda_n' - lambda_n)`` (every other primed entry must
    equal its unprimed one: :func:`sync_primed`).

    Reference: :func:`reference_solver._normal_impulses` (positions), and
    ``_restitution_impulses``."""
    rows.v[...] = flat[rows.gather]
    np.matmul(normal, rows.x_normal, out=rows.primed_n)
    np.maximum(rows.primed_n, 0.0, out=rows.primed_n)
    rows.v += rows.normal_update @ rows.x_changes
    rows.lam[...] = rows.primed  # only lambda_n' of this block's slots changed
    flat[rows.gather] = rows.v


def sync_primed(work: np.ndarray) -> None:
    """``lambda' = lambda`` for every row (before the normal-only passes)."""
    work[:, PRIMED] = work[:, LAMBDA]
