"""What the renderer draws: ``RenderMesh`` (one mesh and its material) and ``RenderScene``.

A ``RenderMesh`` is plain arrays in the mesh's local frame plus a pose ``world_from_mesh``.
A ``RenderScene`` concatenates the static arrays of many meshes once (vertices, faces,
per-triangle material tables) so that each frame only re-transforms vertices with the
current poses: meshes are static, poses change. Build one ``RenderScene`` when the set of
meshes changes (objects added or removed), update poses with ``set_world_from_mesh`` and
hide meshes with ``set_visible``; pass it to ``render_frame`` every frame.

Conventions: meters, Y up, counter-clockwise faces are front faces; colors are uint8 RGBA;
``uvs`` follow ``uv_origin`` (default ``"bottom"``: v = 0 is the bottom row of the texture
image, which is what ``trimesh`` returns for a glTF/glb file: its loader flips the file's
v, so that texel row = (1 - v) * h; use ``"top"`` for raw glTF uvs, row = v * h).
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from render.camera import check_pose
from render.lights import DEFAULT_LIGHTS, Lights, face_light_factors, lambert_factors
from render.packed_rgba import pack_rgba, pad_texture_wrap
from render.shade import FLAT, TEXTURED, VERTEX_COLOR, MaterialTable

UV_ORIGINS = ("bottom", "top")


def _finite_array(name: str, value: object, shape_tail: tuple[int, ...]) -> np.ndarray:
    """``value`` as float64 with shape ``(n, *shape_tail)`` and finite entries, else ValueError."""
    if value is None:
        raise ValueError(f"{name} must be an array, got None")
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim != 1 + len(shape_tail) or arr.shape[1:] != shape_tail:
        raise ValueError(
            f"{name} must have shape (n, {', '.join(map(str, shape_tail))}), got {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN/inf)")
    return arr


def _uint8_color_array(name: str, value: object, n: int | None) -> np.ndarray:
    """RGBA uint8 colors ``(n, 4)`` (or ``(4,)`` when ``n`` is None); RGB gets alpha 255."""
    arr = np.asarray(value)
    given_shape = arr.shape
    if arr.dtype.kind not in "uif" or np.any(arr < 0) or np.any(arr > 255) or np.any(np.isnan(arr)):
        raise ValueError(f"{name} must hold numbers in [0, 255], got dtype {arr.dtype}")
    expected = (4,) if n is None else (n, 4)
    if arr.shape[-1:] == (3,):
        arr = np.concatenate([arr, np.full(arr.shape[:-1] + (1,), 255)], axis=-1)
    if arr.shape != expected:
        raise ValueError(f"{name} must have shape {expected} (RGBA), got {given_shape}")
    return np.rint(arr).astype(np.uint8)


@dataclass
class RenderMesh:
    """One drawable mesh.

    Attributes
    ----------
    vertices : (V, 3) float64, mesh-local frame, meters.
    faces : (F, 3) int64, vertex indices, counter-clockwise = front face.
    world_from_mesh : (4, 4) float64 pose (may include scaling).
    vertex_colors : (V, 4) uint8 RGBA (or (V, 3) RGB) or None.
    uvs : (V, 2) float texture coordinates or None (required with ``texture``).
    texture : (h, w, 3 | 4) uint8 image, row 0 at the top, or None.
    base_color : (4,) uint8 RGBA multiplied into every pixel (default white).
    lit : False draws the color as is (Habitat's stage); True applies the default lights.
    semantic_id : int in [0, 2**32), written to the ids buffer.
    uv_origin : ``"bottom"`` (trimesh, default) or ``"top"`` (raw glTF), see module doc.
    normals : (V, 3) float vertex normals in the mesh-local frame, or None. A lit mesh with
        normals is Gouraud-shaded (light computed per vertex, interpolated: smooth spheres);
        without, each face is lit by its own flat normal (right for boxes).
    lights : the :class:`render.shade.Lights` of a lit mesh (None: the default setup,
        ``DEFAULT_LIGHTS``); an empty setup draws the mesh flat, like ``lit=False``.
    """

    vertices: np.ndarray
    faces: np.ndarray
    world_from_mesh: np.ndarray = field(default_factory=lambda: np.eye(4))
    vertex_colors: np.ndarray | None = None
    uvs: np.ndarray | None = None
    texture: np.ndarray | None = None
    base_color: np.ndarray = field(default_factory=lambda: np.full(4, 255, dtype=np.uint8))
    lit: bool = False
    semantic_id: int = 0
    uv_origin: str = "bottom"
    normals: np.ndarray | None = None
    lights: Lights | None = None

    def __post_init__(self) -> None:
        if self.lights is not None and not isinstance(self.lights, Lights):
            raise TypeError(f"lights must be render.shade.Lights or None, got {self.lights!r}")
        self.vertices = _finite_array("vertices", self.vertices, (3,))
        n_vertices = len(self.vertices)
        faces = np.asarray(self.faces)
        if faces.ndim != 2 or faces.shape[1] != 3 or faces.dtype.kind not in "iu":
            raise ValueError(f"faces must be an (F, 3) int array, got {faces.dtype} {faces.shape}")
        if faces.size and (faces.min() < 0 or faces.max() >= n_vertices):
            raise ValueError(f"faces index vertices out of range [0, {n_vertices})")
        self.faces = faces.astype(np.int64)
        self.world_from_mesh = check_pose(self.world_from_mesh, "world_from_mesh")
        if self.vertex_colors is not None:
            self.vertex_colors = _uint8_color_array("vertex_colors", self.vertex_colors, n_vertices)
        if self.uvs is not None:
            self.uvs = _finite_array("uvs", self.uvs, (2,)).astype(np.float32)
            if len(self.uvs) != n_vertices:
                raise ValueError(
                    f"uvs must have one row per vertex ({n_vertices}), got {len(self.uvs)}"
                )
        if self.texture is not None:
            self.texture = _check_texture(self.texture)
            if self.uvs is None:
                raise ValueError("texture given without uvs")
        self.base_color = _uint8_color_array("base_color", self.base_color, None)
        if not isinstance(self.lit, (bool, np.bool_)):
            raise TypeError(f"lit must be a bool, got {self.lit!r}")
        sid = self.semantic_id
        if isinstance(sid, bool) or not isinstance(sid, (int, np.integer)) or not 0 <= sid < 2**32:
            raise ValueError(f"semantic_id must be an int in [0, 2**32), got {sid!r}")
        if self.normals is not None:
            self.normals = _finite_array("normals", self.normals, (3,))
            if len(self.normals) != n_vertices:
                raise ValueError(f"normals must have one row per vertex ({n_vertices})")
        if self.uv_origin not in UV_ORIGINS:
            raise ValueError(f"uv_origin must be one of {UV_ORIGINS}, got {self.uv_origin!r}")


def _check_texture(texture: object) -> np.ndarray:
    """Texture as (h, w, 4) uint8 RGBA (RGB gets alpha 255, gray is replicated)."""
    tex = np.asarray(texture)
    if tex.dtype != np.uint8:
        raise ValueError(f"texture must be uint8, got {tex.dtype}")
    if tex.ndim == 2:
        tex = np.repeat(tex[:, :, None], 3, axis=2)
    if tex.ndim != 3 or tex.shape[2] not in (3, 4) or tex.shape[0] == 0 or tex.shape[1] == 0:
        raise ValueError(f"texture must have shape (h, w, 3|4), got {tex.shape}")
    if tex.shape[2] == 3:
        tex = np.concatenate([tex, np.full(tex.shape[:2] + (1,), 255, np.uint8)], axis=2)
    return np.ascontiguousarray(tex)


class RenderScene:
    """Meshes concatenated once for fast repeated rendering (see module docstring).

    Attributes
    ----------
    meshes : the ``RenderMesh`` list (do not mutate its arrays; build a new scene instead).
    world_from_mesh : (M, 4, 4) float64 current poses.
    visible : (M,) bool.
    vertices_local : (3, V) float64, all meshes' local vertices (coordinate-major).
    vertex_slices : M slices of ``vertices_local``.
    materials : ``MaterialTable`` (faces ``(3, T)`` in global vertex ids, colors, textures).
    tri_lit : (T,) bool.  tri_semantic : (T,) uint32.
    """

    def __init__(self, meshes: Sequence[RenderMesh]) -> None:
        meshes = list(meshes)
        for i, mesh in enumerate(meshes):
            if not isinstance(mesh, RenderMesh):
                raise TypeError(f"meshes[{i}] must be a RenderMesh, got {type(mesh).__name__}")
        self.meshes = meshes
        n_meshes = len(meshes)
        self.world_from_mesh = np.array([m.world_from_mesh for m in meshes]).reshape(n_meshes, 4, 4)
        self.visible = np.ones(n_meshes, dtype=bool)
        counts = np.array([len(m.vertices) for m in meshes], dtype=np.int64)
        offsets = np.concatenate([[0], np.cumsum(counts)])
        bounds = zip(offsets[:-1], offsets[1:], strict=True)
        self.vertex_slices = [slice(int(a), int(b)) for a, b in bounds]
        local = [m.vertices for m in meshes] or [np.zeros((0, 3))]
        self.vertices_local = np.ascontiguousarray(np.concatenate(local).T)  # (3, V)
        n_faces = np.array([len(m.faces) for m in meshes], dtype=np.int64)
        tri_mesh = np.repeat(np.arange(n_meshes), n_faces)
        self._group_lights(meshes, tri_mesh)
        self.tri_semantic = np.array([m.semantic_id for m in meshes], dtype=np.uint32)[tri_mesh]
        mesh_faces = [m.faces + off for m, off in zip(meshes, offsets[:-1], strict=True)]
        faces = np.concatenate(mesh_faces or [np.zeros((0, 3), np.int64)])
        self.materials = _material_table(meshes, tri_mesh, np.ascontiguousarray(faces.T))
        self.smooth_meshes = [
            i
            for i, m in enumerate(meshes)
            if self.mesh_light_group[i] >= 0 and m.normals is not None
        ]
        self.tri_smooth = np.isin(tri_mesh, self.smooth_meshes)

    def _group_lights(self, meshes: list[RenderMesh], tri_mesh: np.ndarray) -> None:
        """``light_groups``: the distinct :class:`Lights` of the lit meshes (by identity);
        ``mesh_light_group (M,)`` and ``tri_light_group (T,)`` index them, -1 where unlit
        (``lit=False`` or an empty, flat setup); ``tri_lit (T,)``."""
        self.light_groups: list[Lights] = []
        groups = []
        for mesh in meshes:
            lights = DEFAULT_LIGHTS if mesh.lights is None else mesh.lights
            if not mesh.lit or lights.is_flat:
                groups.append(-1)
                continue
            index = next((k for k, known in enumerate(self.light_groups) if known is lights), None)
            if index is None:
                index = len(self.light_groups)
                self.light_groups.append(lights)
            groups.append(index)
        self.mesh_light_group = np.array(groups, dtype=np.int64)
        self.tri_light_group = self.mesh_light_group[tri_mesh]
        self.tri_lit = self.tri_light_group >= 0

    def face_light_factors(
        self,
        tri_ids: np.ndarray,
        normals_world: np.ndarray,
        points_world: np.ndarray,
        world_from_camera: np.ndarray | None = None,
    ) -> np.ndarray:
        """Flat light factor ``(k,)`` float32 of triangles ``tri_ids`` (1 where unlit), from
        their world normals and centroids, each with its mesh's light setup."""
        out = np.ones(len(tri_ids), dtype=np.float32)
        groups = self.tri_light_group[tri_ids]
        for g, lights in enumerate(self.light_groups):
            sel = np.flatnonzero(groups == g)
            if len(sel) == 0:
                continue
            if lights is DEFAULT_LIGHTS:  # the common case, rigidsim's historic formula
                out[sel] = face_light_factors(normals_world[sel])
            elif not lights.has_mesh_frame:
                world = lights.in_world(world_from_camera, None)
                out[sel] = lambert_factors(normals_world[sel], points_world[sel], lights, world)
            else:  # lights that move with each mesh: one resolution per mesh
                mesh_of = self.materials.tri_mesh[tri_ids[sel]]
                for mesh in np.unique(mesh_of).tolist():
                    sub = sel[mesh_of == mesh]
                    world = lights.in_world(world_from_camera, self.world_from_mesh[mesh])
                    out[sub] = lambert_factors(normals_world[sub], points_world[sub], lights, world)
        return out

    @property
    def n_triangles(self) -> int:
        """Total number of triangles T."""
        return self.materials.faces.shape[1]

    def set_world_from_mesh(self, index: int, world_from_mesh: np.ndarray) -> None:
        """Set mesh ``index``'s pose, a (4, 4) matrix (ValueError if malformed)."""
        if not 0 <= index < len(self.meshes):
            raise KeyError(f"mesh index {index!r} out of range [0, {len(self.meshes)})")
        self.world_from_mesh[index] = check_pose(world_from_mesh, "world_from_mesh")

    def set_visible(self, index: int, visible: bool) -> None:
        """Show or hide mesh ``index``."""
        if not 0 <= index < len(self.meshes):
            raise KeyError(f"mesh index {index!r} out of range [0, {len(self.meshes)})")
        self.visible[index] = bool(visible)

    def vertices_in_camera(self, camera_from_world: np.ndarray) -> np.ndarray:
        """All vertices in the camera frame, ``(3, V)`` float64 (a fresh array, so that
        threads may render one scene from several cameras at once).

        ``p_camera = camera_from_world @ world_from_mesh @ p_local`` per mesh.
        """
        vertices_camera = np.empty_like(self.vertices_local)
        for i, sl in enumerate(self.vertex_slices):
            camera_from_mesh = camera_from_world @ self.world_from_mesh[i]
            out = vertices_camera[:, sl]
            np.matmul(camera_from_mesh[:3, :3], self.vertices_local[:, sl], out=out)  # R p
            out += camera_from_mesh[:3, 3:4]  # + t
        return vertices_camera

    def vertex_light_factors(self, world_from_camera: np.ndarray | None = None) -> np.ndarray:
        """Light factor of every vertex of the Gouraud-shaded meshes, ``(1, V)`` float32.

        Normals go to the world frame with the normal matrix ``(R_wm^-1)^T`` (correct under
        non-uniform scaling); other vertices get 1.
        """
        light = np.ones((1, self.vertices_local.shape[1]), dtype=np.float32)
        for i in self.smooth_meshes:
            pose = self.world_from_mesh[i]
            normal_matrix = np.linalg.inv(pose[:3, :3]).T
            normals_world = self.meshes[i].normals @ normal_matrix.T  # n_w = N n_local
            lights = self.light_groups[self.mesh_light_group[i]]
            if lights is DEFAULT_LIGHTS:
                light[0, self.vertex_slices[i]] = face_light_factors(normals_world)
                continue
            points = self.meshes[i].vertices @ pose[:3, :3].T + pose[:3, 3]  # p_w = R p + t
            world = lights.in_world(world_from_camera, pose)
            light[0, self.vertex_slices[i]] = lambert_factors(normals_world, points, lights, world)
        return light


def _material_table(
    meshes: list[RenderMesh], tri_mesh: np.ndarray, faces: np.ndarray
) -> MaterialTable:
    """Concatenate the meshes' materials into one ``MaterialTable`` (``faces`` is (3, T)).

    Vertex colors are premultiplied by their mesh's base color. A vertex-colored triangle
    whose 3 corners have the same color is shaded like a flat one (one gather per pixel).
    """
    base = np.array([m.base_color for m in meshes], dtype=np.uint8).reshape(-1, 4)
    base_unit = base.astype(np.float32) / 255.0
    has_vc = np.array([m.vertex_colors is not None for m in meshes], dtype=bool)
    textured = np.array([m.texture is not None for m in meshes], dtype=bool)
    tri_color = base[tri_mesh]  # (T, 4) uint8 flat color of each triangle
    tri_kind = np.where(textured[tri_mesh], TEXTURED, FLAT).astype(np.int8)
    vertex_colors = uvs = None
    if has_vc.any():
        columns = [
            m.vertex_colors * base_unit[i] if has_vc[i] else np.tile(base[i], (len(m.vertices), 1))
            for i, m in enumerate(meshes)
        ]
        vertex_colors = np.concatenate(columns).T.astype(np.float32) / 255.0  # (4, V) premultiplied
        corner = [np.rint(vertex_colors[:, faces[k]] * 255.0).astype(np.uint8) for k in range(3)]
        uniform = np.all((corner[0] == corner[1]) & (corner[1] == corner[2]), axis=0)
        colored = has_vc[tri_mesh]
        tri_color[colored] = corner[0][:, colored].T  # premultiplied corner color
        tri_kind[colored & ~uniform & ~textured[tri_mesh]] = VERTEX_COLOR
    if textured.any():
        columns = [
            m.uvs if textured[i] else np.zeros((len(m.vertices), 2)) for i, m in enumerate(meshes)
        ]
        uvs = np.ascontiguousarray(np.concatenate(columns).T, dtype=np.float32)
    return MaterialTable(
        tri_mesh=tri_mesh,
        tri_base_packed=pack_rgba(tri_color),
        tri_kind=tri_kind,
        faces=faces,
        base_colors=base_unit,
        has_vertex_colors=has_vc,
        vertex_colors=vertex_colors,
        uvs=uvs,
        textures=[_packed_texture(m.texture) if m.texture is not None else None for m in meshes],
        uv_origins=[m.uv_origin for m in meshes],
    )


#: packed, padded textures of recent scenes, keyed by the id of the source array (which the
#: entry keeps alive, so the id cannot be reused): rebuilding a scene after an object is
#: added does not repack the stage's textures
_TEXTURE_CACHE: OrderedDict[int, tuple[np.ndarray, np.ndarray]] = OrderedDict()
_TEXTURE_CACHE_SIZE = 32


def _packed_texture(texture: np.ndarray) -> np.ndarray:
    """``pad_texture_wrap(pack_rgba(texture))``, cached by array identity.

    The cache assumes textures are not modified in place after a scene was built from them.
    """
    entry = _TEXTURE_CACHE.get(id(texture))
    if entry is not None and entry[0] is texture:
        _TEXTURE_CACHE.move_to_end(id(texture))
        return entry[1]
    padded = pad_texture_wrap(pack_rgba(texture))
    _TEXTURE_CACHE[id(texture)] = (texture, padded)
    if len(_TEXTURE_CACHE) > _TEXTURE_CACHE_SIZE:
        _TEXTURE_CACHE.popitem(last=False)  # forget the least recently used
    return padded
