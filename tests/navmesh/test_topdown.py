"""Top-down plot and the leaf-library import rule."""

from __future__ import annotations

import ast
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")

from navmesh.topdown import plot_topdown, topdown_rgb  # noqa: E402

NAVMESH_DIR = Path(__file__).resolve().parents[2] / "navmesh"


def test_topdown_rgb_colours_islands_eroded_cells_and_void(geometry):
    pf = geometry.build(
        geometry.box((0, -0.1, 0), (3, 0, 3)), geometry.box((5, -0.1, 0), (8, 0, 3))
    )
    data = pf.navmesh_data
    rgb = topdown_rgb(data)
    assert rgb.shape == data.floor.shape[1:] + (3,)
    x_cell = lambda x: int((x - data.origin_xz[0]) / data.cell_size)  # noqa: E731
    z_mid = int((1.5 - data.origin_xz[1]) / data.cell_size)
    island_0, island_1 = rgb[z_mid, x_cell(1.5)], rgb[z_mid, x_cell(6.5)]
    gap, edge = rgb[z_mid, x_cell(4.0)], rgb[z_mid, x_cell(0.01)]
    assert not np.allclose(island_0, island_1)  # one colour per island
    np.testing.assert_allclose(gap, (0.25, 0.25, 0.28))  # no surface
    np.testing.assert_allclose(edge, (0.75, 0.75, 0.75))  # surface eroded by the radius


def test_plot_topdown_draws_path_and_agents(geometry):
    pf = geometry.build(geometry.box((0, -0.1, 0), (4, 0, 4)))
    path = [[0.5, 0, 0.5], [3.5, 0, 3.5]]
    ax = plot_topdown(pf.navmesh_data, path_points=path, agent_positions=[[1, 0, 1]])
    lines = {line.get_label(): line for line in ax.get_lines()}
    np.testing.assert_allclose(lines["path"].get_xdata(), [0.5, 3.5])
    np.testing.assert_allclose(lines["path"].get_ydata(), [0.5, 3.5])  # z on the vertical
    assert "agent" in lines and "island 0" in lines
    matplotlib.pyplot.close(ax.figure)


def test_navmesh_never_imports_engine_or_render():
    sources = sorted(NAVMESH_DIR.glob("*.py"))
    assert len(sources) >= 8 and NAVMESH_DIR / "pathfinder.py" in sources  # the glob found them
    for source in sources:
        tree = ast.parse(source.read_text())
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module]
            for name in names:
                assert name.split(".")[0] not in {"engine", "render"}, f"{source}: {name}"
