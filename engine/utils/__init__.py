"""Helpers a Habitat user finds under ``habitat_sim.utils``.

:mod:`engine.utils.common` (quaternions, ``d3_40_colors_rgb``, ``colorize_ids``),
:mod:`engine.utils.settings` (``default_sim_settings``, ``make_cfg``),
:mod:`engine.utils.viz_utils` (Habitat's ``viz_utils``: videos from :mod:`render.video`,
``display_sample``, ``get_island_colored_map``) and :mod:`engine.utils.maps` (top-down maps,
``to_grid``, ``draw_path`` as in Habitat's navigation notebook).
Submodules load on first use, so ``import engine.utils`` stays light.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["common", "maps", "settings", "viz_utils"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        return importlib.import_module(f"engine.utils.{name}")
    raise AttributeError(f"module 'engine.utils' has no attribute {name!r}")
