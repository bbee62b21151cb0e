"""NavMeshSettings: every constant of the navmesh build, with units, in one place.

The fields, their defaults and their camelCase JSON keys follow Habitat-sim's
``esp::nav::NavMeshSettings`` (``src/esp/nav/PathFinder.h``), which in turn mirrors
Recast's ``rcConfig``. rigidsim builds a *grid* navmesh (no polygons), so the polygon
fields (``region_merge_size``, ``edge_max_len``, ``edge_max_error``, ``verts_per_poly``,
``detail_sample_dist``, ``detail_sample_max_error``) are stored, validated and round-tripped
through JSON for compatibility but do not change the build. ``region_min_size`` is used:
islands smaller than ``region_min_size**2`` cells are dropped, as Recast drops small regions.

Conventions: Y up, meters, angles in degrees. Lengths are world units unless a field says
"in cells" (cell_size sized squares in the XZ plane).
"""

from __future__ import annotations

import difflib
import json
import math
from dataclasses import dataclass, fields
from pathlib import Path

# (python field name, JSON key, kind). Kind is "length" (> 0 meters), "nonneg" (>= 0),
# "angle" (degrees in [0, 90]), "bool".
_FIELD_SPECS: tuple[tuple[str, str, str], ...] = (
    ("cell_size", "cellSize", "length"),
    ("cell_height", "cellHeight", "length"),
    ("agent_height", "agentHeight", "nonneg"),  # Habitat accepts 0 (no clearance needed)
    ("agent_radius", "agentRadius", "nonneg"),
    ("agent_max_climb", "agentMaxClimb", "nonneg"),
    ("agent_max_slope", "agentMaxSlope", "angle"),
    ("region_min_size", "regionMinSize", "nonneg"),
    ("region_merge_size", "regionMergeSize", "nonneg"),
    ("edge_max_len", "edgeMaxLen", "nonneg"),
    ("edge_max_error", "edgeMaxError", "nonneg"),
    ("verts_per_poly", "vertsPerPoly", "nonneg"),
    ("detail_sample_dist", "detailSampleDist", "nonneg"),
    ("detail_sample_max_error", "detailSampleMaxError", "nonneg"),
    ("filter_low_hanging_obstacles", "filterLowHangingObstacles", "bool"),
    ("filter_ledge_spans", "filterLedgeSpans", "bool"),
    ("filter_walkable_low_height_spans", "filterWalkableLowHeightSpans", "bool"),
    ("include_static_objects", "includeStaticObjects", "bool"),
)

# Habitat's __eq__ compares every parameter with this absolute tolerance.
EQUALITY_EPS = 1e-5

# Query constants (not build settings), in meters.
# Half extents (x, y, z) of the box searched for the nearest navmesh point: Habitat's
# ``projectToPoly`` passes (2, 4, 2) to Detour's findNearestPoly.
SNAP_HALF_EXTENTS = (2.0, 4.0, 2.0)
# Points clamped onto a square's side are pulled this far inside (Habitat nudges by 0.1 mm).
INSIDE_EPS = 1e-4
# is_navigable: largest horizontal snap displacement still counted as "on the mesh" (1 cm).
NAVIGABLE_XZ_TOLERANCE = 1e-2

# Size budgets, checked up front (ValueError naming the budget) before anything is allocated.
#: cells, the largest XZ grid a build may cover (nx * nz): 10 million, e.g. 158 m x 158 m at
#: Habitat's default 5 cm cells; each cell costs ~30 bytes per surface layer during a build.
MAX_GRID_CELLS = 10_000_000
#: samples, the most triangle samples the rasterization may take (about 17 bytes each plus
#: a sort): a 1e-4 m cell or cell height over a room asks for billions.
MAX_RASTER_SAMPLES = 30_000_000
#: nodes (layers x cells), the largest layered grid a ``.navmesh`` file may hold; its arrays
#: cost 26 bytes per node (floor, ceiling, navigable, 4 links, island): at most ~520 MB.
MAX_NAV_NODES = 20_000_000
#: pixels, the largest top-down view ``get_topdown_view`` renders (16 bytes per pixel).
MAX_TOPDOWN_PIXELS = 4096 * 4096


def check_budget(count: float, budget: int, name: str, what: str) -> None:
    """Raise ValueError naming the budget ``name`` when ``count`` exceeds it."""
    if not count <= budget:  # also catches NaN and inf counts
        raise ValueError(
            f"{what} needs {count:.3g}, more than the budget navmesh.settings.{name} = {budget}"
        )


@dataclass(eq=False)
class NavMeshSettings:
    """Parameters of the navmesh build (Habitat-sim's ``NavMeshSettings``).

    Attributes
    ----------
    cell_size : float
        Side of a square grid cell in the XZ plane, meters (Habitat default 0.05).
    cell_height : float
        Vertical resolution, meters: solid samples closer than this in one column merge into
        one span (default 0.2).
    agent_height : float
        Minimum floor-to-ceiling clearance the agent needs, meters (default 1.5); 0 (accepted
        as Habitat, whose ``make_cfg`` copies ``sensor_height`` here) keeps every floor.
    agent_radius : float
        Walkable area is eroded by this distance from obstacles and drops, meters, rounded up
        to whole cells (default 0.1).
    agent_max_climb : float
        Largest step height the agent can climb between neighbouring cells, meters (0.2).
    agent_max_slope : float
        Steepest walkable triangle, degrees from horizontal (default 45).
    region_min_size : float
        Islands with fewer than ``region_min_size**2`` cells are removed (default 20).
    region_merge_size, edge_max_len, edge_max_error, verts_per_poly, detail_sample_dist,
    detail_sample_max_error : float
        Recast polygonization parameters; stored for compatibility, unused by the grid mesh.
    filter_low_hanging_obstacles : bool
        Let the agent step onto low unwalkable spans (curbs) within max climb (default True).
    filter_ledge_spans : bool
        Remove walkable cells next to a drop deeper than max climb (default True).
    filter_walkable_low_height_spans : bool
        Remove walkable cells whose clearance is below agent_height (default True).
    include_static_objects : bool
        Read by ``Simulator.recompute_navmesh``: add STATIC objects to the stage (False).
    """

    cell_size: float = 0.05
    cell_height: float = 0.2
    agent_height: float = 1.5
    agent_radius: float = 0.1
    agent_max_climb: float = 0.2
    agent_max_slope: float = 45.0
    region_min_size: float = 20.0
    region_merge_size: float = 20.0
    edge_max_len: float = 12.0
    edge_max_error: float = 1.3
    verts_per_poly: float = 6.0
    detail_sample_dist: float = 6.0
    detail_sample_max_error: float = 1.0
    filter_low_hanging_obstacles: bool = True
    filter_ledge_spans: bool = True
    filter_walkable_low_height_spans: bool = True
    include_static_objects: bool = False

    def set_defaults(self) -> None:
        """Reset every field to Habitat's ``setDefaults()`` values."""
        defaults = NavMeshSettings.__new__(NavMeshSettings)
        NavMeshSettings.__init__(defaults)
        for f in fields(self):
            setattr(self, f.name, getattr(defaults, f.name))

    def validate(self) -> None:
        """Raise ValueError naming the first field with an invalid value."""
        for name, _key, kind in _FIELD_SPECS:
            _check_field(name, getattr(self, name), kind)

    def to_dict(self) -> dict:
        """Return the settings as a dict keyed by Habitat's camelCase JSON names."""
        return {key: getattr(self, name) for name, key, _kind in _FIELD_SPECS}

    def update_from_dict(self, data: dict) -> None:
        """Overwrite the fields present in ``data`` (camelCase keys); validate first.

        Raises
        ------
        KeyError
            For a key that is not a NavMeshSettings JSON key.
        ValueError
            For a value out of range; the settings are left unchanged.
        """
        key_to_spec = {key: (name, kind) for name, key, kind in _FIELD_SPECS}
        converted = {}
        for key, value in data.items():
            if key not in key_to_spec:
                raise KeyError(f"unknown NavMeshSettings JSON key {key!r}")
            name, kind = key_to_spec[key]
            _check_field(name, value, kind)
            converted[name] = bool(value) if kind == "bool" else float(value)
        for name, value in converted.items():
            setattr(self, name, value)

    def read_from_json(self, path: str | Path) -> None:
        """Overwrite these settings with the values of a JSON file (camelCase keys).

        Raises FileNotFoundError for a missing file and ValueError for malformed JSON.
        """
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"NavMeshSettings JSON file not found: {str(path)!r}")
        try:
            data = json.loads(path.read_text())
        except json.JSONDecodeError as err:
            raise ValueError(f"malformed NavMeshSettings JSON {str(path)!r}: {err}") from err
        if not isinstance(data, dict):
            raise ValueError(f"NavMeshSettings JSON {str(path)!r} must hold an object")
        self.update_from_dict(data)

    def write_to_json(self, path: str | Path) -> None:
        """Write these settings to a JSON file with Habitat's camelCase keys."""
        Path(path).write_text(json.dumps(self.to_dict(), indent=4) + "\n")

    def __eq__(self, other: object) -> bool:
        """Equal when every parameter matches within 1e-5 (Habitat's ``__eq__``)."""
        if not isinstance(other, NavMeshSettings):
            return NotImplemented
        for name, _key, kind in _FIELD_SPECS:
            mine, theirs = getattr(self, name), getattr(other, name)
            if kind == "bool":
                if bool(mine) != bool(theirs):
                    return False
            elif abs(float(mine) - float(theirs)) > EQUALITY_EPS:
                return False
        return True

    def __ne__(self, other: object) -> bool:
        result = self.__eq__(other)
        return result if result is NotImplemented else not result

    def __setattr__(self, name: str, value: object) -> None:
        """Refuse unknown fields (Habitat's settings are a fixed-field C++ struct), naming
        the closest field: ``settings.agent_raduis = 0.2`` raises ``AttributeError``."""
        known = [f.name for f in fields(self)]
        if name not in known:
            close = difflib.get_close_matches(name, known, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else f"; its fields are {known}"
            raise AttributeError(f"'NavMeshSettings' object has no attribute {name!r}{hint}")
        object.__setattr__(self, name, value)

    # Not hashable (mutable and compared with a tolerance): a class that defines __eq__ and
    # no __hash__ gets ``__hash__ = None`` from Python itself.


def _check_field(name: str, value: object, kind: str) -> None:
    """Raise ValueError/TypeError naming ``name`` when ``value`` does not fit ``kind``."""
    if kind == "bool":
        if not isinstance(value, bool):
            raise TypeError(f"NavMeshSettings.{name} must be a bool, got {value!r}")
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"NavMeshSettings.{name} must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"NavMeshSettings.{name} must be finite, got {value!r}")
    if kind == "length" and value <= 0.0:
        raise ValueError(f"NavMeshSettings.{name} must be > 0 meters, got {value!r}")
    if kind == "nonneg" and value < 0.0:
        raise ValueError(f"NavMeshSettings.{name} must be >= 0, got {value!r}")
    if kind == "angle" and not 0.0 <= value <= 90.0:
        raise ValueError(f"NavMeshSettings.{name} must be in [0, 90] degrees, got {value!r}")
