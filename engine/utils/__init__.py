"""Helpers a Habitat user finds under ``habitat_sim.utils``.

The submodules are :mod:`engine.utils.common` (quaternions, ``d3_40_colors_rgb``,
``colorize_ids``), :mod:`engine.utils.quaternion_utils` (Habitat's quaternion helpers on
numpy-quaternion), :mod:`engine.utils.settings` (``default_sim_settings``, ``make_cfg``),
:mod:`engine.utils.viz_utils` (Habitat's ``viz_utils``: videos from :mod:`render.video`,
``display_sample``, ``get_island_colored_map``) and :mod:`engine.utils.maps` (top-down maps,
``to_grid``, ``draw_path`` as in Habitat's navigation notebook). As in Habitat,
``quat_from_angle_axis`` and ``quat_rotate_vector`` are also importable from here.
Submodules load on first use, so ``import engine.utils`` stays light.

May import: ``engine.simulator`` and every folder below it (``settings`` builds
configurations), ``engine.demo``, ``render`` (videos) and ``navmesh``; nothing below the
simulator imports ``engine.utils``.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = [
    "collect_env",
    "common",
    "datasets_download",
    "manager_utils",
    "maps",
    "profiling_utils",
    "quat_from_angle_axis",
    "quat_rotate_vector",
    "quaternion_utils",
    "settings",
    "viz_utils",
]

_FROM_COMMON = ("quat_from_angle_axis", "quat_rotate_vector")


def __getattr__(name: str) -> Any:
    if name in _FROM_COMMON:
        return getattr(importlib.import_module("engine.utils.common"), name)
    if name in __all__:
        return importlib.import_module(f"engine.utils.{name}")
    raise AttributeError(f"module 'engine.utils' has no attribute {name!r}")
