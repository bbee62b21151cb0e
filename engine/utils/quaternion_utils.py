"""Habitat's quaternion helpers (``habitat_sim.utils.common.quaternion_utils``), returning what
Habitat returns: numpy-quaternion's ``np.quaternion`` (``quaternion(w, x, y, z)``, scalar
first), except ``quat_to_magnum`` and ``random_quaternion``, which return ``mn.Quaternion``.

Three quaternion spellings meet here:

* numpy-quaternion ``np.quaternion(w, x, y, z)``: ``q.real`` is ``w``, ``q.imag`` is
  ``[x, y, z]`` (what Habitat's agent states hold);
* Magnum ``mn.Quaternion((x, y, z), w)``: ``q.scalar``, ``q.vector``;
* "coeffs" ``[x, y, z, w]`` (scalar last): the order the simulator backend stores.

Conventions: right handed, radians; a rotation by ``theta`` about the unit axis ``u`` is
``q = cos(theta/2) + sin(theta/2) u`` and rotates vectors as ``v' = q v q^-1``. Inputs that
Habitat types as ``np.quaternion`` also accept an ``mn.Quaternion`` (rigidsim's extension,
so the helpers work on object rotations directly). Like Habitat, ``quat_from_coeffs`` does
not normalize: a zero list gives the zero quaternion.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import quaternion as qt

from engine import mn

__all__ = [
    "angle_between_quats",
    "quat_from_angle_axis",
    "quat_from_coeffs",
    "quat_from_magnum",
    "quat_from_two_vectors",
    "quat_rotate_vector",
    "quat_to_angle_axis",
    "quat_to_coeffs",
    "quat_to_magnum",
    "random_quaternion",
]


def _as_np_quaternion(quat: Any) -> qt.quaternion:
    """An ``np.quaternion`` from an ``np.quaternion`` or an ``mn.Quaternion`` (not normalized)."""
    if isinstance(quat, qt.quaternion):
        return quat
    if isinstance(quat, mn.Quaternion):
        x, y, z, w = quat.xyzw
        return qt.quaternion(w, x, y, z)
    raise TypeError(f"expected an np.quaternion or mn.Quaternion, got {type(quat).__name__}")


def quat_from_coeffs(coeffs: Any) -> qt.quaternion:
    """The ``np.quaternion`` of coefficients ``[x, y, z, w]`` (imaginary part first)."""
    values = np.asarray(coeffs, dtype=np.float64).reshape(-1)
    if values.shape != (4,):
        raise ValueError(f"coeffs must have 4 entries [x, y, z, w], got {coeffs!r}")
    return qt.quaternion(values[3], values[0], values[1], values[2])


def quat_to_coeffs(quat: Any) -> np.ndarray:
    """``(4,) float64`` coefficients ``[x, y, z, w]`` of a quaternion."""
    q = _as_np_quaternion(quat)
    return np.array([q.x, q.y, q.z, q.w], dtype=np.float64)


def quat_to_magnum(quat: Any) -> mn.Quaternion:
    """``np.quaternion(w, x, y, z)`` -> ``mn.Quaternion((x, y, z), w)`` (not normalized)."""
    q = _as_np_quaternion(quat)
    return mn.Quaternion((q.x, q.y, q.z), q.w)


def quat_from_magnum(quat: Any) -> qt.quaternion:
    """``mn.Quaternion((x, y, z), w)`` -> ``np.quaternion(w, x, y, z)``."""
    return _as_np_quaternion(quat)


def quat_to_angle_axis(quat: Any) -> tuple[float, np.ndarray]:
    """``(theta, axis)`` of a rotation: ``theta = |r|``, ``axis = r / |r|`` with ``r`` the
    rotation vector ``2 log(q)``. Below 1e-5 rad the angle is 0 and the axis is +x (Habitat's
    hard-coded choice)."""
    rotation_vector = qt.as_rotation_vector(_as_np_quaternion(quat))
    theta = float(np.linalg.norm(rotation_vector))
    if abs(theta) < 1e-5:
        return 0.0, np.array([1.0, 0.0, 0.0])
    return theta, rotation_vector / theta


def quat_from_angle_axis(theta: float, axis: Any) -> qt.quaternion:
    """Rotation by ``theta`` radians about ``axis`` (normalized here): ``exp(theta u / 2)``."""
    direction = np.asarray(axis, dtype=np.float64).reshape(-1)
    length = float(np.linalg.norm(direction))
    if direction.shape != (3,) or not math.isfinite(length) or length == 0.0:
        raise ValueError(f"axis must be a finite non-zero 3-vector, got {axis!r}")
    return qt.from_rotation_vector(float(theta) * direction / length)


def quat_from_two_vectors(v0: Any, v1: Any) -> qt.quaternion:
    """The shortest rotation ``q`` with ``quat_rotate_vector(q, v0) ~ v1`` (directions).

    With unit ``a, b`` and ``c = a . b``: ``q = (s / 2, (a x b) / s)`` with
    ``s = sqrt(2 (1 + c))`` (half-way quaternion). For opposite vectors (``c ~ -1``) the axis
    is any unit vector perpendicular to both (the null space of ``[a; b]``), turned by pi.
    """
    a = np.asarray(v0, dtype=np.float64)
    b = np.asarray(v1, dtype=np.float64)
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    c = float(a @ b)
    if c < -1.0 + 1e-8:
        c = max(c, -1.0)
        _, _, vh = np.linalg.svd(np.stack([a, b]), full_matrices=True)
        w_squared = 0.5 * (1.0 + c)  # cos^2(theta / 2)
        axis = vh[2] * math.sqrt(1.0 - w_squared)
        return qt.quaternion(math.sqrt(w_squared), *axis)
    s = math.sqrt(2.0 * (1.0 + c))
    return qt.quaternion(0.5 * s, *(np.cross(a, b) / s))


def angle_between_quats(q1: Any, q2: Any) -> float:
    """Angle in radians of the rotation taking ``q1`` to ``q2``, in ``[0, pi]``:
    ``2 atan2(|dq.imag|, |dq.real|)`` with ``dq = conj(q1) q2``."""
    dq = np.conjugate(_as_np_quaternion(q1)) * _as_np_quaternion(q2)
    return float(2.0 * np.arctan2(np.linalg.norm(dq.imag), np.abs(dq.real)))


def quat_rotate_vector(q: Any, v: Any) -> np.ndarray:
    """``(3,)`` vector ``v' = q v q^-1`` (``v`` as the pure quaternion ``(0, v)``)."""
    vector = np.asarray(v, dtype=np.float64).reshape(-1)
    if vector.shape != (3,):
        raise ValueError(f"v must be a 3-vector, got {v!r}")
    quat = _as_np_quaternion(q)
    pure = qt.quaternion(0.0, *vector)
    return (quat * pure * quat.inverse()).imag


def random_quaternion() -> mn.Quaternion:
    """A uniformly random rotation as ``mn.Quaternion`` (Habitat returns Magnum here), from
    three uniform numbers ``u`` drawn with ``np.random.rand`` (Shoemake / LaValle,
    *Planning Algorithms* 5.2.2)::

        q = (sqrt(1-u0) sin(2 pi u1), sqrt(1-u0) cos(2 pi u1),
             sqrt(u0) sin(2 pi u2), sqrt(u0) cos(2 pi u2))      as (w, x, y, z)
    """
    u = np.random.rand(3)
    vector = (
        math.sqrt(1.0 - u[0]) * math.cos(2.0 * math.pi * u[1]),
        math.sqrt(u[0]) * math.sin(2.0 * math.pi * u[2]),
        math.sqrt(u[0]) * math.cos(2.0 * math.pi * u[2]),
    )
    return mn.Quaternion(vector, math.sqrt(1.0 - u[0]) * math.sin(2.0 * math.pi * u[1]))
