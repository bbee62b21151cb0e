"""Habitat's ``habitat_sim.utils.viz_utils``, plus the plotting helpers of its navigation
notebook.

Videos come from :mod:`render.video` (``make_video``, ``observation_to_image``,
``depth_to_rgb``, ``semantic_to_rgb``, ``display_video``...). Added here:

* ``get_island_colored_map(island_view)``: an RGB ``PIL.Image`` of
  ``pathfinder.get_topdown_island_view(...)``, white where nothing is navigable, island ``i``
  colored ``d3_40_colors_rgb[i]`` (islands past 40 get seeded random colors);
* ``display_sample(rgb_obs, semantic_obs=None, depth_obs=None)``: the observations side by
  side with matplotlib;
* ``display_map(topdown_map, key_points=None)``: a map with points ``(col, row)`` marked;
* ``convert_points_to_topdown(pathfinder, points, meters_per_pixel)``: world points to map
  pixels ``(col, row)`` for plotting, as the notebook defines it;
* ``get_fast_video_writer(video_file, fps)``: an imageio mp4 writer.
"""

from __future__ import annotations

from typing import Any

import imageio
import numpy as np
from PIL import Image

from engine.utils.colors import d3_40_colors_rgb
from render.video import (  # noqa: F401  (re-exported: Habitat's viz_utils names)
    border_frames_from_overlay,
    depth_to_rgb,
    display_video,
    is_notebook,
    make_video,
    make_video_frame,
    observation_to_image,
    semantic_to_rgb,
)

__all__ = [
    "border_frames_from_overlay",
    "convert_points_to_topdown",
    "depth_to_rgb",
    "display_map",
    "display_sample",
    "display_video",
    "get_fast_video_writer",
    "get_island_colored_map",
    "is_notebook",
    "make_video",
    "make_video_frame",
    "observation_to_image",
    "semantic_to_rgb",
]


def get_island_colored_map(island_top_down_map_data: np.ndarray) -> Image.Image:
    """RGB image of an island index map (-1 = not navigable -> white), laid out as Habitat's.

    Habitat writes map cell ``[x, y]`` to image pixel ``(x, -y)``: the image is
    ``shape[0]`` wide and ``shape[1]`` tall, image row ``j`` shows map column ``-j mod H``
    (column 0 at the top, then the last column upwards). Islands beyond the 40 fixed colors
    get seeded random colors (deterministic, where Habitat's vary per run).
    """
    islands = np.asarray(island_top_down_map_data)
    if islands.ndim != 2:
        raise ValueError(f"island map must be 2D, got shape {islands.shape}")
    # image[j, i] = map[i, (-j) mod H]: Habitat's pixels[x, -y] with PIL's negative wrap
    islands = islands.T[(-np.arange(islands.shape[1])) % islands.shape[1]]
    n_islands = int(islands.max(initial=-1)) + 1
    extra = np.random.default_rng(0).integers(0, 256, size=(max(0, n_islands - 40), 3))
    palette = np.concatenate([d3_40_colors_rgb[:n_islands], extra.astype(np.uint8)])
    rgb = np.full(islands.shape + (3,), 255, np.uint8)
    on_island = islands >= 0
    rgb[on_island] = palette[islands[on_island]]  # island index -> its color
    return Image.fromarray(rgb, "RGB")


def get_fast_video_writer(video_file: str, fps: int = 60):
    """An imageio mp4 writer (``append_data(frame)``, ``close()``), as Habitat's helper.

    Frames must be ``(H, W, 3) uint8`` with even sizes for H.264.
    """
    return imageio.get_writer(video_file, fps=fps, quality=5, format="FFMPEG", macro_block_size=1)


def convert_points_to_topdown(
    pathfinder: Any, points: list, meters_per_pixel: float
) -> list[np.ndarray]:
    """Map pixels ``(col, row)`` of world points: ``((x - x_min) / mpp, (z - z_min) / mpp)``."""
    lower = np.asarray(pathfinder.get_bounds()[0], dtype=np.float64)
    return [
        np.array([(p[0] - lower[0]) / meters_per_pixel, (p[2] - lower[2]) / meters_per_pixel])
        for p in (np.asarray(q, dtype=np.float64) for q in points)
    ]


def display_sample(
    rgb_obs: np.ndarray,
    semantic_obs: np.ndarray | None = None,
    depth_obs: np.ndarray | None = None,
    show: bool = True,
):
    """Show color (and semantic, depth) observations side by side; returns the figure."""
    import matplotlib.pyplot as plt

    images = [
        (
            "rgb",
            Image.fromarray(np.asarray(rgb_obs), "RGBA" if np.shape(rgb_obs)[-1] == 4 else "RGB"),
        )
    ]
    if semantic_obs is not None and np.size(semantic_obs):
        images.append(("semantic", semantic_to_rgb(np.asarray(semantic_obs))))
    if depth_obs is not None and np.size(depth_obs):
        depth = np.asarray(depth_obs, dtype=np.float64)
        scale = depth.max() if depth.max() > 0 else 1.0
        images.append(("depth", Image.fromarray((depth / scale * 255).astype(np.uint8), "L")))
    figure = plt.figure(figsize=(12, 8))
    for i, (title, image) in enumerate(images):
        axes = figure.add_subplot(1, len(images), i + 1)
        axes.axis("off")
        axes.set_title(title)
        axes.imshow(image, cmap="gray" if title == "depth" else None)
    if show:
        plt.show()
    return figure


def display_map(topdown_map: np.ndarray, key_points: list | None = None, show: bool = True):
    """Show a top-down map with optional key points ``(col, row)``; returns the figure."""
    import matplotlib.pyplot as plt

    figure = plt.figure(figsize=(12, 8))
    axes = figure.add_subplot(1, 1, 1)
    axes.axis("off")
    axes.imshow(topdown_map)
    for point in key_points or []:
        axes.plot(point[0], point[1], marker="o", markersize=10, alpha=0.8)
    if show:
        plt.show()
    return figure
