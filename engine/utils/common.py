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


# Habitat's id colors live in engine.utils.colors; re-exported here as Habitat has them
from engine.utils.colors import colorize_ids, d3_40_colors_hex, d3_40_colors_rgb  # noqa: E402

__all__ += ["colorize_ids", "d3_40_colors_hex", "d3_40_colors_rgb"]
