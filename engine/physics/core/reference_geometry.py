"""Plain 3-vector helpers and the contact point of the reference path.

Matrix-vector products are written out as three dot products (:func:`rotate`,
:func:`unrotate`) so they round like the batched ``einsum`` calls of the fast path.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def dot(u: np.ndarray, v: np.ndarray) -> float:
    """``u . v`` of two 3-vectors, summed in index order."""
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def dot12(u: np.ndarray, v: np.ndarray) -> float:
    """``u . v`` of two 12-vectors (a Jacobian row and a velocity or mobility row)."""
    return float(sum(x * y for x, y in zip(u.tolist(), v.tolist(), strict=True)))


def cross3(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``u x v`` of two 3-vectors."""
    return np.array(
        [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    )


def rotate(r: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``R v``: a body-frame vector in the world frame."""
    return np.array([dot(r[0], v), dot(r[1], v), dot(r[2], v)])


def unrotate(r: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``R^T v``: a world vector in the body frame."""
    return np.array([dot(r[:, 0], v), dot(r[:, 1], v), dot(r[:, 2], v)])


@dataclass
class Contact:
    """One contact point: world anchors on A and B, unit normal from A to B.

    ``depth = (point_a - point_b) . normal`` is positive when the bodies overlap.
    ``feature``: the number of the features it comes from (a rule's feature number, made
    the pair's contact key by ``reference_contacts.pair_contacts``).
    """

    point_a: np.ndarray
    point_b: np.ndarray
    normal: np.ndarray
    feature: int = 0

    @property
    def depth(self) -> float:
        return dot(self.point_a - self.point_b, self.normal)
