"""Short-vector dot products shared by the collision kernels.

``vecdot(u, v)`` is ``u . v`` over the last axis (2-4 components), broadcast over the rest:
``sum_k u_k v_k``. On NumPy 2.0 and later it is NumPy's ``np.vecdot``, one call that sums
the products in order; on NumPy 1.x (habitat-lab's environment keeps it) it is the same
products summed over the last axis, ``(u * v).sum(axis=-1)``, which for so short an axis
also adds them in order: the same numbers, one NumPy operation more.
"""

from __future__ import annotations

import numpy as np


def _summed_products(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``sum_k u_k v_k`` over the last axis, written as NumPy 1.x allows."""
    return (u * v).sum(axis=-1)


#: ``u . v`` over the last axis (see the module docstring)
vecdot = getattr(np, "vecdot", _summed_products)
