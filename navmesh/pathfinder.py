"""PathFinder: Habitat-sim's navmesh query API over rigidsim's layered grid navmesh.

Names, defaults and return conventions follow ``habitat_sim.nav.PathFinder``
(``src/esp/nav/PathFinder.cpp``): points in, points out, ``snap_point`` returns a NaN vector
when nothing is near, ``find_path`` fills ``points`` / ``geodesic_distance`` (inf and False
when unreachable), ``try_step`` slides along walls. rigidsim additions: ``build(vertices,
faces, settings)`` (Habitat builds through ``Simulator.recompute_navmesh``), ``navmesh_data``
(the arrays, for plotting), and clear exceptions for bad input.

World frame: Y up, -Z forward, meters. Every position returned is a plain ``(3,) float64``
``np.ndarray``; every position accepted may be any 3-sequence (list, tuple, ndarray,
magnum-like Vector3).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from navmesh.build import build_navmesh
from navmesh.geodesic_field import GeodesicField
from navmesh.navmesh_data import NavMeshData
from navmesh.polygons import navmesh_polygons
from navmesh.proximity import (
    closest_boundary_point,
    has_wall_within,
    island_radii,
    nodes_in_disk,
    topdown_islands,
)
from navmesh.query import NavGrid
from navmesh.search import GridGraph, path_length, pull_string
from navmesh.settings import (
    MAX_TOPDOWN_PIXELS,
    NAVIGABLE_XZ_TOLERANCE,
    NavMeshSettings,
    check_budget,
)
from navmesh.step_filter import try_step

_NOT_LOADED = "PathFinder is not loaded: build() or load_nav_mesh() first"


def _nan3() -> np.ndarray:
    return np.full(3, np.nan)


@dataclass
class ShortestPath:
    """Query and result of ``PathFinder.find_path`` between two points."""

    requested_start: np.ndarray = field(default_factory=lambda: np.zeros(3))
    requested_end: np.ndarray = field(default_factory=lambda: np.zeros(3))
    points: list = field(default_factory=list)  # list of (3,) float64 waypoints
    geodesic_distance: float = math.inf  # meters, inf when no path exists


@dataclass
class MultiGoalShortestPath:
    """Query and result of ``PathFinder.find_path`` to the closest of several ends."""

    requested_start: np.ndarray = field(default_factory=lambda: np.zeros(3))
    requested_ends: list = field(default_factory=list)  # list of (3,) points
    points: list = field(default_factory=list)
    geodesic_distance: float = math.inf
    closest_end_point_index: int = -1  # index into requested_ends of the chosen end


@dataclass
class HitRecord:
    """Closest obstacle: ``hit_pos`` (3,), ``hit_normal`` (3,) unit XZ vector from the wall
    toward the query point, ``hit_dist`` meters (``max_search_radius`` when none found).
    ``HitRecord()`` is a record of no hit (zero vectors, infinite distance)."""

    hit_pos: np.ndarray = field(default_factory=lambda: np.zeros(3))
    hit_normal: np.ndarray = field(default_factory=lambda: np.zeros(3))
    hit_dist: float = math.inf


def as_point(value: ArrayLike, name: str = "point") -> np.ndarray:
    """Return ``value`` as a finite ``(3,) float64`` array or raise naming ``name``."""
    if value is None:
        raise TypeError(f"{name} must be a 3-vector, got None")
    try:
        point = np.array(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError) as err:
        raise TypeError(f"{name} must be a 3-vector of numbers, got {value!r}") from err
    if point.shape != (3,):
        raise ValueError(f"{name} must have 3 components, got shape {point.shape}")
    if not np.all(np.isfinite(point)):
        raise ValueError(f"{name} must be finite, got {point.tolist()}")
    return point


class PathFinder:
    """Loads or builds a navmesh and answers sampling, path, step and island queries."""

    def __init__(self) -> None:
        self._data: NavMeshData | None = None
        self._grid: NavGrid | None = None
        self._graph: GridGraph | None = None
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
        self._graph, self._island_radius = None, None
        return True

    def save_nav_mesh(self, path: str | Path) -> bool:
        """Write the navmesh to ``path`` (format in ``navmesh.navmesh_data``); False if empty."""
        if self._data is None:
            return False
        self._data.save(path)
        return True

    def _install(self, data: NavMeshData) -> None:
        self._data, self._grid = data, NavGrid(data)
        self._graph, self._island_radius = None, None

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
        return snapped if snapped is not None else _nan3()

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
            return _nan3()
        # no navmesh is 1e30 m wide: a larger radius selects the same squares, no overflow
        nodes = nodes_in_disk(grid, center, min(float(radius), 1e30), int(grid.island[node]))
        for _ in range(max(1, int(max_tries))):
            point = self._sample_in(nodes)
            if np.linalg.norm(point - center) < radius:
                return point
        return _nan3()

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
        index, points = self._best_path(start, ends)
        if isinstance(path, MultiGoalShortestPath):
            path.closest_end_point_index = index
        if index < 0:
            return False
        path.points, path.geodesic_distance = points, path_length(points)
        return True

    def _best_path(self, start: np.ndarray, ends: list[np.ndarray]) -> tuple[int, list[np.ndarray]]:
        """(index of the closest reachable end, its waypoints) or (-1, [])."""
        grid = self._require_grid()
        start_node, start_pt = grid.nearest_node(start)
        if start_pt is None:  # start is off the navmesh (start_node == -1)
            return -1, []
        goals: list[tuple[int, int, np.ndarray]] = []  # (end index, node, snapped end)
        for k, end in enumerate(ends):
            node, pt = grid.nearest_node(end)
            if pt is not None and grid.island[node] == grid.island[start_node]:
                goals.append((k, node, pt))
        if not goals:
            return -1, []
        graph = self._grid_graph()
        # Habitat's multi-goal pruning: visit ends by straight-line distance (a lower bound of
        # the geodesic) and skip those that cannot beat the best path found so far.
        goals.sort(key=lambda goal: (float(np.linalg.norm(goal[2] - start_pt)), goal[0]))
        best: tuple[int, list[np.ndarray], float] = (-1, [], math.inf)
        for k, node, pt in goals:
            if np.linalg.norm(pt - start_pt) >= best[2]:
                continue
            points = self._single_path(graph, start_node, start_pt, node, pt)
            length = path_length(points)
            if length < best[2]:
                best = (k, points, length)
        return best[0], best[1]

    def _single_path(
        self,
        graph: GridGraph,
        start_node: int,
        start_pt: np.ndarray,
        end_node: int,
        end_pt: np.ndarray,
    ) -> list[np.ndarray]:
        """Waypoints from start_pt to end_pt (same island): straight when in line of sight,
        else Dijkstra on the grid graph then string pulling."""
        grid = self._require_grid()
        if np.allclose(start_pt, end_pt):
            return [start_pt.copy(), end_pt.copy()]
        if grid.line_of_sight(start_node, start_pt[[0, 2]], end_pt[[0, 2]], end_node):
            return [start_pt.copy(), end_pt.copy()]
        limit = 2.0 * float(np.linalg.norm(end_pt - start_pt)) + 1.0
        _, pred = graph.tree_from(start_node, [end_node], limit)
        nodes = graph.node_path(pred, start_node, end_node)
        return pull_string(grid, nodes, start_pt, end_pt)

    def _grid_graph(self) -> GridGraph:
        """The graph of navigable squares for Dijkstra, built on first use."""
        if self._graph is None:
            self._graph = GridGraph(self._require_grid())
        return self._graph

    def geodesic_field(self, goal: ArrayLike) -> GeodesicField:
        """Geodesic distances to ``goal`` from everywhere, from one Dijkstra search.

        ``field.distance(point)`` then answers in microseconds (see ``navmesh.geodesic_field``
        for the rule and its accuracy); a greedy follower asks it once per candidate action.
        """
        return GeodesicField(self._require_grid(), self._grid_graph(), as_point(goal, "goal"))

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
            return HitRecord(_nan3(), _nan3(), float(max_search_radius))
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
        if not (
            isinstance(meters_per_pixel, (int, float))
            and not isinstance(meters_per_pixel, bool)
            and math.isfinite(meters_per_pixel)
            and meters_per_pixel > 0
        ):
            raise ValueError(f"meters_per_pixel must be finite and > 0, got {meters_per_pixel!r}")
        if isinstance(height, bool) or not isinstance(
            height, (int, float, np.integer, np.floating)
        ):
            raise TypeError(f"height must be a number, got {height!r}")
        if not math.isfinite(height):
            raise ValueError(f"height must be finite, got {height!r}")
        if not (isinstance(eps, (int, float, np.integer, np.floating)) and eps >= 0):
            raise ValueError(f"eps must be a number >= 0, got {eps!r}")
        data = self._require()
        span = data.bounds[1] - data.bounds[0]
        # (z span / mpp) x (x span / mpp) pixels, in floats so that no int can overflow
        pixels = float(span[0] / meters_per_pixel) * float(span[2] / meters_per_pixel)
        check_budget(
            pixels,
            MAX_TOPDOWN_PIXELS,
            "MAX_TOPDOWN_PIXELS",
            f"a top-down view at {meters_per_pixel} m per pixel",
        )
        return topdown_islands(
            self._require_grid(), data.bounds, float(meters_per_pixel), height, eps
        )
