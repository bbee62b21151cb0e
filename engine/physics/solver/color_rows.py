"""The fused color update: the normal and friction rows of one graph color in one pass.

Box2D v3's ``b2SolveContact`` in structure-of-arrays form. Each manifold keeps one column
vector, its *row state* (``S = 4`` point slots; ``rho`` the radius of each slot's friction
circle, ``mu lambda_n``)::

    x = [V = (v_a, w_a, v_b, w_b) (12) | 1 | lambda_n, lambda_t1, lambda_t2 (S each)
         | lambda_n', lambda_t1', lambda_t2', rho (S each)]

The accumulated impulses ``lambda`` stay in ``x`` for the whole solve; only the 12
velocities are gathered from the bodies and scattered back, once per color and sweep.
Every step of sequential impulses (Catto 2005, see :mod:`sequential_impulses`) is a matrix
times ``x`` followed by a clamp:

* normal rows, the accumulated impulse clamped ``>= 0``::

      lambda_n' = max(lambda_n - m_n (J_n V + b), 0) = max(P_n x, 0),
      P_n = [-m_n J_n | -m_n b | I]

* friction rows, which see the velocities after the normal impulses, ``V + W_n (lambda_n'
  - lambda_n)``, and the circles' radii::

      lambda_t* = lambda_t - m_t J_t (V + W_n (lambda_n' - lambda_n))      = P_t x
      rho       = mu lambda_n'

  then each slot's 2-D impulse is scaled back onto the Coulomb circle ``|lambda_t'| <= rho``;
* the velocities once, ``V += W_n (lambda_n' - lambda_n) + W_t (lambda_t' - lambda_t) =
  W (lambda' - lambda)``, and ``lambda = lambda'``.

This is the order of the plain solver (a manifold's normal rows, then its friction rows
reading the new velocities: :func:`reference_solver._normal_impulses` and
``_friction_impulses``); only the sums run in another order. A color and sweep costs 14
NumPy calls (the separate normal and friction updates with their own gathers took 24).
The quantities are kept by kind (all t1 of a manifold, then all t2, then all rho) so that
the circle's elementwise calls run over contiguous runs of ``S`` numbers; the velocity
change is not folded into one more matrix (``[I 0 -W W] x``, two calls fewer): its
identity and ``-W`` blocks made the matrices 40 % larger, and on 500 cubes the step spent
more time making and reading them than the calls saved. Without accumulated impulses
(box2d-lite's toggle, ``accumulate_impulses=False``) the primed entries are increments:
``P_n`` and ``P_t`` have no ``I`` columns, ``rho = mu (lambda_n + dl_n)``, ``V += W dl``
and ``lambda += dl``. The first ``block_normal_sweeps`` replace ``lambda_n'`` by the block
candidates where they keep every impulse non-negative (:func:`block_matrix`).

Gauss-Seidel over the slots (``block_jacobi=False``) sweeps a color once per used slot,
each time with matrices whose rows of the other slots keep their impulses (``lambda' =
lambda``, or a zero increment; their friction circles are not applied): :func:`one_slot`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.settings import BLOCK_FEASIBILITY_TOLERANCE, MAX_MANIFOLD_POINTS

#: point slots per manifold
SLOTS = MAX_MANIFOLD_POINTS
S = SLOTS
#: the row state's columns (module docstring)
ONE = 12
LAMBDA = slice(13, 13 + 3 * S)
LAMBDA_N = slice(13, 13 + S)
LAMBDA_T = slice(13 + S, 13 + 3 * S)
PRIMED = slice(13 + 3 * S, 13 + 6 * S)
PRIMED_N = slice(13 + 3 * S, 13 + 4 * S)
#: what P_t writes: lambda_t1', lambda_t2', rho
FRICTION_OUT = slice(13 + 4 * S, 13 + 7 * S)
WIDTH = FRICTION_OUT.stop
#: the inputs of P_n ([V, 1, lambda_n]) and P_t (up to lambda_n')
NORMAL_INPUT, FRICTION_INPUT = LAMBDA_N.stop, PRIMED_N.stop


@dataclass
class RowMatrices:
    """The matrices of all ``m`` manifolds of a step (module docstring): ``normal (m, S,
    NORMAL_INPUT)`` ``P_n``, ``friction (m, 3S, FRICTION_INPUT)`` ``P_t`` (rows t1, t2, rho),
    ``w (m, 12, 3S)`` ``W = [W_n W_t]`` in the order of lambda; with the block
    normal solve ``block (m, 2S, NORMAL_INPUT)`` ``[P_B; P_B']`` and ``touching (m, S,
    1)``; ``accumulate``: the primed entries are accumulated impulses (else increments)."""

    normal: np.ndarray
    friction: np.ndarray
    w: np.ndarray
    block: np.ndarray | None = None
    touching: np.ndarray | None = None
    accumulate: bool = True


@dataclass
class ColorRows:
    """Views of one color's ``manifolds`` into the work array and the matrices, made once
    per step so that a sweep only does algebra; ``slot``: the one slot these rows update
    (Gauss-Seidel over the slots; ``others`` the other slots), None: all.

    ``gather (k, 12, 1)`` flat velocity indices of [v_a, w_a, v_b, w_b]; ``v``, ``lam``,
    ``primed`` the row state's parts; ``x_normal``, ``x_friction`` the inputs of the
    matrices; ``primed_n (k, S, 1)``, ``friction_out (k, 3S, 1)`` what
    ``P_n`` and ``P_t`` write, and ``t1``, ``t2``, ``rho (k, 1, S)``, ``pairs (k, 2, S)``
    views of the latter; the matrices' rows ``normal``, ``friction``, ``w``, ``block``,
    ``touching``.
    """

    manifolds: slice
    slot: int | None
    others: list[int]
    gather: np.ndarray
    v: np.ndarray
    lam: np.ndarray
    primed: np.ndarray
    x_normal: np.ndarray
    x_friction: np.ndarray
    primed_n: np.ndarray
    friction_out: np.ndarray
    t1: np.ndarray
    t2: np.ndarray
    rho: np.ndarray
    pairs: np.ndarray
    normal: np.ndarray
    friction: np.ndarray
    w: np.ndarray
    block: np.ndarray | None
    touching: np.ndarray | None


def new_work(impulse: np.ndarray) -> np.ndarray:
    """The work array ``(m, WIDTH, 1)``: row states holding the constant 1 and the cached
    ``impulse (m, S, 3)`` (normal, t1, t2) as lambda and lambda'."""
    work = np.zeros((len(impulse), WIDTH, 1))
    work[:, ONE] = 1.0
    work[:, LAMBDA, 0] = impulse.swapaxes(1, 2).reshape(len(impulse), 3 * S)
    work[:, PRIMED] = work[:, LAMBDA]
    return work


def impulses(work: np.ndarray) -> np.ndarray:
    """The accumulated impulses ``(m, S, 3)`` (normal, t1, t2) of a work array."""
    return work[:, LAMBDA, 0].reshape(len(work), 3, S).swapaxes(1, 2).copy()


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


def by_kind(rows: np.ndarray) -> np.ndarray:
    """The tangent rows ``(m, 2S, ...)`` of a batch, (t1, t2) per slot, reordered as all t1
    then all t2 (the row state's order)."""
    m = len(rows)
    return rows.reshape(m, S, 2, -1).swapaxes(1, 2).reshape(m, 2 * S, -1)


def row_matrices(batch, bias: np.ndarray, accumulate: bool) -> RowMatrices:
    """The :class:`RowMatrices` of a :class:`contact_batch.ContactBatch` with the velocity
    bias ``bias (m, S, 1)`` (``b``: a gap may close by ``gap / h`` this step)."""
    m = len(bias)
    scaled_normal = -batch.normal_mass[..., None] * batch.normal_jac  # -m_n J_n
    scaled_tangent = by_kind(-batch.tangent_mass[..., None] * batch.tangent_jac)  # -m_t J_t
    coupling = scaled_tangent @ batch.normal_w  # -m_t J_t W_n, (m, 2S, S)
    friction = np.zeros((m, 3 * S, FRICTION_INPUT))  # rows: t1, t2, rho of each slot
    friction[:, : 2 * S, :ONE] = scaled_tangent
    friction[:, : 2 * S, PRIMED_N] = coupling
    mu_eye = batch.friction[:, :, None] * np.eye(S)  # (m, S, S)
    friction[:, 2 * S :, PRIMED_N] = mu_eye  # rho = mu lambda_n'
    if accumulate:
        friction[:, : 2 * S, LAMBDA_N] = -coupling
        friction[:, : 2 * S, LAMBDA_T] = np.eye(2 * S)
    else:
        friction[:, 2 * S :, LAMBDA_N] = mu_eye  # rho = mu (lambda_n + dl_n)
    w = np.concatenate([batch.normal_w, by_kind(batch.tangent_w.swapaxes(1, 2)).swapaxes(1, 2)], 2)
    with_block = batch.normal_block is not None and accumulate
    return RowMatrices(
        normal_matrix(scaled_normal, batch.normal_mass[..., None] * bias, accumulate),
        friction,
        w,
        block_matrix(batch, bias) if with_block else None,
        batch.touching[..., None] if with_block else None,
        accumulate,
    )


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


def one_slot(matrix: np.ndarray, slot: int, first: int, keep: bool) -> np.ndarray:
    """``matrix (k, r, c)`` (``P_n`` or ``P_t``, whose impulse rows start at column
    ``first``) with every impulse row but ``slot``'s replaced by a row that keeps that
    impulse (``keep``: ``lambda' = lambda``, else a zero increment); the rows of rho stay."""
    rows = matrix.shape[1]
    kinds = min(rows // S, 2)  # the normal (1) or the tangent (2) rows carry impulses
    mine = np.zeros(rows, dtype=bool)
    mine[slot : kinds * S : S] = True
    mine[kinds * S :] = True  # rho
    kept = np.zeros_like(matrix)
    if keep:
        kept[:, : kinds * S, first : first + kinds * S] = np.eye(kinds * S)
    return np.where(mine[:, None], matrix, kept)


def color_rows(
    work: np.ndarray,
    matrices: RowMatrices,
    gathers: np.ndarray,
    colors: list[tuple[slice, int]],
    block_jacobi: bool,
) -> list[list[ColorRows]]:
    """Each color's :class:`ColorRows`: ``colors`` holds ``(manifolds, used slots)`` per
    color, ``gathers (m, 12, 1)`` the flat velocity indices of each manifold. Block Jacobi:
    one update of all slots per color; otherwise one per used slot, in slot order."""
    out = []
    for s, used in colors:
        slots: list[int | None] = [None] if block_jacobi else list(range(used))
        out.append([_rows(work[s], matrices, gathers[s], s, slot) for slot in slots])
    return out


def _rows(z: np.ndarray, matrices: RowMatrices, gather, s: slice, slot: int | None) -> ColorRows:
    """The :class:`ColorRows` of the manifolds ``s`` (row states ``z``) for all slots or one
    (the block normal solve, made only with block Jacobi, takes all slots)."""
    friction_out = z[:, FRICTION_OUT]
    kinds = z[:, FRICTION_OUT, 0].reshape(len(z), 3, S)  # a view: t1, t2, rho
    normal, friction = matrices.normal[s], matrices.friction[s]
    if slot is not None:
        normal = one_slot(normal, slot, LAMBDA_N.start, matrices.accumulate)
        friction = one_slot(friction, slot, LAMBDA_T.start, matrices.accumulate)
    with_block = matrices.block is not None and slot is None
    return ColorRows(
        s,
        slot,
        [] if slot is None else [k for k in range(S) if k != slot],
        gather,
        z[:, :ONE],
        z[:, LAMBDA],
        z[:, PRIMED],
        z[:, :NORMAL_INPUT],
        z[:, :FRICTION_INPUT],
        z[:, PRIMED_N],
        friction_out,
        kinds[:, 0:1],
        kinds[:, 1:2],
        kinds[:, 2:3],
        kinds[:, 0:2],
        normal,
        friction,
        matrices.w[s],
        matrices.block[s] if with_block else None,  # type: ignore[index]
        matrices.touching[s] if with_block else None,  # type: ignore[index]
    )


def rows_matrix(rows: ColorRows, matrix: np.ndarray) -> np.ndarray:
    """The rows of a normal-only matrix ``(m, S, NORMAL_INPUT)`` (positions, restitution;
    accumulated) that ``rows`` update: its manifolds, and only its slot."""
    mine = matrix[rows.manifolds]
    return mine if rows.slot is None else one_slot(mine, rows.slot, LAMBDA_N.start, True)


def fused_update(rows: ColorRows, flat: np.ndarray, accumulate: bool, block: bool) -> None:
    """One sweep of a color's normal and friction rows (module docstring) on the flat body
    velocities ``flat (6 n,)``; ``block``: take the block normal candidates where they keep
    every impulse non-negative (needs ``rows.block``). Call inside
    ``np.errstate(divide="ignore", invalid="ignore")`` (the circle's 0 / 0).

    Reference: :func:`reference_solver._normal_impulses` then ``_friction_impulses``."""
    rows.v[...] = flat[rows.gather]
    np.matmul(rows.normal, rows.x_normal, out=rows.primed_n)
    if block and rows.block is not None:
        _block_candidates(rows)
    np.maximum(rows.primed_n, 0.0, out=rows.primed_n)  # lambda_n' >= 0 (or dl_n >= 0)
    np.matmul(rows.friction, rows.x_friction, out=rows.friction_out)  # t1, t2, rho
    # back onto the circle: scale = min(1, rho / |lambda_t|) for t1 and t2 of each slot;
    # fmin ignores the NaN of 0 / 0 (no friction impulse and no limit: scale 1)
    scale = np.hypot(rows.t1, rows.t2)
    np.divide(rows.rho, scale, out=scale)
    np.fmin(scale, 1.0, out=scale)
    if rows.slot is not None:  # one slot at a time: the others keep their impulses
        scale[:, :, rows.others] = 1.0
    rows.pairs *= scale
    if accumulate:
        rows.v += rows.w @ (rows.primed - rows.lam)  # V += W (lambda' - lambda)
        rows.lam[...] = rows.primed
    else:
        rows.v += rows.w @ rows.primed  # V += W dl
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
    """One sweep of a color's normal rows alone with the matrix rows ``normal (k, S,
    NORMAL_INPUT)`` (the position solve's ``P_n``, or the restitution pass's;
    :func:`rows_matrix`): ``lambda_n' = max(P x, 0)``, ``V += W_n (lambda_n' - lambda_n)``
    (every other primed entry must equal its unprimed one: :func:`sync_primed`).

    Reference: :func:`reference_solver._normal_impulses` (positions), and
    ``_restitution_impulses``."""
    rows.v[...] = flat[rows.gather]
    np.matmul(normal, rows.x_normal, out=rows.primed_n)
    np.maximum(rows.primed_n, 0.0, out=rows.primed_n)
    rows.v += rows.w @ (rows.primed - rows.lam)  # only lambda_n' changed
    rows.lam[...] = rows.primed
    flat[rows.gather] = rows.v


def sync_primed(work: np.ndarray) -> None:
    """``lambda' = lambda`` for every row (before the normal-only passes)."""
    work[:, PRIMED] = work[:, LAMBDA]
