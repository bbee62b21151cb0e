"""Vectorized unit-quaternion helpers, order ``[x, y, z, w]`` (scalar last, like scipy).

A unit quaternion q = (v, w) rotates a vector by ``R(q) p``; composition ``q1 * q2`` applies
q2 first. Rotation by angle theta about unit axis u: ``q = (u sin(theta/2), cos(theta/2))``.

Speed note: for the few-body arrays of a physics step, NumPy's per-call overhead dominates,
so the bilinear maps (rotation matrix, Hamilton product, cross product) are written as one
outer product and one matrix product with a constant coefficient table. For example
``R_ij(q) = sum_ab q_a q_b A[a, b, ij]`` with ``A`` read off
``R = (w^2 - v.v) I + 2 v v^T + 2 w [v]x``.
"""

from __future__ import annotations

import numpy as np

# one rotation matrix -> [x, y, z, w] (Shepperd's method): the scalar path lives in engine.mn
from engine.mn.rotations import matrix_to_quaternion as matrix_to_quat  # noqa: F401

from .settings import SMALL_ROTATION_ANGLE, TINY

X, Y, Z, W = range(4)


def _table(shape, entries) -> np.ndarray:
    table = np.zeros(shape)
    for index, value in entries:
        table[index] += value
    return table


# R_ij = sum_ab q_a q_b MATRIX_TABLE[a*4 + b, i*3 + j]   (unit quaternions)
_R = {
    (0, 0): [(W, W, 1), (X, X, 1), (Y, Y, -1), (Z, Z, -1)],
    (0, 1): [(X, Y, 2), (W, Z, -2)],
    (0, 2): [(X, Z, 2), (W, Y, 2)],
    (1, 0): [(X, Y, 2), (W, Z, 2)],
    (1, 1): [(W, W, 1), (X, X, -1), (Y, Y, 1), (Z, Z, -1)],
    (1, 2): [(Y, Z, 2), (W, X, -2)],
    (2, 0): [(X, Z, 2), (W, Y, -2)],
    (2, 1): [(Y, Z, 2), (W, X, 2)],
    (2, 2): [(W, W, 1), (X, X, -1), (Y, Y, -1), (Z, Z, 1)],
}
MATRIX_TABLE = _table(
    (16, 9), [((a * 4 + b, i * 3 + j), c) for (i, j), terms in _R.items() for a, b, c in terms]
)
# (q1 * q2)_k = sum_ab q1_a q2_b PRODUCT_TABLE[a*4 + b, k]:
# vector = w1 v2 + w2 v1 + v1 x v2, scalar = w1 w2 - v1 . v2
_EPS = [(0, 1, 2, 1), (1, 2, 0, 1), (2, 0, 1, 1), (0, 2, 1, -1), (2, 1, 0, -1), (1, 0, 2, -1)]
PRODUCT_TABLE = _table(
    (16, 4),
    [((W * 4 + k, k), 1) for k in range(3)]
    + [((k * 4 + W, k), 1) for k in range(3)]
    + [((i * 4 + j, k), s) for i, j, k, s in _EPS]
    + [((W * 4 + W, W), 1)]
    + [((k * 4 + k, W), -1) for k in range(3)],
)
# (a x b)_k = sum_ij a_i b_j eps_ijk
CROSS_TABLE = _table((9, 3), [((i * 3 + j, k), s) for i, j, k, s in _EPS])


def _outer(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Flattened outer products ``(..., len_a * len_b)``."""
    return (a[..., :, None] * b[..., None, :]).reshape(a.shape[:-1] + (-1,))


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross products of ``(..., 3)`` arrays (faster than ``np.cross`` on small arrays)."""
    if a.shape != b.shape:
        a, b = np.broadcast_arrays(a, b)
    return _outer(a, b) @ CROSS_TABLE


def vector_length(v: np.ndarray) -> np.ndarray:
    """``|v|`` over the last axis, kept as a length-1 axis: ``sqrt(v . v)``, the formula
    ``np.linalg.norm`` uses, without its Python-level argument handling (a hot path)."""
    return np.sqrt(np.add.reduce(v * v, axis=-1, keepdims=True))


def quat_multiply(q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Hamilton product ``q1 * q2`` of ``(..., 4)`` arrays [x, y, z, w]."""
    return _outer(q1, q2) @ PRODUCT_TABLE


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrices ``(..., 3, 3)`` of unit quaternions ``(..., 4)`` [x, y, z, w]."""
    return (_outer(q, q) @ MATRIX_TABLE).reshape(q.shape[:-1] + (3, 3))


def rotation_quat(rotation_vector: np.ndarray) -> np.ndarray:
    """Quaternions ``(..., 4)`` of rotation vectors ``(..., 3)`` (angle = norm, axis = direction).

    ``exp(theta u / 2) = (u sin(theta / 2), cos(theta / 2))``; a zero vector gives identity.
    """
    angle = np.sqrt(np.sum(rotation_vector * rotation_vector, axis=-1, keepdims=True))
    # sin(theta/2) / theta -> 1/2 as theta -> 0 (the axis is irrelevant at zero angle)
    turned = angle > SMALL_ROTATION_ANGLE
    half = angle / 2
    scale = np.where(turned, np.sin(half) / np.where(turned, angle, 1.0), 0.5)
    return np.concatenate([rotation_vector * scale, np.cos(half)], axis=-1)


def rotation_vector(q_now: np.ndarray, q_before: np.ndarray) -> np.ndarray:
    """``(k, 3)`` axis times angle (rad, in [0, pi]) of the turn ``q_now q_before^-1`` (the
    inverse of :func:`rotation_quat`) from
    unit quaternions ``[x, y, z, w]`` ``(k, 4)``."""
    inverse = q_before * np.array([-1.0, -1.0, -1.0, 1.0])  # conjugate = inverse (unit)
    turn = quat_multiply(q_now, inverse)
    turn = np.where(turn[:, 3:] < 0.0, -turn, turn)  # q and -q: the shorter way round
    sine = vector_length(turn[:, :3])[:, 0]
    angle = 2.0 * np.arctan2(sine, turn[:, 3])
    axis = turn[:, :3] / np.maximum(sine, TINY)[:, None]
    return axis * angle[:, None]


def live_rotations(bodies) -> np.ndarray:
    """``(n, 3, 3)`` rotation matrices of all ``n = bodies.count`` slots: computed for the
    live bodies, identity for freed slots (whose quaternion is the identity anyway), so a
    world that once held many objects pays only for those alive."""
    n = bodies.count
    live = np.flatnonzero(bodies.body_alive[:n])
    if len(live) == n:  # no freed slot (the usual world): every body's matrix
        return quat_to_matrix(bodies.body_rotation[live])
    rotation = np.tile(np.eye(3), (n, 1, 1))
    rotation[live] = quat_to_matrix(bodies.body_rotation[live])
    return rotation
