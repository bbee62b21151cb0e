"""rigidsim.navmesh: a grid-based 2.5D multi-level navigation mesh with Habitat's PathFinder API.

A leaf library: it takes plain arrays (world frame, Y up, meters: ``vertices (V, 3) float64``,
``faces (F, 3) int64``) and never imports ``engine`` or ``render``.

Build pipeline (``navmesh.build.build_navmesh``, after Recast's ``handleBuild``):

1. grid: square ``cell_size`` cells over the XZ footprint of the mesh;
2. slope: triangles within ``agent_max_slope`` of horizontal are walkable;
3. rasterize: triangles are sampled into grid columns and merged into solid height spans;
4. filters: low hanging obstacles, ceilings lower than ``agent_height``;
5. layers: span tops become walkable surfaces, several per column (stairs, multi-floor);
6. ledges: surfaces next to drops deeper than ``agent_max_climb`` are removed;
7. connect: neighbouring surfaces within ``agent_max_climb`` are linked;
8. erode: the walkable area shrinks by ``agent_radius`` (chamfer distance transform);
9. islands: connected components; islands under ``region_min_size**2`` cells are dropped.

Queries (``PathFinder``): snapping and sampling, exact shortest paths (Dijkstra over the
visibility graph of the navmesh's reflex corners) and the per-goal distance field,
``try_step`` / ``try_step_no_sliding`` (Detour's moveAlongSurface contract), obstacle
distance, top-down maps, ``.navmesh`` save/load (an ``.npz`` archive, see
``navmesh.navmesh_data``). ``navmesh.topdown.plot_topdown`` draws the map with matplotlib.
"""

from navmesh.build import build_navmesh
from navmesh.navmesh_data import NavMeshData
from navmesh.pathfinder import PathFinder
from navmesh.records import HitRecord, MultiGoalShortestPath, ShortestPath
from navmesh.settings import NavMeshSettings

__all__ = [
    "HitRecord",
    "MultiGoalShortestPath",
    "NavMeshData",
    "NavMeshSettings",
    "PathFinder",
    "ShortestPath",
    "build_navmesh",
]
