"""Short-vector dot products shared by the collision kernels.

``u . v = sum_k u_k v_k`` over the last axis (2-4 components), broadcast over the rest,
always the same products added left to right, ``(u_0 v_0 + u_1 v_1) + u_2 v_2``:

* :func:`summed_products`: written out, one multiply and add per component. It avoids
  NumPy's reduction over a short last axis, which pays ~50 ns per output element
  (``.sum(axis=-1)`` is 4x slower on a ``(150, 24, 3)`` array, 2.5x on ``(100, 2, 8, 3)``).
* ``vecdot``: NumPy's ``np.vecdot`` (NumPy 2.0 and later), one call that adds the products
  in the same order; on NumPy 1.x (habitat-lab's environment keeps it)
  :func:`summed_products`. The same numbers either way; only an exact zero may come out
  as +0 where the written-out sum gives -0.
* :func:`dot`: ``vecdot`` for small operands, :func:`summed_products` above
  ``DOT_VECDOT_SIZE`` components, where ``vecdot``'s per-result cost outweighs the calls
  it saves (measured 2x slower on a ``(150, 24, 3)`` array).
"""

from __future__ import annotations

import numpy as np

#: largest operand (components) :func:`dot` hands to ``vecdot`` (one call, about 25 ns per
#: result); larger ones get the written-out sum (a few calls, about 10 ns per result)
DOT_VECDOT_SIZE = 1024


def summed_products(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``sum_k u_k v_k`` over the last axis, written out (see the module docstring)."""
    total = u[..., 0] * v[..., 0]
    for k in range(1, max(u.shape[-1], v.shape[-1])):
        total += u[..., k] * v[..., k]
    return total


#: ``u . v`` over the last axis in one NumPy call where NumPy has ``vecdot``
vecdot = getattr(np, "vecdot", summed_products)


def dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``u . v`` over the last axis: ``vecdot`` up to ``DOT_VECDOT_SIZE`` components, the
    written-out sum above (see the module docstring)."""
    if max(u.size, v.size) <= DOT_VECDOT_SIZE:
        return vecdot(u, v)
    return summed_products(u, v)
