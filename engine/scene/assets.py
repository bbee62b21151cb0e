"""Load render/collision assets (glTF, GLB, OBJ, PLY) into plain NumPy meshes.

An asset file becomes a list of :class:`MeshData`, one per mesh instance of the file's
scene graph, in world-ready coordinates:

1. ``trimesh`` parses the file into a scene graph (nodes with 4x4 transforms).
2. Each mesh instance is moved by its node's world transform ``T_node`` (nested nodes
   multiply down the graph): ``p_asset = T_node p_mesh``.
3. The asset frame is converted to rigidsim's frame (Y up, -Z forward, right handed):
   the asset's ``up`` maps to +Y and its ``front`` to -Z with the rotation
   ``R = [right; up; -front]`` (rows), ``right = front x up``. For example a Z-up asset
   (``up = (0, 0, 1)``, ``front = (0, 1, 0)``) maps ``(x, y, z) -> (x, z, -y)``.
4. Units and scale: ``p_world = scale * (R (units_to_meters * p_asset))``, the per-axis
   ``scale`` acting in the converted (Y-up) frame.

Colors follow glTF's metallic-roughness base color: a textured mesh is colored
``texture(uv) * base_color / 255``; a mesh with vertex colors uses ``vertex_colors``
(already multiplied by the material's base color); otherwise the flat ``base_color``.

Texture coordinates follow OpenGL (trimesh flips glTF's ``v`` on load, so
``v_returned = 1 - v_gltf``): ``v = 0`` is the *bottom* edge of the image and ``v = 1`` its
top edge. With a texture of shape ``(h, w, 4)`` (row 0 = top row, as stored in the file) a
nearest-texel lookup of ``(u, v)`` in ``[0, 1]`` reads::

    col = u * (w - 1)          row = (1 - v) * (h - 1)

(bilinear filtering with texel centers uses ``col = u w - 1/2``, ``row = (1 - v) h - 1/2``;
``render.RenderMesh(uv_origin="bottom")`` is this convention).

Loaded meshes are cached by ``(path, mtime, size, up, front, scale, units_to_meters)``.
The arrays of a returned :class:`MeshData` are shared with the cache and **read-only**
(writing raises ``ValueError``); copy them (``mesh.copy()``) before editing.

Primitive asset handles (``cubeSolid``, ``icosphereSolid_subdivs_1``, ...) are built by
:func:`primitive_meshes` (see ``engine/scene/primitives.py`` for the shapes).

Conventions: meters, ``vertices (V, 3) float64``, ``faces (F, 3) int64`` counter-clockwise
seen from outside.
"""

from __future__ import annotations

import dataclasses
import os
import struct
from collections import OrderedDict
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import trimesh
from trimesh.visual import ColorVisuals, TextureVisuals

from engine.scene.primitives import PRIMITIVE_ASSET_HANDLES, is_primitive_handle, primitive_geometry

__all__ = [
    "MeshData",
    "PRIMITIVE_ASSET_HANDLES",
    "SUPPORTED_EXTENSIONS",
    "frame_rotation",
    "is_primitive_handle",
    "load_meshes",
    "merge_meshes",
    "mesh_aabb",
    "primitive_meshes",
]

SUPPORTED_EXTENSIONS = (".glb", ".gltf", ".obj", ".ply")
DEFAULT_BASE_COLOR = (255, 255, 255, 255)  # white: a mesh without any material
_CACHE_SIZE = 64  # assets kept in memory (least recently used are dropped)
_ORTHOGONAL_TOLERANCE = 1e-6  # |up . front| allowed after normalizing


@dataclasses.dataclass
class MeshData:
    """One triangle mesh with its appearance, as plain arrays.

    Attributes
    ----------
    vertices : (V, 3) float64
        Positions in meters (world-ready frame: Y up, -Z forward).
    faces : (F, 3) int64
        Vertex indices, counter-clockwise seen from outside.
    vertex_colors : (V, 4) uint8 or None
        RGBA per vertex (material base color already applied).
    uvs : (V, 2) float32 or None
        Texture coordinates, OpenGL convention: texel row = ``(1 - v) * (h - 1)``.
    texture : (h, w, 4) uint8 or None
        RGBA image, row 0 = top; multiply a sample by ``base_color / 255``.
    base_color : (4,) uint8
        RGBA material color (white when the file has none).
    name : str
        Node or geometry name from the file (or the primitive handle).
    """

    vertices: np.ndarray
    faces: np.ndarray
    vertex_colors: np.ndarray | None = None
    uvs: np.ndarray | None = None
    texture: np.ndarray | None = None
    base_color: np.ndarray = dataclasses.field(
        default_factory=lambda: np.array(DEFAULT_BASE_COLOR, dtype=np.uint8)
    )
    name: str = ""

    def copy(self) -> MeshData:
        """Deep copy with writable arrays."""
        return MeshData(
            vertices=self.vertices.copy(),
            faces=self.faces.copy(),
            vertex_colors=None if self.vertex_colors is None else self.vertex_colors.copy(),
            uvs=None if self.uvs is None else self.uvs.copy(),
            texture=None if self.texture is None else self.texture.copy(),
            base_color=self.base_color.copy(),
            name=self.name,
        )


_mesh_cache: OrderedDict[tuple, tuple[MeshData, ...]] = OrderedDict()


# ----------------------------------------------------------------------------------------
# Public API
# ----------------------------------------------------------------------------------------


def load_meshes(
    path: str | os.PathLike,
    up: Sequence[float] = (0.0, 1.0, 0.0),
    front: Sequence[float] = (0.0, 0.0, -1.0),
    scale: Sequence[float] | np.ndarray = (1.0, 1.0, 1.0),
    units_to_meters: float = 1.0,
) -> list[MeshData]:
    """Load every mesh of an asset file, node transforms applied, in rigidsim's frame.

    Parameters
    ----------
    path : str or PathLike
        A ``.glb``, ``.gltf``, ``.obj`` or ``.ply`` file.
    up, front : (3,) float
        The asset's up and front directions (non-zero, orthogonal; normalized here).
        They are mapped to +Y and -Z. Habitat's defaults are ``(0, 1, 0)``, ``(0, 0, -1)``.
    scale : (3,) float
        Positive per-axis scale applied after the frame conversion.
    units_to_meters : float
        Positive factor turning file units into meters, applied before the rotation.

    Returns
    -------
    list of MeshData
        One per mesh instance, in the file's scene-graph order. Arrays are read-only and
        shared between calls (see the module docstring).

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the parameters are invalid, the format is unsupported, or the file cannot be
        read or holds no triangles (the message names the file).
    """
    file_path = Path(path)
    if not file_path.is_file():
        raise FileNotFoundError(f"asset file not found: {str(path)!r}")
    rotation = frame_rotation(up, front)
    scale_vec = _positive_vector(scale, "scale")
    units = _positive_float(units_to_meters, "units_to_meters")
    if file_path.suffix.lower() not in SUPPORTED_EXTENSIONS:
        raise ValueError(
            f"asset file {str(path)!r} has unsupported extension {file_path.suffix!r}; "
            f"expected one of {SUPPORTED_EXTENSIONS}"
        )
    resolved = file_path.resolve()
    stat = resolved.stat()
    key = (
        str(resolved), stat.st_mtime_ns, stat.st_size,
        tuple(rotation.ravel()), tuple(scale_vec), units,
    )  # fmt: skip
    cached = _mesh_cache.get(key)
    if cached is None:
        cached = _load_uncached(resolved, rotation, scale_vec, units)
        _mesh_cache[key] = cached
        while len(_mesh_cache) > _CACHE_SIZE:
            _mesh_cache.popitem(last=False)
    _mesh_cache.move_to_end(key)
    return [dataclasses.replace(mesh) for mesh in cached]


def clear_mesh_cache() -> None:
    """Forget every cached asset (the next :func:`load_meshes` re-reads the files)."""
    _mesh_cache.clear()


def primitive_meshes(handle: str) -> list[MeshData]:
    """Build the unit mesh of a Habitat primitive asset handle (a one-element list).

    ``cubeSolid`` is ``[-1, 1]^3``, spheres have radius 1, cylinders/cones/capsules have
    radius 1 around +Y; see ``engine/scene/primitives.py``. Wireframe handles return the solid
    surface with the same parameters. Raises ``ValueError`` for an unknown handle.
    """
    vertices, faces = primitive_geometry(handle)
    mesh = MeshData(vertices=vertices, faces=faces, name=handle)
    return [_freeze(mesh)]


def merge_meshes(meshes: Sequence[MeshData], name: str = "merged") -> MeshData:
    """Concatenate meshes into one (faces re-indexed).

    The result always carries ``vertex_colors``: each part's vertex colors, else its
    texture's mean color times its base color, else its base color. Textures and UVs are
    dropped (a merged mesh is meant for collision, navmesh and bounds, or flat drawing).
    Raises ``ValueError`` for an empty list.
    """
    meshes = list(meshes)
    if not meshes:
        raise ValueError("merge_meshes needs at least one mesh, got an empty list")
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
    vertices = np.concatenate([np.asarray(m.vertices, dtype=np.float64) for m in meshes])
    faces = np.concatenate(
        [np.asarray(m.faces, dtype=np.int64) + off for m, off in zip(meshes, offsets, strict=True)]
    )
    colors = np.concatenate([_flat_vertex_colors(m) for m in meshes])
    return MeshData(vertices=vertices, faces=faces, vertex_colors=colors, name=name)


def mesh_aabb(meshes: MeshData | Sequence[MeshData]) -> np.ndarray:
    """Axis-aligned bounds of one mesh or a list: ``(2, 3)`` float64 ``[min, max]``."""
    if isinstance(meshes, MeshData):
        meshes = [meshes]
    points = [np.asarray(m.vertices, dtype=np.float64) for m in meshes if len(m.vertices)]
    if not points:
        raise ValueError("mesh_aabb needs at least one mesh with vertices")
    stacked = np.concatenate(points)
    return np.stack([stacked.min(axis=0), stacked.max(axis=0)])


def frame_rotation(up: Sequence[float], front: Sequence[float]) -> np.ndarray:
    """Rotation ``(3, 3)`` taking the asset's ``up`` to +Y and ``front`` to -Z.

    Rows are ``right = front x up``, ``up``, ``-front`` (all unit length), so that
    ``R @ up = e_y`` and ``R @ front = -e_z``. Raises ``ValueError`` if a vector is not
    finite 3-D and non-zero, or if ``up`` and ``front`` are not orthogonal.
    """
    up_vec = _unit_vector(up, "up")
    front_vec = _unit_vector(front, "front")
    if abs(float(up_vec @ front_vec)) > _ORTHOGONAL_TOLERANCE:
        raise ValueError(f"up {list(up)} and front {list(front)} must be orthogonal")
    right = np.cross(front_vec, up_vec)
    return np.stack([right, up_vec, -front_vec])


# ----------------------------------------------------------------------------------------
# Loading internals
# ----------------------------------------------------------------------------------------


def _load_uncached(
    path: Path, rotation: np.ndarray, scale: np.ndarray, units: float
) -> tuple[MeshData, ...]:
    """Parse the file with trimesh and convert every mesh instance."""
    _check_gltf_text(path)
    try:
        scene = trimesh.load(str(path), force="scene", process=False)
    except Exception as error:  # trimesh raises many types for broken files
        raise ValueError(f"cannot read asset file {str(path)!r}: {error}") from error
    if not isinstance(scene, trimesh.Scene):  # force="scene" promises one; say so if not
        raise ValueError(f"cannot read asset file {str(path)!r}: not a scene ({type(scene)})")
    # p_world = S R (u T_node p): one affine map per node.
    linear = scale[:, None] * rotation * units
    meshes = []
    for node in scene.graph.nodes_geometry:
        node_from_mesh, geometry_name = scene.graph[node]
        geometry = scene.geometry.get(geometry_name)
        if not isinstance(geometry, trimesh.Trimesh) or len(geometry.faces) == 0:
            continue  # point clouds, paths and empty meshes carry no surface
        mesh = _convert_geometry(geometry, str(node))
        points = mesh.vertices @ node_from_mesh[:3, :3].T + node_from_mesh[:3, 3]
        mesh.vertices = points @ linear.T  # p' = S R u p
        if np.linalg.det(node_from_mesh[:3, :3]) < 0.0:
            mesh.faces = mesh.faces[:, ::-1].copy()  # a mirroring node flips the winding
        meshes.append(_freeze(mesh))
    if not meshes:
        raise ValueError(f"asset file {str(path)!r} contains no triangle mesh")
    return tuple(meshes)


#: the type of a GLB's first chunk, "JSON" (glTF 2.0, section 4.4.3.2)
_GLB_JSON_CHUNK = 0x4E4F534A


def _check_gltf_text(path: Path) -> None:
    """Refuse a ``.glb`` whose JSON chunk, or a ``.gltf`` file, is not UTF-8 text (glTF 2.0
    requires UTF-8; trimesh would otherwise guess an encoding, or fail importing the
    optional guesser). Other files, and GLBs too broken to find the chunk, pass on to
    trimesh, whose error is reported with the file's name."""
    suffix = path.suffix.lower()
    if suffix == ".gltf":
        text = path.read_bytes()
    elif suffix == ".glb":
        with path.open("rb") as stream:
            header = stream.read(20)
            if len(header) < 20 or header[:4] != b"glTF":
                return
            length, kind = struct.unpack("<II", header[12:20])
            if kind != _GLB_JSON_CHUNK:
                return
            text = stream.read(length)
    else:
        return
    try:
        text.decode("utf-8")
    except UnicodeDecodeError as error:
        raise ValueError(
            f"cannot read asset file {str(path)!r}: its glTF JSON is not UTF-8 text (byte "
            f"{text[error.start]:#04x} at offset {error.start}); glTF files must be UTF-8"
        ) from None


def _convert_geometry(geometry: trimesh.Trimesh, name: str) -> MeshData:
    """Copy positions, faces and appearance out of one trimesh geometry."""
    vertices = np.array(geometry.vertices, dtype=np.float64)
    faces = np.array(geometry.faces, dtype=np.int64)
    visual = geometry.visual
    kind = getattr(visual, "kind", None)
    base_color = _material_base_color(getattr(visual, "material", None))
    mesh = MeshData(vertices=vertices, faces=faces, base_color=base_color, name=name)
    if kind == "texture" and isinstance(visual, TextureVisuals):
        image = _material_image(visual.material)
        if image is not None and visual.uv is not None and len(visual.uv) == len(vertices):
            mesh.uvs = np.asarray(visual.uv, dtype=np.float32)
            mesh.texture = image
    elif kind == "vertex" and isinstance(visual, ColorVisuals):
        colors = np.asarray(visual.vertex_colors, dtype=np.uint8)
        mesh.vertex_colors = _multiply_colors(colors, base_color)
    elif kind == "face" and isinstance(visual, ColorVisuals):
        # Give every face its own three vertices so a per-face color becomes per-vertex.
        face_colors = np.asarray(visual.face_colors, dtype=np.uint8)
        mesh.vertices = vertices[faces.ravel()]
        mesh.faces = np.arange(3 * len(faces), dtype=np.int64).reshape(-1, 3)
        mesh.vertex_colors = _multiply_colors(np.repeat(face_colors, 3, axis=0), base_color)
    return mesh


def _material_base_color(material: object) -> np.ndarray:
    """RGBA uint8 base color of a trimesh material (PBR baseColorFactor or diffuse)."""
    color = None
    if material is not None:
        color = getattr(material, "baseColorFactor", None)
        if color is None and hasattr(material, "diffuse"):
            color = material.diffuse
    if color is None:
        return np.array(DEFAULT_BASE_COLOR, dtype=np.uint8)
    color = np.asarray(color).ravel()
    if color.dtype.kind == "f" and color.max() <= 1.0:
        color = np.round(color * 255.0)  # factors in [0, 1] -> bytes
    rgba = np.full(4, 255, dtype=np.uint8)
    rgba[: min(4, len(color))] = np.clip(color[:4], 0, 255).astype(np.uint8)
    return rgba


def _material_image(material: object) -> np.ndarray | None:
    """The material's base-color texture as ``(h, w, 4)`` uint8 RGBA, or None."""
    image = getattr(material, "baseColorTexture", None)
    if image is None:
        image = getattr(material, "image", None)
    if image is None:
        return None
    return np.asarray(image.convert("RGBA"), dtype=np.uint8)


def _multiply_colors(colors: np.ndarray, base_color: np.ndarray) -> np.ndarray:
    """Per-vertex ``c * base / 255`` in uint8 (glTF multiplies COLOR_0 by the factor)."""
    product = colors.astype(np.uint32) * base_color.astype(np.uint32)
    return ((product + 127) // 255).astype(np.uint8)  # rounded c * b / 255


def _flat_vertex_colors(mesh: MeshData) -> np.ndarray:
    """``(V, 4)`` uint8 colors standing in for the mesh's appearance (see merge_meshes)."""
    if mesh.vertex_colors is not None:
        return np.asarray(mesh.vertex_colors, dtype=np.uint8)
    color = np.asarray(mesh.base_color, dtype=np.uint8)
    if mesh.texture is not None:
        mean = np.asarray(mesh.texture, dtype=np.float64).reshape(-1, 4).mean(axis=0)
        color = _multiply_colors(np.round(mean).astype(np.uint8)[None], color)[0]
    return np.tile(color, (len(mesh.vertices), 1))


def _freeze(mesh: MeshData) -> MeshData:
    """Make the mesh's arrays read-only so cached data cannot be edited by accident."""
    for field in ("vertices", "faces", "vertex_colors", "uvs", "texture", "base_color"):
        array = getattr(mesh, field)
        if array is not None:
            array = np.ascontiguousarray(array)
            array.flags.writeable = False
            setattr(mesh, field, array)
    return mesh


# ----------------------------------------------------------------------------------------
# Argument checks
# ----------------------------------------------------------------------------------------


def _unit_vector(value: Sequence[float], name: str) -> np.ndarray:
    """Finite non-zero 3-vector, normalized; ValueError naming ``name`` otherwise."""
    try:
        vector = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 3-vector, got {value!r}") from None
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise ValueError(f"{name} must be a finite 3-vector, got {value!r}")
    length = float(np.linalg.norm(vector))
    if length < 1e-12:
        raise ValueError(f"{name} must be non-zero, got {value!r}")
    return vector / length


def _positive_vector(value: Sequence[float] | np.ndarray, name: str) -> np.ndarray:
    """Finite 3-vector with every component > 0; ValueError naming ``name`` otherwise."""
    try:
        vector = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 3-vector, got {value!r}") from None
    if vector.shape != (3,) or not np.all(np.isfinite(vector)) or np.any(vector <= 0.0):
        raise ValueError(f"{name} must be a finite 3-vector of positive numbers, got {value!r}")
    return vector


def _positive_float(value: float, name: str) -> float:
    """Finite float > 0; ValueError naming ``name`` otherwise."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number, got {value!r}") from None
    if not np.isfinite(number) or number <= 0.0:
        raise ValueError(f"{name} must be a positive number, got {value!r}")
    return number
