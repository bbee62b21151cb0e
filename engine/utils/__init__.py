"""Helpers a Habitat user finds under ``habitat_sim.utils`` (see :mod:`engine.utils.common`).

Habitat's ``viz_utils`` (videos) lives in :mod:`render.video`: ``from render import video as
vut`` replaces ``from habitat_sim.utils import viz_utils as vut``.
"""

from engine.utils import common

__all__ = ["common"]
