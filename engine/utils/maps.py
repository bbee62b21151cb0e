"""Top-down maps as Habitat's navigation notebook draws them (habitat-lab's ``maps`` helpers).

A top-down map is the navmesh seen from above at one height, ``meters_per_pixel`` per pixel:
pixel ``(row, col)`` is the world point ``(x_min + col * mpp, height, z_min + row * mpp)``
(rows follow +Z, columns +X), ``x_min, z_min`` from ``pathfinder.get_bounds()``.

* ``get_topdown_map(pathfinder, height, meters_per_pixel)``: ``uint8`` map, 0 not navigable,
  1 navigable, 2 the border of the navigable area (navigable pixels next to a non-navigable
  one);
* ``colorize_topdown_map(map)``: RGB (grey 150 outside, white inside, dark grey 50 border);
* ``to_grid(z, x, grid_dimensions, pathfinder)`` / ``from_grid``: world <-> pixel;
* ``draw_path(image, points, color, thickness)``: a polyline through pixel points
  ``(row, col)``; ``draw_agent(image, center, rotation, radius_px)``: a disc with a heading.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from PIL import Image, ImageDraw

__all__ = [
    "MAP_BORDER_INDICATOR",
    "MAP_INVALID_POINT",
    "MAP_VALID_POINT",
    "colorize_topdown_map",
    "draw_agent",
    "draw_path",
    "from_grid",
    "get_topdown_map",
    "to_grid",
]

MAP_INVALID_POINT = 0
MAP_VALID_POINT = 1
MAP_BORDER_INDICATOR = 2
TOP_DOWN_MAP_COLORS = np.array([[150, 150, 150], [255, 255, 255], [50, 50, 50]], np.uint8)


def get_topdown_map(pathfinder: Any, height: float, meters_per_pixel: float = 0.05) -> np.ndarray:
    """``uint8`` map of the navmesh at ``height``: 0 outside, 1 navigable, 2 border."""
    navigable = np.asarray(pathfinder.get_topdown_view(meters_per_pixel, height), dtype=bool)
    topdown = navigable.astype(np.uint8)
    padded = np.pad(navigable, 1, constant_values=False)
    # a navigable pixel with a non-navigable 4-neighbour is on the border
    inner = padded[:-2, 1:-1] & padded[2:, 1:-1] & padded[1:-1, :-2] & padded[1:-1, 2:]
    topdown[navigable & ~inner] = MAP_BORDER_INDICATOR
    return topdown


def colorize_topdown_map(topdown_map: np.ndarray) -> np.ndarray:
    """``(H, W, 3) uint8`` colors of a map made by :func:`get_topdown_map`."""
    return TOP_DOWN_MAP_COLORS[np.clip(topdown_map, 0, 2)]


def to_grid(
    realworld_x: float, realworld_y: float, grid_resolution: tuple[int, int], pathfinder: Any
) -> tuple[int, int]:
    """Pixel ``(row, col)`` of the world point ``x = realworld_y``, ``z = realworld_x``
    on a map of ``grid_resolution = (rows, cols)`` covering the navmesh bounds (habitat-lab's
    argument order: ``to_grid(z, x, ...)``)."""
    lower, upper = pathfinder.get_bounds()
    cell_z = abs(upper[2] - lower[2]) / grid_resolution[0]
    cell_x = abs(upper[0] - lower[0]) / grid_resolution[1]
    return int((realworld_x - lower[2]) / cell_z), int((realworld_y - lower[0]) / cell_x)


def from_grid(
    grid_x: int, grid_y: int, grid_resolution: tuple[int, int], pathfinder: Any
) -> tuple[float, float]:
    """World ``(z, x)`` of pixel ``(row, col)``: the inverse of :func:`to_grid`."""
    lower, upper = pathfinder.get_bounds()
    cell_z = abs(upper[2] - lower[2]) / grid_resolution[0]
    cell_x = abs(upper[0] - lower[0]) / grid_resolution[1]
    return lower[2] + grid_x * cell_z, lower[0] + grid_y * cell_x


def _draw_on(image: np.ndarray, draw: Any) -> None:
    """Run ``draw(ImageDraw, fill)`` on ``image`` in place (2D label map or RGB image)."""
    pil = Image.fromarray(image)
    draw(ImageDraw.Draw(pil))
    image[...] = np.asarray(pil)


def draw_path(
    top_down_map: np.ndarray, path_points: list, color: Any = 10, thickness: int = 2
) -> None:
    """Draw a polyline through pixel points ``(row, col)`` on the map, in place."""
    xy = [(float(p[1]), float(p[0])) for p in path_points]  # PIL wants (x=col, y=row)
    fill = tuple(int(c) for c in color) if np.ndim(color) else int(color)
    if len(xy) >= 2:
        _draw_on(top_down_map, lambda d: d.line(xy, fill=fill, width=int(thickness)))


def draw_agent(
    image: np.ndarray,
    agent_center_coord: tuple,
    agent_rotation: float,
    agent_radius_px: int = 5,
    color: tuple = (0, 0, 255),
) -> None:
    """A disc at pixel ``(row, col)`` with a line along the heading ``agent_rotation``
    (radians, 0 looking up the map = -Z), drawn in place on an RGB image."""
    row, col = (float(v) for v in agent_center_coord)
    r = float(agent_radius_px)
    tip = (col - r * np.sin(agent_rotation), row - r * np.cos(agent_rotation))

    def draw(d: Any) -> None:
        d.ellipse([col - r, row - r, col + r, row + r], fill=tuple(color))
        d.line([(col, row), tip], fill=(255, 255, 255), width=max(1, int(r) // 3))

    _draw_on(image, draw)
