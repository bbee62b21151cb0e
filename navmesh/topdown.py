"""plot_topdown: a matplotlib top-down map of a navmesh, islands coloured, with paths and agents.

The map is drawn in world XZ coordinates seen from above (looking down -Y): +X to the
right, +Z downward, like Habitat's top-down maps (rows follow +Z). Per cell it shows the
island of the chosen surface layer (a colour per island), walkable-but-not-navigable cells
(eroded by the agent radius, removed ledges or dropped islands) in light grey and cells with
no walkable surface (walls, furniture, void) in dark grey.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from navmesh.navmesh_data import NavMeshData

_VOID_RGB = (0.25, 0.25, 0.28)  # no walkable surface: obstacle or hole
_ERODED_RGB = (0.75, 0.75, 0.75)  # walkable surface the agent cannot stand on


def topdown_rgb(data: NavMeshData, height: float | None = None, eps: float = 0.5) -> np.ndarray:
    """Return an ``(nz, nx, 3)`` float RGB image of the navmesh, one pixel per cell.

    ``height`` picks, per cell, the surface closest to it within ``eps`` meters (multi-floor
    scenes); None shows the highest navigable surface.
    """
    floor = data.floor
    if height is None:
        score = np.where(data.navigable, floor, -np.inf)  # prefer the highest navigable layer
        layer = np.argmax(score, axis=0)
    else:
        score = np.where(np.abs(floor - height) <= eps, -np.abs(floor - height), -np.inf)
        layer = np.argmax(score, axis=0)
    island = np.take_along_axis(data.island, layer[None], axis=0)[0]
    has_surface = np.any(~np.isnan(floor), axis=0)
    n_islands = int(data.island.max(initial=-1)) + 1
    colors = plt.get_cmap("tab10" if n_islands <= 10 else "tab20")
    rgb = np.empty(island.shape + (3,))
    rgb[:] = _VOID_RGB
    rgb[has_surface] = _ERODED_RGB
    on_island = island >= 0
    rgb[on_island] = np.asarray(colors(island[on_island] % colors.N))[:, :3]
    return rgb


def plot_topdown(
    data: NavMeshData,
    ax=None,
    path_points=None,
    agent_positions=None,
    height: float | None = None,
    title: str | None = None,
):
    """Draw the navmesh seen from above and return the matplotlib Axes.

    Parameters
    ----------
    data : NavMeshData
        The navmesh (``PathFinder.navmesh_data``).
    ax : matplotlib Axes, optional
        Where to draw; a new figure is made when None.
    path_points : (K, 3) array-like, optional
        World waypoints drawn as a polyline (e.g. ``ShortestPath.points``).
    agent_positions : (A, 3) array-like, optional
        World positions drawn as markers.
    height : float, optional
        Surface height to show on multi-floor scenes (see ``topdown_rgb``).
    title : str, optional
        Axes title.
    """
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 6))
    nz, nx = data.floor.shape[1:]
    x0, z0 = data.origin_xz
    extent = (x0, x0 + nx * data.cell_size, z0 + nz * data.cell_size, z0)
    ax.imshow(topdown_rgb(data, height), extent=extent, interpolation="nearest")
    n_islands = int(data.island.max(initial=-1)) + 1
    colors = plt.get_cmap("tab10" if n_islands <= 10 else "tab20")
    for k in range(min(n_islands, colors.N)):
        ax.plot([], [], "s", color=colors(k), label=f"island {k}")
    if path_points is not None and len(path_points) > 0:
        pts = np.asarray(path_points, dtype=float).reshape(-1, 3)
        ax.plot(pts[:, 0], pts[:, 2], "-o", color="crimson", lw=2, ms=3, label="path")
    if agent_positions is not None and len(agent_positions) > 0:
        pos = np.asarray(agent_positions, dtype=float).reshape(-1, 3)
        ax.plot(pos[:, 0], pos[:, 2], "^", color="black", mfc="yellow", ms=9, label="agent")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.set_aspect("equal")
    ax.legend(loc="upper right", fontsize="small", framealpha=0.8)
    if title:
        ax.set_title(title)
    return ax
