"""Helpers a Habitat user finds under ``habitat_sim.utils`` (see :mod:`engine.utils.common`).

Habitat's ``viz_utils`` (videos) lives in :mod:`render.video`: ``from render import video as
vut`` replaces ``from habitat_sim.utils import viz_utils as vut``. As in Habitat,
``quat_from_angle_axis`` and ``quat_rotate_vector`` are also importable from here.
"""

from engine.utils import common, quaternion_utils
from engine.utils.common import quat_from_angle_axis, quat_rotate_vector

__all__ = ["common", "quat_from_angle_axis", "quat_rotate_vector", "quaternion_utils"]
