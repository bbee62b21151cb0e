"""Habitat's ``habitat_sim.utils.common`` quaternion helpers, on rigidsim's quaternion type.

Habitat code often converts between numpy-quaternion (``np.quaternion(w, x, y, z)``),
Magnum (``mn.Quaternion((x, y, z), w)``) and "coeffs" lists ``[x, y, z, w]`` with these
helpers. rigidsim has a single quaternion type, :class:`engine.mn.Quaternion` (stored
``[x, y, z, w]``, scalar last), so the helpers keep Habitat's names and meaning but return
``mn.Quaternion``; inputs may be any quaternion-like value :func:`engine.mn.to_quaternion`
accepts (an ``mn.Quaternion``, an object with ``w, x, y, z`` attributes, or ``[x, y, z, w]``).

Conventions: right handed, angles in radians, a rotation by ``theta`` about a unit axis ``u``
is ``q = (u sin(theta/2), cos(theta/2))`` and rotates vectors as ``v' = q v q*``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from engine import mn

__all__ = [
    "quat_from_angle_axis",
    "quat_from_coeffs",
    "quat_from_magnum",
    "quat_from_two_vectors",
    "quat_rotate_vector",
    "quat_to_angle_axis",
    "quat_to_coeffs",
    "quat_to_magnum",
]


def quat_from_coeffs(coeffs: Any) -> mn.Quaternion:
    """The quaternion of a ``[x, y, z, w]`` list or ``(4,)`` array (normalized).

    >>> quat_from_coeffs([0.0, 0.0, 0.0, 1.0])
    Quaternion((0, 0, 0), 1)
    """
    return mn.to_quaternion(np.asarray(coeffs, dtype=np.float64), "coeffs")


def quat_to_coeffs(quat: Any) -> np.ndarray:
    """``(4,) float64`` ``[x, y, z, w]`` of a quaternion-like value."""
    return mn.to_quaternion(quat, "quat").xyzw


def quat_from_magnum(quat: Any) -> mn.Quaternion:
    """Habitat converts Magnum to numpy-quaternion here; in rigidsim both are one type."""
    return mn.to_quaternion(quat, "quat")


def quat_to_magnum(quat: Any) -> mn.Quaternion:
    """Habitat converts numpy-quaternion to Magnum here; in rigidsim both are one type."""
    return mn.to_quaternion(quat, "quat")


def quat_from_angle_axis(theta: float, axis: Any) -> mn.Quaternion:
    """Rotation by ``theta`` radians about ``axis`` (3-vector, normalized here).

    >>> quat_rotate_vector(quat_from_angle_axis(math.pi / 2, [0, 1, 0]), [1, 0, 0]).round(12)
    array([ 0.,  0., -1.])
    """
    return mn.Quaternion.rotation(mn.Rad(float(theta)), mn.to_vector3(axis, "axis"))


def quat_to_angle_axis(quat: Any) -> tuple[float, np.ndarray]:
    """Angle in ``[0, 2 pi)`` radians and unit axis ``(3,)`` of a rotation.

    ``theta = 2 atan2(|v|, w)`` for ``q = (v, w)``; the identity returns ``(0, [1, 0, 0])``
    (any axis would do, Habitat returns x as well).
    """
    xyzw = mn.to_quaternion(quat, "quat").xyzw
    vector_length = float(np.linalg.norm(xyzw[:3]))
    if vector_length < 1e-12:
        return 0.0, np.array([1.0, 0.0, 0.0])
    theta = 2.0 * math.atan2(vector_length, xyzw[3])  # theta = 2 atan2(|v|, w)
    return theta, xyzw[:3] / vector_length


def quat_rotate_vector(quat: Any, vector: Any) -> np.ndarray:
    """``(3,) float64`` vector ``v' = q v q*`` (``vector`` any 3-vector)."""
    q = mn.to_quaternion(quat, "quat")
    return np.asarray(q.transform_vector(mn.to_vector3(vector, "vector")), dtype=np.float64)


def quat_from_two_vectors(v0: Any, v1: Any) -> mn.Quaternion:
    """The shortest rotation taking the direction of ``v0`` to that of ``v1``.

    With unit ``a, b``: axis ``a x b``, angle ``acos(a . b)``; opposite vectors turn by pi
    about any axis perpendicular to ``a``. Zero vectors raise ``ValueError``.
    """
    a = np.asarray(mn.to_vector3(v0, "v0"), dtype=np.float64)
    b = np.asarray(mn.to_vector3(v1, "v1"), dtype=np.float64)
    norm_a, norm_b = np.linalg.norm(a), np.linalg.norm(b)
    if norm_a < 1e-12 or norm_b < 1e-12:
        raise ValueError(f"quat_from_two_vectors needs non-zero vectors, got {a}, {b}")
    a, b = a / norm_a, b / norm_b
    axis = np.cross(a, b)
    cosine = float(np.clip(a @ b, -1.0, 1.0))
    if np.linalg.norm(axis) < 1e-12:
        if cosine > 0.0:
            return mn.Quaternion()
        # opposite: any perpendicular axis; cross with the least aligned basis vector
        axis = np.cross(a, np.eye(3)[int(np.argmin(np.abs(a)))])
    return quat_from_angle_axis(math.acos(cosine), axis)


# Habitat's id colors live in engine.utils.colors; re-exported here as Habitat has them
from engine.utils.colors import colorize_ids, d3_40_colors_hex, d3_40_colors_rgb  # noqa: E402

__all__ += ["colorize_ids", "d3_40_colors_hex", "d3_40_colors_rgb"]
