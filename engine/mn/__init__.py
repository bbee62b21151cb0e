"""A small Magnum-like math module: the types Habitat tutorials use via ``import magnum as mn``.

rigidsim code writes ``from engine import mn`` and then uses the same names as Magnum's Python
bindings: :class:`Vector3`, :class:`Quaternion`, :class:`Deg`, :class:`Rad`, :class:`Matrix4`,
:class:`Range3D`. The types are thin wrappers around NumPy arrays so that they mix freely with
lists and ``np.ndarray`` (``Vector3 + [1, 2, 3]``, ``np.asarray(v)``).

Conventions (declared once, used everywhere in rigidsim)
-------------------------------------------------------
* Right handed, Y up, -Z forward; meters, radians inside.
* A quaternion is stored as a ``(4,)`` float64 array in the order ``[x, y, z, w]`` (scalar last,
  like Magnum's ``Quaternion((x, y, z), w)`` and SciPy). Conversion from other orders
  (numpy-quaternion's ``(w, x, y, z)``, JSON's ``[w, x, y, z]``) happens only at the API boundary,
  in :func:`to_quaternion` and the template loaders.
* Rotating a vector: ``v' = q v q*``; the matrix of ``q`` is the usual
  ``R = (w^2 - |u|^2) I + 2 u u^T + 2 w [u]x`` with ``u = (x, y, z)``.

Magnum quirks kept on purpose: ``Vector3.dot()`` with no argument is the **squared** length, and
``Matrix4.translation`` is both a static constructor (``Matrix4.translation(v)``) and, on an
instance, the translation part (``m.translation``).
"""
from __future__ import annotations

from engine.mn.matrices import Matrix3x3, Matrix4, Range3D
from engine.mn.rotations import (
    Quaternion,
    matrix_to_quaternion,
    quaternion_multiply,
    quaternion_to_matrix,
    to_quaternion,
)
from engine.mn.vectors import Deg, Rad, Vector2, Vector3, to_vector3

__all__ = [
    "Deg",
    "Matrix3x3",
    "Matrix4",
    "Quaternion",
    "Rad",
    "Range3D",
    "Vector2",
    "Vector3",
    "matrix_to_quaternion",
    "quaternion_multiply",
    "quaternion_to_matrix",
    "to_quaternion",
    "to_vector3",
]
