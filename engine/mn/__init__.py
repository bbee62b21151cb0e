"""A small Magnum-like math module: the types Habitat tutorials use via ``import magnum as mn``.

rigidsim code writes ``from engine import mn`` and then uses the same names as Magnum's Python
bindings: :class:`Vector2`, :class:`Vector3`, :class:`Vector4`, :class:`Vector2i`,
:class:`Vector3i`, :class:`Color3`, :class:`Color4`, :class:`Quaternion`, :class:`Deg`,
:class:`Rad`, :class:`Matrix3x3`, :class:`Matrix3`, :class:`Matrix4`, :class:`Range1D`,
:class:`Range2D`, :class:`Range3D` and the free functions and constants of ``mn.math``
(:mod:`engine.mn.math`), and :class:`Vector3d` (``==`` with Magnum's double epsilon).

Magnum names Habitat code touches for features rigidsim lacks (asset importers, mesh and
scene tools, image views) exist so that code imports: the modules :mod:`engine.mn.trade`,
:mod:`engine.mn.meshtools`, :mod:`engine.mn.scenetools` and the names ``MeshPrimitive``,
``PixelFormat`` (real enums), ``PixelStorage`` and ``MutableImageView2D`` (placeholders that
raise ``NotImplementedError`` when constructed; :mod:`engine.mn.images`).
Float types compare with Magnum's fuzzy ``==`` (relative epsilon 1e-5, see
:mod:`engine.mn.vectors`). The types are thin wrappers around NumPy arrays so that they mix
freely with lists and ``np.ndarray`` (``Vector3 + [1, 2, 3]``, ``np.asarray(v)``).

Conventions (declared once, used everywhere in rigidsim)
--------------------------------------------------------
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

Read :mod:`~engine.mn.vectors`, :mod:`~engine.mn.rotations`, :mod:`~engine.mn.matrices`,
:mod:`~engine.mn.ranges`, :mod:`~engine.mn.colors`, :mod:`~engine.mn.math`. May import:
NumPy only; every other folder of ``engine`` may import it.
"""

from __future__ import annotations

from engine.mn import math, meshtools, scenetools, trade
from engine.mn.colors import Color3, Color4
from engine.mn.images import MutableImageView2D, PixelFormat, PixelStorage
from engine.mn.matrices import Matrix3, Matrix3x3, Matrix4
from engine.mn.ranges import Range1D, Range2D, Range3D
from engine.mn.rotations import (
    Quaternion,
    matrix_to_quaternion,
    quaternion_multiply,
    quaternion_to_matrix,
    to_quaternion,
)
from engine.mn.trade import MeshPrimitive
from engine.mn.vectors import (
    Deg,
    Rad,
    Vector2,
    Vector2i,
    Vector3,
    Vector3d,
    Vector3i,
    Vector4,
    stable_norm,
    to_vector3,
)

__all__ = [
    "Color3",
    "Color4",
    "Deg",
    "Matrix3",
    "Matrix3x3",
    "Matrix4",
    "MeshPrimitive",
    "MutableImageView2D",
    "PixelFormat",
    "PixelStorage",
    "Quaternion",
    "Rad",
    "Range1D",
    "Range2D",
    "Range3D",
    "Vector2",
    "Vector2i",
    "Vector3",
    "Vector3d",
    "Vector3i",
    "Vector4",
    "math",
    "meshtools",
    "scenetools",
    "trade",
    "matrix_to_quaternion",
    "quaternion_multiply",
    "quaternion_to_matrix",
    "stable_norm",
    "to_quaternion",
    "to_vector3",
]
