"""Habitat's id colors: ``d3_40_colors_rgb`` and ``colorize_ids`` (``habitat_sim.utils.common``).

Id ``i`` is drawn with ``d3_40_colors_rgb[i % 40]`` (d3's category20 then category20b), the
palette the semantic video frames use (:data:`render.video.D3_40_COLORS_RGB`).
"""

from __future__ import annotations

import numpy as np

from render.video import D3_40_COLORS_RGB

__all__ = ["colorize_ids", "d3_40_colors_hex", "d3_40_colors_rgb"]

#: ``(40, 3) uint8`` palette
d3_40_colors_rgb: np.ndarray = D3_40_COLORS_RGB.copy()
#: the same colors as ``"0xrrggbb"`` strings (Habitat's ``d3_40_colors_hex``)
d3_40_colors_hex: list[str] = ["0x" + "".join(f"{c:02x}" for c in rgb) for rgb in d3_40_colors_rgb]


def colorize_ids(ids: np.ndarray) -> np.ndarray:
    """``(H, W, 3) uint8`` image of an ``(H, W)`` integer id map, id ``i >= 0`` colored
    ``d3_40_colors_rgb[i % 40]``, negative ids (nothing) black, as Habitat."""
    ids = np.asarray(ids)
    if ids.ndim != 2 or ids.dtype.kind not in "iu":
        raise ValueError(f"colorize_ids needs an (H, W) integer array, got {ids.dtype} {ids.shape}")
    colored = d3_40_colors_rgb[np.mod(ids, 40)]  # palette lookup per pixel
    colored[ids < 0] = 0
    return colored
