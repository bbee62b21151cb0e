"""NavMeshData: the layered walkable grid a build produces, and its ``.navmesh`` file format.

Grid conventions (declared once here, repeated where used):

- World frame: Y up, meters. The grid covers the XZ footprint of the input mesh.
- Cell ``(iz, ix)`` is the square ``x in [x0 + ix*cs, x0 + (ix+1)*cs)``,
  ``z in [z0 + iz*cs, z0 + (iz+1)*cs)`` with ``(x0, z0) = origin_xz`` and ``cs = cell_size``.
  Arrays are indexed ``[layer, iz, ix]``: rows follow +Z, columns follow +X, as in
  Habitat's top-down view.
- A cell holds up to ``n_layers`` walkable surfaces ("layers", sorted bottom to top: a floor
  under a stair landing under a mezzanine). A *node* is one (layer, cell) pair with the flat
  index ``node = (layer * nz + iz) * nx + ix``.
- ``links[d]`` holds, for every node, the layer of its neighbour across side ``d`` of the
  cell (``DIRECTIONS[d]`` = (dx, dz)), or -1 when the agent cannot step there.

File format (``save``/``load``): a NumPy ``.npz`` archive (written to the exact path given,
whatever its extension) with the keys ``format`` (= ``"rigidsim-navmesh"``),
``format_version`` (= ``FORMAT_VERSION``), ``settings_json`` (camelCase settings),
``bounds`` (2, 3) float64, ``origin_xz`` (2,) float64, ``cell_size`` () float64,
``floor`` / ``ceiling`` (L, nz, nx) float64 (NaN where no layer), ``navigable``
(L, nz, nx) bool, ``links`` (4, L, nz, nx) int8 and ``island`` (L, nz, nx) int32 (-1 where
not navigable).
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.lib import format as npy_format

from navmesh.settings import MAX_NAV_NODES, NavMeshSettings, check_budget

FORMAT_NAME = "rigidsim-navmesh"
FORMAT_VERSION = 1

# The four cell sides as (dx, dz) steps: +X, -X, +Z, -Z.
DIRECTIONS = np.array([[1, 0], [-1, 0], [0, 1], [0, -1]], dtype=np.int64)


@dataclass
class NavMeshData:
    """The result of ``build_navmesh``: a layered 2.5D grid of navigable cells.

    Attributes
    ----------
    settings : NavMeshSettings
        The settings the grid was built with.
    bounds : (2, 3) float64
        World AABB ``[min, max]`` of the input mesh, meters (Habitat's ``get_bounds``).
    origin_xz : (2,) float64
        World (x, z) of the corner of cell (0, 0), meters.
    cell_size : float
        Cell side, meters.
    floor : (L, nz, nx) float64
        Surface height (world y) of each layer, NaN where the layer does not exist.
    ceiling : (L, nz, nx) float64
        Height of the first solid above that surface (inf when open sky).
    navigable : (L, nz, nx) bool
        Walkable after every filter and the agent-radius erosion.
    links : (4, L, nz, nx) int8
        Neighbour layer across side d (``DIRECTIONS[d]``), -1 when not connected; only set
        between navigable nodes.
    island : (L, nz, nx) int32
        Connected-component index of each navigable node (0 = largest island), else -1.
    """

    settings: NavMeshSettings
    bounds: np.ndarray
    origin_xz: np.ndarray
    cell_size: float
    floor: np.ndarray
    ceiling: np.ndarray
    navigable: np.ndarray
    links: np.ndarray
    island: np.ndarray

    @property
    def shape(self) -> tuple[int, int, int]:
        """(n_layers, nz, nx) of the layered grid."""
        return self.floor.shape

    def save(self, path: str | Path) -> None:
        """Write the grid to ``path`` in the documented ``.npz`` format."""
        with open(path, "wb") as stream:
            np.savez_compressed(
                stream,
                format=np.array(FORMAT_NAME),
                format_version=np.array(FORMAT_VERSION),
                settings_json=np.array(json.dumps(self.settings.to_dict())),
                bounds=self.bounds,
                origin_xz=self.origin_xz,
                cell_size=np.array(self.cell_size),
                floor=self.floor,
                ceiling=self.ceiling,
                navigable=self.navigable,
                links=self.links,
                island=self.island,
            )

    @staticmethod
    def load(path: str | Path) -> NavMeshData:
        """Read a grid written by ``save``, validated before anything is returned.

        The archive's array headers are read first (no decompression): every key must be
        present with its documented dtype and consistent shapes, and the grid must fit
        ``MAX_NAV_NODES``, so a small crafted file cannot demand a huge array. Then the
        contents are checked: finite bounds, origin and cell size, valid settings, links
        inside ``[-1, L)`` that never leave the grid and join navigable surfaces, islands
        ``-1`` exactly where not navigable, finite floors under navigable nodes.

        Raises
        ------
        FileNotFoundError
            When ``path`` does not exist.
        ValueError
            When the file is empty, not a rigidsim navmesh of a supported version, or
            inconsistent (the message names the first problem).
        """
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"navmesh file not found: {str(path)!r}")
        where = f"navmesh file {str(path)!r}"
        headers = _array_headers(path, where)
        _check_headers(headers, where)
        try:
            archive = np.load(path, allow_pickle=False)
        except (OSError, ValueError, EOFError) as err:
            raise ValueError(f"{where} cannot be read ({err})") from err
        with archive:
            try:
                arrays = {key: archive[key] for key in _EXPECTED}
            except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as err:
                raise ValueError(f"{where} cannot be read ({err})") from err
        if str(arrays["format"]) != FORMAT_NAME:
            raise ValueError(f"not a rigidsim navmesh file: {str(path)!r}")
        version = int(arrays["format_version"])
        if version != FORMAT_VERSION:
            raise ValueError(f"{where} has format_version {version}, expected {FORMAT_VERSION}")
        settings = NavMeshSettings()
        try:
            settings_dict = json.loads(str(arrays["settings_json"]))
        except json.JSONDecodeError as err:
            raise ValueError(f"{where}: malformed settings_json ({err})") from err
        if not isinstance(settings_dict, dict):
            raise ValueError(f"{where}: settings_json must hold a JSON object")
        try:
            settings.update_from_dict(settings_dict)
        except (KeyError, TypeError) as err:
            raise ValueError(f"{where}: bad settings_json ({err})") from err
        for key, low, high in (
            ("links", -1, np.iinfo(np.int8).max),
            ("island", -1, np.iinfo(np.int32).max),
        ):
            values = arrays[key]  # checked before the cast, which would wrap big values
            if values.size and (values.min() < low or values.max() > high):
                raise ValueError(f"{where}: {key!r} values must lie in [{low}, {high}]")
        data = NavMeshData(
            settings=settings,
            bounds=arrays["bounds"].astype(np.float64, copy=False),
            origin_xz=arrays["origin_xz"].astype(np.float64, copy=False),
            cell_size=float(arrays["cell_size"]),
            floor=arrays["floor"].astype(np.float64, copy=False),
            ceiling=arrays["ceiling"].astype(np.float64, copy=False),
            navigable=arrays["navigable"].astype(bool, copy=False),
            links=arrays["links"].astype(np.int8, copy=False),
            island=arrays["island"].astype(np.int32, copy=False),
        )
        check_contents(data, where)
        return data


# key -> (dtype kinds accepted, number of dimensions); shapes are cross-checked below
_EXPECTED = {
    "format": ("U", 0),
    "format_version": ("iu", 0),
    "settings_json": ("U", 0),
    "bounds": ("f", 2),
    "origin_xz": ("f", 1),
    "cell_size": ("f", 0),
    "floor": ("f", 3),
    "ceiling": ("f", 3),
    "navigable": ("b", 3),
    "links": ("i", 4),
    "island": ("i", 3),
}
#: characters, the longest string (format name, settings JSON) a navmesh file may hold.
_MAX_STRING = 100_000


def _array_headers(path: Path, where: str) -> dict[str, tuple[tuple, np.dtype]]:
    """``{key: (shape, dtype)}`` of every array in the ``.npz``, read from the ``.npy``
    headers without decompressing the data."""
    headers = {}
    try:
        with zipfile.ZipFile(path) as archive:
            for info in archive.infolist():
                if not info.filename.endswith(".npy"):
                    continue
                with archive.open(info) as stream:
                    version = npy_format.read_magic(stream)
                    read = (
                        npy_format.read_array_header_1_0
                        if version == (1, 0)
                        else npy_format.read_array_header_2_0
                    )
                    shape, _fortran, dtype = read(stream)
                headers[info.filename[: -len(".npy")]] = (shape, dtype)
    except (zipfile.BadZipFile, OSError, ValueError, EOFError) as err:
        raise ValueError(f"{where} is not a rigidsim navmesh (.npz) file ({err})") from err
    return headers


def _check_headers(headers: dict, where: str) -> None:
    """Keys, dtypes, dimensions, consistent shapes and the size budget, from headers only."""
    for key, (kinds, ndim) in _EXPECTED.items():
        if key not in headers:
            raise ValueError(f"{where} lacks the array {key!r}")
        shape, dtype = headers[key]
        if dtype.kind not in kinds or dtype.hasobject or len(shape) != ndim:
            raise ValueError(
                f"{where}: {key!r} must be a {ndim}-d array of kind {kinds!r}, "
                f"got shape {shape} dtype {dtype}"
            )
        if dtype.kind == "U" and dtype.itemsize > 4 * _MAX_STRING:
            raise ValueError(f"{where}: {key!r} is longer than {_MAX_STRING} characters")
    grid = headers["floor"][0]
    check_budget(
        float(np.prod(grid, dtype=np.float64)),
        MAX_NAV_NODES,
        "MAX_NAV_NODES",
        f"{where} with a grid of shape {grid}",
    )
    expected = {
        "bounds": (2, 3),
        "origin_xz": (2,),
        "ceiling": grid,
        "navigable": grid,
        "island": grid,
        "links": (4, *grid),
    }
    for key, shape in expected.items():
        if tuple(headers[key][0]) != tuple(shape):
            raise ValueError(
                f"{where}: {key!r} has shape {headers[key][0]}, expected {shape} (floor is {grid})"
            )


def check_contents(data: NavMeshData, where: str = "navmesh") -> None:
    """Raise ValueError naming the first inconsistency of a grid's arrays (see ``load``)."""
    n_layers, nz, nx = data.shape
    if not (np.all(np.isfinite(data.bounds)) and np.all(data.bounds[0] <= data.bounds[1])):
        raise ValueError(
            f"{where}: bounds must be finite with min <= max, got {data.bounds.tolist()}"
        )
    if not np.all(np.isfinite(data.origin_xz)):
        raise ValueError(f"{where}: origin_xz must be finite, got {data.origin_xz.tolist()}")
    if not (np.isfinite(data.cell_size) and data.cell_size > 0):
        raise ValueError(f"{where}: cell_size must be finite and > 0, got {data.cell_size!r}")
    if np.any(np.isinf(data.floor)) or np.any(np.isnan(data.ceiling) & ~np.isnan(data.floor)):
        raise ValueError(f"{where}: floor must be finite or NaN, with a ceiling over each floor")
    navigable = data.navigable
    if np.any(navigable & (np.isnan(data.floor) | ~(data.ceiling >= data.floor))):
        raise ValueError(f"{where}: a navigable node has no floor or a ceiling below it")
    island = data.island
    if np.any((island >= 0) != navigable) or np.any(island < -1):
        raise ValueError(f"{where}: island must be >= 0 exactly on navigable nodes, else -1")
    links = data.links
    if np.any(links < -1) or np.any(links >= n_layers):
        raise ValueError(
            f"{where}: links must lie in [-1, {n_layers}), got [{links.min()}, {links.max()}]"
        )
    for d, (dx, dz) in enumerate(DIRECTIONS):
        linked = links[d] >= 0  # (L, nz, nx)
        if not np.any(linked):
            continue
        layer, iz, ix = np.nonzero(linked)
        jx, jz = ix + dx, iz + dz
        if np.any((jx < 0) | (jx >= nx) | (jz < 0) | (jz >= nz)):
            raise ValueError(f"{where}: a link across side {d} leaves the grid")
        target = links[d][layer, iz, ix].astype(np.int64)
        if not (np.all(navigable[layer, iz, ix]) and np.all(navigable[target, jz, jx])):
            raise ValueError(f"{where}: a link across side {d} joins a non-navigable node")
