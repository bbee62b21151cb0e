"""Habitat's ``habitat_sim.utils.common``: the quaternion helpers and friends.

The quaternion helpers live in :mod:`engine.utils.quaternion_utils` and return what Habitat's
return (numpy-quaternion ``np.quaternion``, or ``mn.Quaternion`` for ``quat_to_magnum`` and
``random_quaternion``); they are re-exported here, as Habitat's ``utils.common`` does.
Habitat's newer layout has ``habitat_sim.utils.common.quaternion_utils``; the same import path
works here (``from engine.utils.common.quaternion_utils import quat_from_coeffs``): the module
is registered under that name too.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np

from engine import mn
from engine.utils import quaternion_utils
from engine.utils.quaternion_utils import (
    angle_between_quats,
    quat_from_angle_axis,
    quat_from_coeffs,
    quat_from_magnum,
    quat_from_two_vectors,
    quat_rotate_vector,
    quat_to_angle_axis,
    quat_to_coeffs,
    quat_to_magnum,
    random_quaternion,
)

# ``engine.utils.common.quaternion_utils`` resolves to the same module (Habitat's newer path)
sys.modules.setdefault(f"{__name__}.quaternion_utils", quaternion_utils)

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
    "quaternion_utils",
    "random_quaternion",
]


# Habitat's id colors live in engine.utils.colors; re-exported here as Habitat has them, and
# ``engine.utils.common.common`` (Habitat's module of them) resolves to that module
from engine.utils import colors  # noqa: E402
from engine.utils.colors import colorize_ids, d3_40_colors_hex, d3_40_colors_rgb  # noqa: E402

sys.modules.setdefault(f"{__name__}.common", colors)

__all__ += ["colorize_ids", "d3_40_colors_hex", "d3_40_colors_rgb", "orthonormalize_rotation_shear"]


def orthonormalize_rotation_shear(transformation: Any) -> mn.Matrix4:
    """The 4x4 ``transformation`` with its 3x3 block made a pure rotation (Habitat's core helper).

    Gram-Schmidt on the columns in order x, y, z: scaling and shear are removed, the
    translation is kept, and a left-handed block is turned right handed (z = x cross y).
    ValueError for a non-finite matrix or a block of rank below 2.
    """
    matrix = np.array(transformation, dtype=np.float64)
    if matrix.shape != (4, 4) or not np.all(np.isfinite(matrix)):
        raise ValueError(f"transformation must be a finite 4x4 matrix, got {transformation!r}")
    x, y = matrix[:3, 0], matrix[:3, 1]
    x_len = float(np.linalg.norm(x))
    y = y - (y @ x) / max(x_len * x_len, 1e-300) * x  # y minus its part along x
    y_len = float(np.linalg.norm(y))
    if x_len < 1e-12 or y_len < 1e-12:
        raise ValueError(f"transformation has a degenerate rotation block: {transformation!r}")
    x, y = x / x_len, y / y_len
    matrix[:3, :3] = np.column_stack([x, y, np.cross(x, y)])
    return mn.Matrix4(matrix)
