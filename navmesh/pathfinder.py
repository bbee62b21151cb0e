"""PathFinder: Habitat-sim's navmesh query API over rigidsim's layered grid navmesh.

Names, defaults and return conventions follow ``habitat_sim.nav.PathFinder``
(``src/esp/nav/PathFinder.cpp``): points in, points out, ``snap_point`` returns a NaN vector
when nothing is near, ``find_path`` fills ``points`` / ``geodesic_distance`` (inf and False
when unreachable), ``try_step`` slides along walls. rigidsim additions: ``build(vertices,
faces, settings)`` (Habitat builds through ``Simulator.recompute_navmesh``), ``navmesh_data``
(the arrays, for plotting), and clear exceptions for bad input.

This module is the API surface; the work is done by concept elsewhere: ``navmesh.records``
(query records, point checks), ``navmesh.path_query`` (find_path's search),
``navmesh.step_filter`` (try_step), ``navmesh.proximity`` (walls, islands, disks),
``navmesh.geodesic_field`` (distances to one goal), ``navmesh.polygons`` (mesh export) and
``navmesh.maps`` (top-down views).

World frame: Y up, -Z forward, meters. Every position returned is a plain ``(3,) float64``
``np.ndarray``; every position accepted may be any 3-sequence (list, tuple, ndarray,
magnum-like Vector3).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from navmesh.build import build_navmesh
from navmesh.geodesic_field import GeodesicField
from navmesh.maps import check_topdown_arguments, topdown_island_view
from navmesh.navmesh_data import NavMeshData
from navmesh.path_query import best_path, path_length
from navmesh.polygons import navmesh_polygons
from navmesh.proximity import (
    closest_boundary_point,
    has_wall_within,
    island_radii,
    nodes_in_disk,
)
from navmesh.query import NavGrid
from navmesh.records import HitRecord, MultiGoalShortestPath, ShortestPath, as_point, nan3
from navmesh.settings import NAVIGABLE_XZ_TOLERANCE, NavMeshSettings
from navmesh.step_filter import try_step
from navmesh.visibility import CornerGraph

__all__ = ["HitRecord", "MultiGoalShortestPath", "PathFinder", "ShortestPath", "as_point"]

_NOT_LOADED = "PathFinder is not loaded: build() or load_nav_mesh() first"


class PathFinder:
    """Loads or builds a navmesh and answers sampling, path, step and island queries."""

    def __init__(self) -> None:
        self._data: NavMeshData | None = None
        self._grid: NavGrid | None = None
        self._corners: CornerGraph | None = None
        self._island_radius: np.ndarray | None = None
        self._rng = np.random.default_rng(0)

    # -- building, loading, saving -----------------------------------------------------------
    def build(
        self, vertices: ArrayLike, faces: ArrayLike, settings: NavMeshSettings | None = None
    ) -> bool:
        """Build the navmesh of a world-frame triangle mesh (rigidsim addition).

        ``vertices (V, 3) float64`` meters, Y up; ``faces (F, 3) int64``. Returns True on
        success (the previous navmesh is replaced); raises ValueError/TypeError for bad input
        and leaves the current navmesh unchanged.
        """
        settings = NavMeshSettings() if settings is None else settings
        if not isinstance(settings, NavMeshSettings):
            raise TypeError(f"settings must be a NavMeshSettings, got {type(settings)}")
        self._install(build_navmesh(vertices, faces, settings))
        return True

    def load_nav_mesh(self, path: str | Path) -> bool:
        """Load a file written by ``save_nav_mesh``.

        As Habitat, a bad file (empty, truncated, not a navmesh, inconsistent arrays, over
        the size budget; see ``NavMeshData.load``) returns False with a warning and the
        navmesh loaded before stays in use. Raises FileNotFoundError when ``path`` does not
        exist (rigidsim's addition: Habitat only logs it).
        """
        try:
            data = NavMeshData.load(path)
            grid = NavGrid(data)
        except FileNotFoundError:
            raise
        except (ValueError, KeyError, TypeError, OSError, EOFError) as err:
            warnings.warn(f"load_nav_mesh: {err}; the previous navmesh is kept", stacklevel=2)
            return False
        self._data, self._grid = data, grid
        self._island_radius, self._corners = None, None
        return True

    def save_nav_mesh(self, path: str | Path) -> bool:
        """Write the navmesh to ``path`` (format in ``navmesh.navmesh_data``); False if empty."""
        if self._data is None:
            return False
        self._data.save(path)
        return True

    def _install(self, data: NavMeshData) -> None:
        self._data, self._grid = data, NavGrid(data)
        self._island_radius, self._corners = None, None

    @property
    def is_loaded(self) -> bool:
        """True once a navmesh was built or loaded."""
        return self._data is not None

    @property
    def navmesh_data(self) -> NavMeshData:
        """The layered grid arrays (for plots and notebooks)."""
        return self._require()

    @property
    def nav_mesh_settings(self) -> NavMeshSettings | None:
        """A copy of the settings the current navmesh was built with; None when not loaded
        (as Habitat)."""
        if self._data is None:
            return None
        return NavMeshSettings(**vars(self._data.settings))

    @property
    def nav_grid(self) -> NavGrid:
        """The query structure of the loaded navmesh, for batch queries (rigidsim addition:
        ``navmesh.step_filter``, ``navmesh.proximity`` and ``navmesh.geodesic_field`` take it)."""
        return self._require_grid()

    def _require(self) -> NavMeshData:
        if self._data is None:
            raise RuntimeError(_NOT_LOADED)
        return self._data

    def _require_grid(self) -> NavGrid:
        """The query grid of the loaded navmesh (set together with ``_data``)."""
        if self._grid is None:
            raise RuntimeError(_NOT_LOADED)
        return self._grid

    # -- global properties -------------------------------------------------------------------
    def get_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(min (3,), max (3,)) world AABB of the mesh the navmesh was built from, meters."""
        bounds = self._require().bounds
        return bounds[0].copy(), bounds[1].copy()

    @property
    def num_islands(self) -> int:
        """Number of connected navigable components."""
        return self._require_grid().n_islands

    @property
    def navigable_area(self) -> float:
        """Total navigable area projected on XZ, square meters."""
        return self.island_area(-1)

    def island_area(self, island_index: int = -1) -> float:
        """Navigable XZ area of one island (all islands for -1), square meters."""
        grid = self._require_grid()
        self._check_island(island_index)
        mask = grid.island >= 0 if island_index < 0 else grid.island == island_index
        return float(np.count_nonzero(mask)) * grid.cell_size**2

    def _check_island(self, island_index: object) -> None:
        if isinstance(island_index, bool) or not isinstance(island_index, (int, np.integer)):
            raise TypeError(f"island_index must be an int, got {island_index!r}")
        n_islands = self._require_grid().n_islands
        if not -1 <= island_index < n_islands:
            raise ValueError(f"island_index {island_index} out of range [-1, {n_islands})")

    # -- points ------------------------------------------------------------------------------
    def seed(self, new_seed: int) -> None:
        """Seed the random point sampler (same seed -> same sequence of points)."""
        if isinstance(new_seed, bool) or not isinstance(new_seed, (int, np.integer)):
            raise TypeError(f"seed must be an int, got {new_seed!r}")
        self._rng = np.random.default_rng(int(new_seed) & 0xFFFFFFFF)

    def snap_point(self, point: ArrayLike, island_index: int = -1) -> np.ndarray:
        """Closest navigable point (Detour's findNearestPoly box: 2 m, 4 m, 2 m); NaN if none."""
        p = as_point(point, "point")
        grid = self._require_grid()
        self._check_island(island_index)
        _, snapped = grid.nearest_node(p, island_index)
        return snapped if snapped is not None else nan3()

    def is_navigable(self, pt: ArrayLike, max_y_delta: float = 0.5) -> bool:
        """True when ``pt`` snaps onto the navmesh with no XZ motion (<= 1 cm) and at most
        ``max_y_delta`` meters vertically."""
        p = as_point(pt, "pt")
        _, snapped = self._require_grid().nearest_node(p)
        if snapped is None:  # nothing within the snap box
            return False
        horizontal = math.hypot(snapped[0] - p[0], snapped[2] - p[2])
        return abs(snapped[1] - p[1]) <= max_y_delta and horizontal <= NAVIGABLE_XZ_TOLERANCE

    def get_island(self, pt: ArrayLike) -> int:
        """Island index of the navmesh point nearest ``pt``, -1 when nothing is near."""
        p = as_point(pt, "pt")
        grid = self._require_grid()
        node, _ = grid.nearest_node(p)
        return int(grid.island[node]) if node >= 0 else -1

    def island_radius(self, pt: ArrayLike | int) -> float:
        """Largest distance of the island's cell centres from their centroid (Habitat's
        island radius), meters.

        ``pt`` is a point (the island nearest it; 0 when nothing is near) or, as in
        Habitat's newer API, an island index (``int``).
        """
        if isinstance(pt, (int, np.integer)) and not isinstance(pt, bool):
            n_islands = self._require_grid().n_islands
            if not 0 <= pt < n_islands:
                raise ValueError(f"island_index {pt} out of range [0, {n_islands})")
            island = int(pt)
        else:
            island = self.get_island(pt)
        if island < 0:
            return 0.0
        if self._island_radius is None:
            self._island_radius = island_radii(self._require_grid())
        return float(self._island_radius[island])

    def get_random_navigable_point(self, max_tries: int = 10, island_index: int = -1) -> np.ndarray:
        """Uniformly distributed (by XZ area) navigable point, optionally on one island.

        Sampling a node then a point in its square cannot fail, so ``max_tries`` (kept for
        Habitat's signature) is only validated. Raises RuntimeError when nothing is navigable.
        """
        if int(max_tries) < 1:
            raise ValueError(f"max_tries must be >= 1, got {max_tries!r}")
        grid = self._require_grid()
        self._check_island(island_index)
        mask = grid.island >= 0 if island_index < 0 else grid.island == island_index
        nodes = np.flatnonzero(mask)
        if nodes.size == 0:
            raise RuntimeError("NavMesh has no navigable area to sample from")
        return self._sample_in(nodes)

    def get_random_navigable_point_near(
        self, circle_center: ArrayLike, radius: float, max_tries: int = 100, island_index: int = -1
    ) -> np.ndarray:
        """Random navigable point within ``radius`` (3D) of ``circle_center`` on the island
        nearest the centre (or ``island_index``); NaN vector after ``max_tries`` failures."""
        center = as_point(circle_center, "circle_center")
        if not (isinstance(radius, (int, float)) and math.isfinite(radius) and radius > 0):
            raise ValueError(f"radius must be a finite number > 0, got {radius!r}")
        grid = self._require_grid()
        self._check_island(island_index)
        node, _ = grid.nearest_node(center, island_index)
        if node < 0:
            return nan3()
        # no navmesh is 1e30 m wide: a larger radius selects the same squares, no overflow
        nodes = nodes_in_disk(grid, center, min(float(radius), 1e30), int(grid.island[node]))
        for _ in range(max(1, int(max_tries))):
            point = self._sample_in(nodes)
            if np.linalg.norm(point - center) < radius:
                return point
        return nan3()

    def _sample_in(self, nodes: np.ndarray) -> np.ndarray:
        """Pick a node uniformly, then a uniform point inside its square."""
        grid = self._require_grid()
        node = int(nodes[self._rng.integers(nodes.size)])
        u, v = self._rng.random(2)
        ix, iz = grid.node_cell(node)
        x, z = grid.clamp_into_cell(
            node, grid.x0 + (ix + u) * grid.cell_size, grid.z0 + (iz + v) * grid.cell_size
        )
        return np.array([x, grid.floor[node], z])

    # -- paths -------------------------------------------------------------------------------
    def find_path(self, path: ShortestPath | MultiGoalShortestPath) -> bool:
        """Fill ``path.points`` and ``path.geodesic_distance``; True when a path exists.

        ``path`` is a ``ShortestPath`` or a ``MultiGoalShortestPath`` (which also gets
        ``closest_end_point_index``). Unreachable: ``points == []``, distance inf, False.
        """
        if isinstance(path, ShortestPath):
            ends = [as_point(path.requested_end, "requested_end")]
        elif isinstance(path, MultiGoalShortestPath):
            ends = [as_point(e, "requested_ends") for e in path.requested_ends]
        else:
            raise TypeError(f"path must be a ShortestPath or MultiGoalShortestPath, got {path!r}")
        start = as_point(path.requested_start, "requested_start")
        self._require()
        path.points, path.geodesic_distance = [], math.inf
        index, points = best_path(self._require_grid(), self._corner_graph(), start, ends)
        if isinstance(path, MultiGoalShortestPath):
            path.closest_end_point_index = index
        if index < 0:
            return False
        path.points, path.geodesic_distance = points, path_length(points)
        return True

    def geodesic_field(self, goal: ArrayLike) -> GeodesicField:
        """Geodesic distances to ``goal`` from everywhere, from one search from the goal.

        ``field.distance(point)`` is ``find_path``'s geodesic distance from ``point`` (the same
        search over the visibility graph, see ``navmesh.geodesic_field``), answered without a
        new search; a greedy follower asks it once per candidate action.
        """
        return GeodesicField(self._require_grid(), self._corner_graph(), as_point(goal, "goal"))

    def _corner_graph(self) -> CornerGraph:
        """The navmesh's reflex corners and their visibility rows, built on first use."""
        if self._corners is None:
            self._corners = CornerGraph(self._require_grid())
        return self._corners

    # -- stepping ----------------------------------------------------------------------------
    def try_step(self, start: ArrayLike, end: ArrayLike) -> np.ndarray:
        """Move from ``start`` toward ``end``, sliding along walls (see ``step_filter``)."""
        grid = self._require_grid()
        return try_step(grid, as_point(start, "start"), as_point(end, "end"), True)

    def try_step_no_sliding(self, start: ArrayLike, end: ArrayLike) -> np.ndarray:
        """Move from ``start`` toward ``end``, stopping at the first wall (direction kept)."""
        grid = self._require_grid()
        return try_step(grid, as_point(start, "start"), as_point(end, "end"), False)

    # -- obstacles ---------------------------------------------------------------------------
    def distance_to_closest_obstacle(self, pt: ArrayLike, max_search_radius: float = 2.0) -> float:
        """Distance from the snapped ``pt`` to the navmesh boundary, capped at the radius."""
        return self.closest_obstacle_surface_point(pt, max_search_radius).hit_dist

    def is_near_obstacle(self, pt: ArrayLike, distance: float) -> bool:
        """Whether the navmesh boundary lies closer than ``distance`` to the snapped ``pt``
        (rigidsim addition: ``distance_to_closest_obstacle(pt, r) < distance`` for any
        ``r >= distance``, stopping at the first wall found). Off the mesh: False, as that
        distance is inf there."""
        p = as_point(pt, "pt")
        if not (isinstance(distance, (int, float)) and distance > 0):
            raise ValueError(f"distance must be > 0, got {distance!r}")
        grid = self._require_grid()
        node, snapped = grid.nearest_node(p)
        if snapped is None:  # off the mesh
            return False
        return has_wall_within(grid, node, snapped, float(distance))

    def closest_obstacle_surface_point(
        self, pt: ArrayLike, max_search_radius: float = 2.0
    ) -> HitRecord:
        """Closest boundary point within ``max_search_radius`` of the snapped ``pt``.

        Off the mesh: ``hit_dist`` inf (positions zero), as Habitat. No wall in range:
        ``hit_dist == max_search_radius`` and NaN ``hit_pos`` / ``hit_normal``.
        """
        p = as_point(pt, "pt")
        if not (isinstance(max_search_radius, (int, float)) and max_search_radius > 0):
            raise ValueError(f"max_search_radius must be > 0, got {max_search_radius!r}")
        grid = self._require_grid()
        node, snapped = grid.nearest_node(p)
        if snapped is None:  # off the navmesh (node == -1)
            return HitRecord(np.zeros(3), np.zeros(3), math.inf)
        hit = closest_boundary_point(grid, node, snapped, float(max_search_radius))
        if hit is None:
            return HitRecord(nan3(), nan3(), float(max_search_radius))
        hit_pos, hit_normal, hit_dist = hit
        return HitRecord(hit_pos, hit_normal, hit_dist)

    # -- mesh export -------------------------------------------------------------------------
    def build_navmesh_vertices(self, island_index: int = -1) -> list[np.ndarray]:
        """Vertices of the navmesh surface as a triangle mesh (Habitat's name), meters.

        The navigable squares of the island (``island_index`` -1: every island) merged into
        rectangles of equal height, 4 corners each (``navmesh.polygons``); use with
        :meth:`build_navmesh_vertex_indices` (2 triangles per rectangle, +Y normals).
        """
        return list(self._polygons(island_index)[0])

    def build_navmesh_vertex_indices(self, island_index: int = -1) -> list[int]:
        """Triangle indices into :meth:`build_navmesh_vertices`, counter-clockwise seen from
        above (+Y normals)."""
        return self._polygons(island_index)[1].tolist()

    def _polygons(self, island_index: int) -> tuple[np.ndarray, np.ndarray]:
        self._check_island(island_index)
        return navmesh_polygons(self._require_grid(), island_index)

    # -- maps --------------------------------------------------------------------------------
    def get_topdown_view(
        self, meters_per_pixel: float, height: float, eps: float = 0.5
    ) -> np.ndarray:
        """Boolean map ``(int(zspan / mpp), int(xspan / mpp))``: pixel (h, w) is the point
        ``(x_min + w * mpp, height, z_min + h * mpp)`` and is True when a navigable surface
        lies within ``eps`` meters of ``height`` there."""
        return self.get_topdown_island_view(meters_per_pixel, height, eps) >= 0

    def get_topdown_island_view(
        self, meters_per_pixel: float, height: float, eps: float = 0.5
    ) -> np.ndarray:
        """Like ``get_topdown_view`` but ``int32`` island indices, -1 where not navigable."""
        check_topdown_arguments(meters_per_pixel, height, eps)
        data = self._require()
        return topdown_island_view(self._require_grid(), data.bounds, meters_per_pixel, height, eps)
