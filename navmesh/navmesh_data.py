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
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from navmesh.settings import NavMeshSettings

FORMAT_NAME = "rigidsim-navmesh"
FORMAT_VERSION = 1

# The four cell sides as (dx, dz) steps: +X, -X, +Z, -Z. OPPOSITE[d] is the reverse side.
DIRECTIONS = np.array([[1, 0], [-1, 0], [0, 1], [0, -1]], dtype=np.int64)
OPPOSITE = np.array([1, 0, 3, 2], dtype=np.int64)


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
        """Read a grid written by ``save``.

        Raises
        ------
        FileNotFoundError
            When ``path`` does not exist.
        ValueError
            When the file is not a rigidsim navmesh of a supported version.
        """
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"navmesh file not found: {str(path)!r}")
        try:
            archive = np.load(path, allow_pickle=False)
        except (OSError, ValueError) as err:
            raise ValueError(f"not a rigidsim navmesh file: {str(path)!r} ({err})") from err
        with archive:
            if "format" not in archive or str(archive["format"]) != FORMAT_NAME:
                raise ValueError(f"not a rigidsim navmesh file: {str(path)!r}")
            version = int(archive["format_version"])
            if version != FORMAT_VERSION:
                raise ValueError(
                    f"navmesh file {str(path)!r} has format_version {version}, "
                    f"expected {FORMAT_VERSION}"
                )
            settings = NavMeshSettings()
            settings.update_from_dict(json.loads(str(archive["settings_json"])))
            return NavMeshData(
                settings=settings,
                bounds=archive["bounds"].astype(np.float64),
                origin_xz=archive["origin_xz"].astype(np.float64),
                cell_size=float(archive["cell_size"]),
                floor=archive["floor"].astype(np.float64),
                ceiling=archive["ceiling"].astype(np.float64),
                navigable=archive["navigable"].astype(bool),
                links=archive["links"].astype(np.int8),
                island=archive["island"].astype(np.int32),
            )
