"""Magnum's image names: ``PixelFormat``, ``PixelStorage`` and ``MutableImageView2D``.

Magnum describes an image by its pixel format (``PixelFormat.RGBA8_UNORM`` for 8-bit RGBA,
``PixelFormat.R32F`` for one float channel, the formats of color and depth observations), its
row layout (``PixelStorage``: alignment, row length, skip) and wraps memory as an image view
(``MutableImageView2D``), which habitat-lab's batch renderer hands to the replay renderer to
draw into. rigidsim's observations are NumPy arrays (``(H, W, 4) uint8`` color,
``(H, W) float32`` depth) and it has no replay renderer, so:

- ``PixelFormat`` is a real enum with Magnum's member names (plain values);
- ``PixelStorage`` and ``MutableImageView2D`` are placeholders: annotations work,
  constructing raises ``NotImplementedError``.
"""

from __future__ import annotations

import enum

from engine.core.placeholder import Placeholder

__all__ = ["MutableImageView2D", "PixelFormat", "PixelStorage"]

_INSTEAD = "observations are NumPy arrays: sim.get_sensor_observations()[uuid]"


class PixelFormat(enum.Enum):
    """Magnum's generic pixel formats (the ones Habitat's sensors use, and their kin)."""

    R8_UNORM = enum.auto()
    RG8_UNORM = enum.auto()
    RGB8_UNORM = enum.auto()
    RGBA8_UNORM = enum.auto()
    R16_UNORM = enum.auto()
    R32UI = enum.auto()
    R32I = enum.auto()
    R32F = enum.auto()
    RG32F = enum.auto()
    RGB32F = enum.auto()
    RGBA32F = enum.auto()
    DEPTH32F = enum.auto()


class PixelStorage(Placeholder):
    """Placeholder of Magnum's pixel storage parameters (module docstring)."""

    habitat_name = "magnum.PixelStorage"
    missing = "Magnum image memory layouts are not used (no Magnum images)"
    instead = _INSTEAD


class MutableImageView2D(Placeholder):
    """Placeholder of Magnum's mutable 2D image view (module docstring)."""

    habitat_name = "magnum.MutableImageView2D"
    missing = "Magnum image views for the batch replay renderer to draw into are not used"
    instead = _INSTEAD
