"""Slim color rows: one graph color's normal and friction rows, impulses kept quantity-major.

Sequential impulses (Catto 2005, see :mod:`sequential_impulses`) on the ``k`` manifolds of
one graph color, ``u`` point slots each, written for NumPy's per-call cost:

* every manifold's velocities are gathered as one column ``v = [v_a, w_a, v_b, w_b, 1]``
  (13): the flat velocity array the solver works on ends in a constant 1, so each row's
  bias rides in its matrix (one subtraction fewer per update);
* the matrices are manifold-major, ``(k, rows, 13)``, one small stacked matmul each;
* the accumulated impulses and every elementwise quantity are **quantity-major**: ``(u,
  k)`` arrays whose manifolds are contiguous (Box2D v3's structure-of-arrays contact
  constraints), so the clamps and the friction circle run over long contiguous runs; the
  matmuls write into them through transposed views.

One update of the normal rows, the accumulated impulse clamped ``>= 0``, in the form of
the impulse *taken off* ``q``::

    q = m_n (J_n v + b),   q' = min(q, lambda_n),   lambda_n -= q',   v -= W_n q'

(``lambda_n - q`` is the plain solver's new impulse before its clamp ``max(., 0)``); then
the friction rows, which read the velocities after the normal rows::

    lambda_t* = lambda_t - m_t J_t v,   lambda_t' = lambda_t* min(1, mu lambda_n / |lambda_t*|)

per slot (the 2-D impulse scaled back onto the Coulomb circle; ``fmin`` maps the 0 / 0 of
an unloaded slot to 1), ``v += W_t (lambda_t' - lambda_t)``. This is the plain solver's
order (a manifold's normal rows, then its friction rows, as
``reference_solver._normal_impulses`` and ``_friction_impulses`` do); only the sums run in
another order. A color and sweep is 17 NumPy calls (the friction impulses take turns
between two arrays, so nothing is copied back). Without accumulated impulses (box2d-lite's toggle,
``accumulate_impulses=False``) the clamps act on the increments: ``q' = min(q, 0)``, the
friction increment is scaled onto the circle of the new ``lambda_n``.

The first ``block_normal_sweeps`` take for a manifold the block candidates ``q_B = B (J_n
v + b)`` (:func:`contact_batch.normal_blocks`) where every slot keeps ``lambda_n - q_B >=
0`` but for round-off (``BLOCK_FEASIBILITY_TOLERANCE``), the Jacobi ``q`` elsewhere. The
normal-only passes (the restitution pass and the split-impulse position solve) run the
same rows with their own matrices and impulses (:func:`normal_update`, 7 calls).

Gauss-Seidel over the slots (``block_jacobi=False``) makes one :class:`ColorRows` per used
slot of a color, each the same update on that slot's rows alone.

Why this layout (measured, ``docs/physics_performance.md``): the previous fused update kept
all of a manifold's quantities in one column (14 calls a color and sweep), but every
elementwise call then ran over runs of 4 numbers strided through that column, and its
friction matrix was 12 x 29: per color it cost 1.06-1.67x this one at every size measured
(2 to 250 manifolds), although this one issues 3 calls more. So there is one kernel for
every color size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.settings import BLOCK_FEASIBILITY_TOLERANCE, MAX_MANIFOLD_POINTS

#: point slots per manifold
S = MAX_MANIFOLD_POINTS
#: a manifold's velocity column: [v_a, w_a, v_b, w_b] (12) and the constant 1
COLUMN = 13


@dataclass
class RowMatrices:
    """The manifold-major matrices of all ``m`` manifolds of a step: ``normal (m, S, 13)``
    ``m_n [J_n | b]``, ``normal_w (m, 13, S)`` ``[W_n; 0]``, ``tangent (m, 2, S, 13)`` ``-m_t
    [J_t | 0]`` (the t1 rows, then the t2 rows), ``tangent_w (m, 13, 2, S)``, ``friction (1,
    m)`` mu; with the block normal solve ``block (m, S, 13)`` ``B [J_n | b]`` and
    ``touching (S, m)`` (None: no block solve); ``accumulate``: the impulses are
    accumulated (else increments)."""

    normal: np.ndarray
    normal_w: np.ndarray
    tangent: np.ndarray
    tangent_w: np.ndarray
    friction: np.ndarray
    block: np.ndarray | None = None
    touching: np.ndarray | None = None
    accumulate: bool = True


@dataclass
class BlockRows:
    """A color's block normal rows: ``matrix (k, u, 13)`` ``B [J_n | b]``, ``touching (u,
    k)`` the slots it may change, the scratch ``q (u, k)`` and its column view ``q_col (k,
    u, 1)``."""

    matrix: np.ndarray
    touching: np.ndarray
    q: np.ndarray
    q_col: np.ndarray


@dataclass
class TangentImpulses:
    """A color's accumulated friction impulses ``lam (2, u, k)`` (t1, t2 of each slot, its
    manifolds contiguous), their views ``t1``, ``t2 (u, k)`` and their column view ``col
    (k, 2u, 1)`` (what the friction matmul writes)."""

    lam: np.ndarray
    t1: np.ndarray
    t2: np.ndarray
    col: np.ndarray

    @classmethod
    def of(cls, lam: np.ndarray) -> TangentImpulses:
        """The views of a contiguous ``lam (2, u, k)``."""
        t1, t2 = lam  # its two (u, k) halves
        return cls(lam, t1, t2, column_view(lam))


@dataclass
class ColorRows:
    """One color's rows (``manifolds``, the slots ``slots``), made once per step so that a
    sweep only does algebra.

    ``gather (k, 13, 1)`` flat indices of each manifold's velocity column; the matrices'
    rows ``normal (k, u, 13)``, ``normal_w (k, 13, u)``, ``tangent (k, 2u, 13)``,
    ``tangent_w (k, 13, 2u)``, ``mu (1, k)``; ``lam_n (u, k)`` a view of the normal
    impulses; ``tangents`` two :class:`TangentImpulses` that take turns (sweep ``i`` reads
    ``tangents[i % 2]`` and writes its new impulses into the other: no copy back);
    scratch ``q (u, k)``, ``dt (2, u, k)``, ``scale (u, k)`` and the column views ``q_col
    (k, u, 1)``, ``dt_col (k, 2u, 1)`` for the matmuls; ``block`` the :class:`BlockRows`
    (None: no block normal solve).
    """

    manifolds: slice
    slots: slice
    gather: np.ndarray
    normal: np.ndarray
    normal_w: np.ndarray
    tangent: np.ndarray
    tangent_w: np.ndarray
    mu: np.ndarray
    lam_n: np.ndarray
    tangents: tuple[TangentImpulses, TangentImpulses]
    q: np.ndarray
    q_col: np.ndarray
    dt: np.ndarray
    dt_col: np.ndarray
    scale: np.ndarray
    block: BlockRows | None


def new_impulses(impulse: np.ndarray) -> np.ndarray:
    """The quantity-major impulses ``(3, S, m)`` (normal, t1, t2) of ``impulse (m, S, 3)``."""
    return np.ascontiguousarray(impulse.transpose(2, 1, 0))


def impulses(state: np.ndarray) -> np.ndarray:
    """The impulses ``(m, S, 3)`` (normal, t1, t2) of a quantity-major ``state (3, S, m)``."""
    return state.transpose(2, 1, 0).copy()


def with_constant(gathers: np.ndarray, one: int) -> np.ndarray:
    """``(m, 13, 1)``: the velocity indices ``gathers (m, 12, 1)`` and the index ``one`` of the
    flat array's constant 1."""
    return np.concatenate([gathers, np.full((len(gathers), 1, 1), one)], axis=1)


def by_kind(rows: np.ndarray) -> np.ndarray:
    """The tangent rows ``(m, 2S, c)`` of a batch, (t1, t2) per slot, as ``(m, 2, S, c)``:
    all t1, then all t2."""
    return rows.reshape(len(rows), S, 2, -1).swapaxes(1, 2)


def normal_matrix(mass: np.ndarray, jac: np.ndarray, bias: np.ndarray) -> np.ndarray:
    """``(m, S, 13)`` ``m [J | b]`` of ``mass (m, S)``, ``jac (m, S, 12)``, ``bias (m, S,
    1)``: times a velocity column it gives ``m (J v + b)``."""
    matrix = np.empty((len(jac), S, COLUMN))
    matrix[:, :, :12] = jac
    matrix[:, :, 12:] = bias
    matrix *= mass[..., None]
    return matrix


def row_matrices(batch, bias: np.ndarray, accumulate: bool) -> RowMatrices:
    """The :class:`RowMatrices` of a :class:`contact_batch.ContactBatch` with the velocity
    bias ``bias (m, S, 1)`` (``b``: a gap may close by ``gap / h`` this step)."""
    m = len(bias)
    normal_w = np.zeros((m, COLUMN, S))
    normal_w[:, :12] = batch.normal_w
    tangent = np.zeros((m, 2, S, COLUMN))
    tangent[..., :12] = by_kind(-batch.tangent_mass[..., None] * batch.tangent_jac)
    tangent_w = np.zeros((m, COLUMN, 2, S))
    tangent_w[:, :12] = by_kind(batch.tangent_w.swapaxes(1, 2)).transpose(0, 3, 1, 2)
    block = touching = None
    if batch.normal_block is not None and accumulate:
        block = np.empty((m, S, COLUMN))
        block[:, :, :12] = batch.normal_block @ batch.normal_jac
        block[:, :, 12:] = batch.normal_block @ bias
        touching = np.ascontiguousarray(batch.touching.T)
    return RowMatrices(
        normal_matrix(batch.normal_mass, batch.normal_jac, bias),
        normal_w,
        tangent,
        tangent_w,
        np.ascontiguousarray(batch.friction.T),
        block,
        touching,
        accumulate,
    )


def color_rows(
    state: np.ndarray,
    matrices: RowMatrices,
    gathers: np.ndarray,
    colors: list[tuple[slice, int]],
    block_jacobi: bool,
) -> list[list[ColorRows]]:
    """Each color's :class:`ColorRows` on the impulses ``state (3, S, m)``: ``colors`` holds
    ``(manifolds, used slots)`` per color, ``gathers (m, 13, 1)`` (:func:`with_constant`).
    Block Jacobi: one update of the used slots per color; otherwise one per used slot, in
    slot order."""
    out = []
    for s, used in colors:
        groups = [slice(0, used)] if block_jacobi else [slice(j, j + 1) for j in range(used)]
        out.append([_rows(state, matrices, gathers[s], s, slots) for slots in groups])
    return out


def _rows(state, matrices: RowMatrices, gather, s: slice, slots: slice) -> ColorRows:
    """The :class:`ColorRows` of the manifolds ``s`` and the slots ``slots``."""
    k, u = s.stop - s.start, slots.stop - slots.start
    # the scratch in two allocations: q, the circle's scale and the block candidates (u,
    # k) each; the friction increments and the second friction impulses (2, u, k) each
    q, scale, q_block = np.empty((3, u, k))
    dt, lam_t = np.empty((2, 2, u, k))
    tangents = (
        TangentImpulses.of(np.array(state[1:, slots, s])),  # the cached impulses, a copy
        TangentImpulses.of(lam_t),
    )
    block = None
    if matrices.block is not None and matrices.touching is not None:
        block = BlockRows(
            matrices.block[s, slots], matrices.touching[slots, s], q_block, column_view(q_block)
        )
    return ColorRows(
        s,
        slots,
        gather,
        matrices.normal[s, slots],
        matrices.normal_w[s, :, slots],
        matrices.tangent[s, :, slots].reshape(k, 2 * u, COLUMN),  # a view when u = S
        matrices.tangent_w[s, :, :, slots].reshape(k, COLUMN, 2 * u),
        matrices.friction[:, s],
        state[0, slots, s],
        tangents,
        q,
        column_view(q),
        dt,
        column_view(dt),
        scale,
        block,
    )


def column_view(array: np.ndarray) -> np.ndarray:
    """``(k, r, 1)`` view of a contiguous quantity-major ``array (..., k)`` (``r`` = the
    product of its leading axes): what a stacked matmul reads or writes per manifold."""
    rows = array if array.ndim == 2 else array.reshape(-1, array.shape[-1])  # (r, k)
    return rows.T[:, :, None]


def velocity_update(
    rows: ColorRows, flat: np.ndarray, accumulate: bool, block: bool, sweep: int
) -> None:
    """Sweep ``sweep`` of a color's normal and friction rows (module docstring) on the flat
    velocities ``flat (6 n + 1,)`` (ending in the constant 1); ``block``: take the block
    normal candidates where they keep every impulse non-negative (needs ``rows.block``).
    Call inside ``np.errstate(divide="ignore", invalid="ignore")`` (the circle's 0 / 0);
    the friction impulses end in ``rows.tangents[(sweep + 1) % 2]`` (:func:`store_tangents`).

    Reference: ``reference_solver._normal_impulses`` then ``_friction_impulses``."""
    v = flat[rows.gather]  # (k, 13, 1)
    q, lam_n, scale = rows.q, rows.lam_n, rows.scale
    old, new = rows.tangents[sweep % 2], rows.tangents[(sweep + 1) % 2]
    np.matmul(rows.normal, v, out=rows.q_col)  # q = m_n (J_n v + b)
    if block and rows.block is not None:
        _block_candidates(rows.block, q, lam_n, v)
    np.minimum(q, lam_n if accumulate else 0.0, out=q)  # lambda_n - q >= 0 (or -q >= 0)
    lam_n -= q
    v -= rows.normal_w @ rows.q_col
    np.matmul(rows.tangent, v, out=new.col)  # -m_t J_t v
    if accumulate:
        new.lam += old.lam
    # back onto the circle: scale = min(1, mu lambda_n / |lambda_t|) for t1 and t2 of each
    # slot; fmin ignores the NaN of 0 / 0 (no friction impulse and no limit: scale 1)
    np.hypot(new.t1, new.t2, out=scale)
    np.divide(rows.mu * lam_n, scale, out=scale)
    np.fmin(scale, 1.0, out=scale)
    new.lam *= scale
    if accumulate:
        np.subtract(new.lam, old.lam, out=rows.dt)
        v += rows.tangent_w @ rows.dt_col
    else:  # new holds the increment
        v += rows.tangent_w @ new.col
        new.lam += old.lam
    flat[rows.gather] = v


def store_tangents(colors: list[list[ColorRows]], state: np.ndarray, sweeps: int) -> None:
    """Write the friction impulses after ``sweeps`` sweeps back into ``state (3, S, m)``."""
    for color in colors:
        for rows in color:
            state[1:, rows.slots, rows.manifolds] = rows.tangents[sweeps % 2].lam


def _block_candidates(block: BlockRows, q, lam_n, v: np.ndarray) -> None:
    """The block sweep: ``q = q_B = B (J_n v + b)`` for the manifolds where every slot keeps
    ``(1 + tol) lambda_n - q_B >= 0`` (the rows of B of the slots that do not touch are
    zero: they keep their Jacobi ``q``, written before); ``q``, ``lam_n (u, k)``."""
    np.matmul(block.matrix, v, out=block.q_col)
    feasible = (block.q <= (1.0 + BLOCK_FEASIBILITY_TOLERANCE) * lam_n).all(axis=0)
    np.copyto(q, block.q, where=feasible & block.touching)


def rows_matrix(rows: ColorRows, matrix: np.ndarray) -> np.ndarray:
    """The rows of a normal-only matrix ``(m, S, 13)`` (positions, restitution) that
    ``rows`` update: its manifolds and slots."""
    return matrix[rows.manifolds, rows.slots]


def normal_update(
    rows: ColorRows, flat: np.ndarray, matrix: np.ndarray, lam_n, relaxation=None
) -> None:
    """One sweep of a color's normal rows alone with the matrix rows ``matrix (k, u, 13)``
    (the position solve's ``m_n [J_n | b]``, or the restitution pass's:
    :func:`rows_matrix`) and the accumulated impulses ``lam_n (u, k)`` (updated):
    ``q = min(matrix v, lambda_n)``, ``lambda_n -= q``, ``v -= W_n q``. The soft step
    (:mod:`soft_step`) passes its impulse scales ``relaxation (u, k)``: ``q = matrix v +
    relaxation lambda_n`` before the clamp (2 calls more).

    Reference: ``reference_solver._normal_impulses`` (positions), and
    ``_restitution_impulses``; ``reference_soft._soft_normal_impulses``."""
    v = flat[rows.gather]
    np.matmul(matrix, v, out=rows.q_col)
    if relaxation is not None:  # Box2D v3's soft row: the impulse scale times lambda_n
        np.multiply(relaxation, lam_n, out=rows.scale)
        rows.q += rows.scale
    np.minimum(rows.q, lam_n, out=rows.q)
    lam_n -= rows.q
    v -= rows.normal_w @ rows.q_col
    flat[rows.gather] = v
