"""Shading: the color of each visible pixel from its triangle, attributes and material.

Shading is *deferred*: the rasterizer first finds, per pixel, the nearest triangle and its
depth; each visible pixel is then shaded exactly once here. Perspective-correct vertex
attributes (uvs, vertex colors) come from ``render.raster.AttributePlanes``; ``b`` below
are the perspective-correct barycentrics of the pixel center.

Color of a pixel (all factors in [0, 1], RGBA)::

    color = base_color * vertex_color(b) * texture(uv(b)) * light

* ``vertex_color(b) = sum_k b_k c_k`` (1 if the mesh has no vertex colors).
* ``uv(b) = sum_k b_k uv_k``; ``texture`` samples bilinearly between the four nearest texel
  centers, wrapping (glTF's default REPEAT). Texel ``(i, j)`` has its center at
  ``u = (j + 0.5) / w`` and, for ``uv_origin="bottom"`` (trimesh and OpenGL: v = 0 is the
  bottom row of the image), ``v = 1 - (i + 0.5) / h``; for ``uv_origin="top"`` (the glTF
  file convention) ``v = (i + 0.5) / h``.
* ``light = 1`` for unlit meshes (Habitat draws the stage flat). Lit meshes (Habitat's
  default object light setup: 4 directional lights travelling along
  ``d = (+-1, -0.5, 0)`` and ``(0, -0.5, +-1)`` (world frame, normalized) plus ambient)
  use the Lambert term on the normal ``n`` (world frame): the flat face normal, or, for
  meshes given vertex normals, the vertex normals (Gouraud shading: the light factor is
  computed per vertex and interpolated perspective-correctly)::

      light = clamp(AMBIENT + DIFFUSE * sum_k max(0, n . l_k), 0, 1),  l_k = -d_k

  with ``AMBIENT = 0.4`` and ``DIFFUSE = 0.5``: the top face (``n . l_k = 0.447`` for all
  4 lights) gets 1.0, a vertical side facing +-x or +-z 0.85, the bottom 0.4. Alpha is
  never lit (drawn pixels always get alpha 255).
* Other light setups (:class:`Lights`, Habitat's ``LightInfo`` lists): each light ``k`` has
  a homogeneous vector ``(x, y, z, w)``: ``w = 0`` is a directional light shining *from*
  direction ``(x, y, z)`` (``l_k`` = that direction, normalized), ``w = 1`` a point light at
  ``(x, y, z)`` (``l_k = normalize(p_k - p)`` from the surface point ``p``, the face centroid
  or the vertex); an intensity ``c_k``; and a frame its vector is given in (world, camera or
  mesh, resolved with the camera and mesh poses of the frame)::

      light = clamp(ambient + sum_k c_k max(0, n . l_k), 0, 1)

  An empty setup is flat shading (``light = 1``, Habitat's ``NO_LIGHT_KEY``).

Colors travel packed as one ``uint32`` per pixel (``R | G << 8 | B << 16 | A << 24``: the
bytes R, G, B, A in memory) so that gathers are 1-D and cheap. Bilinear filtering and
lighting of packed colors use the classic SWAR trick of software renderers: the channel
pairs (R, B) and (G, A) are masked into two 16-bit lanes of a uint32 and multiplied by an
8-bit fixed-point weight ``W = round(256 f)`` at once: ``(p & 0x00FF00FF) * W >> 8``.
Weights are quantized to 1/256 (like GPU texture units): a result may differ from the
exact float formula by one level out of 255.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from render.raster import AttributePlanes, VisiblePixels
from render.settings import DEFAULT_SETTINGS, RenderSettings

#: rigidsim's default light setup (constants: a different setup is a :class:`Lights`)
AMBIENT = 0.4
DIFFUSE = 0.5
#: world-frame directions the 4 default lights travel along (unit vectors)
LIGHT_DIRECTIONS = np.array(
    [[1.0, -0.5, 0.0], [-1.0, -0.5, 0.0], [0.0, -0.5, 1.0], [0.0, -0.5, -1.0]]
) / np.sqrt(1.25)
#: frames a light vector may be given in (Habitat's LightPositionModel Global, Camera, Object)
LIGHT_FRAMES = ("world", "camera", "mesh")


@dataclass(frozen=True)
class Lights:
    """A light setup as plain arrays (see the module docstring).

    Attributes
    ----------
    vectors : (L, 4) float, ``(x, y, z, w)``: ``w = 0`` direction towards the light,
        ``w = 1`` light position.
    intensities : (L,) float, ``c_k`` (gray; Habitat's color, averaged over RGB upstream).
    frames : L entries of ``LIGHT_FRAMES``.
    ambient : float, added to every lit pixel (ignored when ``L == 0``: flat shading).
    """

    vectors: np.ndarray
    intensities: np.ndarray
    frames: tuple
    ambient: float = AMBIENT

    def __post_init__(self) -> None:
        vectors = np.asarray(self.vectors, dtype=np.float64).reshape(-1, 4)
        intensities = np.asarray(self.intensities, dtype=np.float64).reshape(-1)
        if len(intensities) != len(vectors) or len(self.frames) != len(vectors):
            raise ValueError("Lights needs one intensity and one frame per light vector")
        if not (np.all(np.isfinite(vectors)) and np.all(np.isfinite(intensities))):
            raise ValueError("light vectors and intensities must be finite")
        if not np.all((vectors[:, 3] == 0.0) | (vectors[:, 3] == 1.0)):
            raise ValueError("light vectors need w == 0 (directional) or w == 1 (point)")
        if any(frame not in LIGHT_FRAMES for frame in self.frames):
            raise ValueError(f"light frames must be in {LIGHT_FRAMES}, got {self.frames}")
        object.__setattr__(self, "vectors", vectors)
        object.__setattr__(self, "intensities", intensities)
        object.__setattr__(self, "frames", tuple(self.frames))

    @property
    def is_flat(self) -> bool:
        return len(self.vectors) == 0

    def in_world(
        self, world_from_camera: np.ndarray | None, world_from_mesh: np.ndarray | None
    ) -> np.ndarray:
        """The ``(L, 4)`` vectors in the world frame (camera / mesh frames resolved)."""
        out = self.vectors.copy()
        for k, frame in enumerate(self.frames):
            if frame == "camera" and world_from_camera is not None:
                out[k] = world_from_camera @ self.vectors[k]
            elif frame == "mesh" and world_from_mesh is not None:
                out[k] = world_from_mesh @ self.vectors[k]
        return out

    @property
    def has_mesh_frame(self) -> bool:
        return "mesh" in self.frames


def lambert_factors(
    normals_world: np.ndarray,
    points_world: np.ndarray | None,
    lights: Lights,
    world_vectors: np.ndarray,
) -> np.ndarray:
    """``clamp(ambient + sum_k c_k max(0, n . l_k), 0, 1)`` per row, ``(T,)`` float32.

    ``normals_world`` (T, 3) any length (zero: ambient only); ``points_world`` (T, 3) surface
    points for point lights; ``world_vectors`` (L, 4) the lights in the world frame.
    """
    if lights.is_flat:
        return np.ones(len(normals_world), dtype=np.float32)
    length = np.linalg.norm(normals_world, axis=1, keepdims=True)
    unit = np.divide(normals_world, length, out=np.zeros_like(normals_world), where=length > 0)
    total = np.zeros(len(unit))
    for vector, intensity in zip(world_vectors, lights.intensities, strict=True):
        if vector[3] == 0.0:  # directional: l = normalize(x, y, z)
            to_light = vector[:3] / max(np.linalg.norm(vector[:3]), 1e-300)
            n_dot_l = unit @ to_light
        else:  # point: l = normalize(p_light - p)
            offset = vector[:3] - points_world
            distance = np.linalg.norm(offset, axis=1)
            n_dot_l = np.einsum("ij,ij->i", unit, offset) / np.maximum(distance, 1e-300)
        total += intensity * np.maximum(n_dot_l, 0.0)
    return np.clip(lights.ambient + total, 0.0, 1.0).astype(np.float32)


_RB_MASK = np.uint32(0x00FF00FF)  # lanes holding R and B
_ALPHA = np.uint32(0xFF000000)
_U8 = np.uint32(8)


#: how a triangle is shaded (``MaterialTable.tri_kind``)
FLAT, VERTEX_COLOR, TEXTURED = 0, 1, 2


@dataclass
class MaterialTable:
    """Per-triangle and per-mesh material arrays of a scene (built by ``RenderScene``).

    T triangles, V vertices and M meshes, all meshes concatenated.

    Attributes
    ----------
    tri_mesh : (T,) int64, mesh index of each triangle.
    tri_base_packed : (T,) uint32, packed RGBA of each ``FLAT`` triangle (base color, times
        its vertex color when all 3 corners share one).
    tri_kind : (T,) int8: ``FLAT`` (one gather per pixel), ``VERTEX_COLOR`` (interpolated
        colors) or ``TEXTURED`` (texture sample times base / interpolated colors).
    faces : (3, T) int64, global vertex ids of each triangle's corners (corner-major).
    base_colors : (M, 4) float32 in [0, 1].
    has_vertex_colors : (M,) bool.
    vertex_colors : (4, V) float32 in [0, 1], premultiplied by the mesh's base color (the
        base color itself for meshes without), or None if no mesh has vertex colors.
    uvs : (2, V) float32 (zeros for meshes without), or None if no mesh is textured.
    textures : M entries, ``(h + 2, w + 2)`` uint32 packed RGBA (row 0 = top) with the
        wrap border of ``pad_texture_wrap``, or None.
    uv_origins : M entries, ``"bottom"`` or ``"top"`` (see module docstring).
    """

    tri_mesh: np.ndarray
    tri_base_packed: np.ndarray
    tri_kind: np.ndarray
    faces: np.ndarray
    base_colors: np.ndarray
    has_vertex_colors: np.ndarray
    vertex_colors: np.ndarray | None
    uvs: np.ndarray | None
    textures: list
    uv_origins: list

    def of_triangles(self, triangles: np.ndarray) -> MaterialTable:
        """The table of the triangles ``triangles`` (global ids) only: their per-triangle
        rows, renumbered ``0 .. len(triangles) - 1`` (per-mesh and per-vertex arrays are
        shared). A frame shades its candidates with it: pixels index it by candidate, so
        no per-pixel lookup of global triangle ids is needed."""
        return dataclasses.replace(
            self,
            tri_mesh=self.tri_mesh[triangles],
            tri_base_packed=self.tri_base_packed[triangles],
            tri_kind=self.tri_kind[triangles],
            faces=self.faces[:, triangles],
        )


def pack_rgba(rgba: np.ndarray) -> np.ndarray:
    """Pack ``(..., 4)`` uint8 RGBA into ``(...)`` uint32 (bytes R, G, B, A in memory)."""
    rgba = np.ascontiguousarray(rgba, dtype=np.uint8)
    return rgba.view("<u4")[..., 0].astype(np.uint32)


def unpack_rgba(packed: np.ndarray) -> np.ndarray:
    """Inverse of ``pack_rgba``: ``(...)`` uint32 to ``(..., 4)`` uint8."""
    packed = np.ascontiguousarray(packed, dtype="<u4")
    return packed[..., None].view(np.uint8)


#: rigidsim's default setup as :class:`Lights`: the 4 directional lights (shining from
#: ``-d_k``) of intensity ``DIFFUSE`` and ambient ``AMBIENT`` (``face_light_factors``).
DEFAULT_LIGHTS = Lights(
    np.hstack([-LIGHT_DIRECTIONS, np.zeros((4, 1))]), np.full(4, DIFFUSE), ("world",) * 4, AMBIENT
)


def face_light_factors(normals_world: np.ndarray) -> np.ndarray:
    """Lambert factor of Habitat's default light setup per face, ``(T,)`` float32.

    Parameters
    ----------
    normals_world : (T, 3) float, face normals in the world frame (any length; zero-length
        normals, from degenerate faces, get the ambient term only).
    """
    length = np.linalg.norm(normals_world, axis=1, keepdims=True)
    unit = np.divide(normals_world, length, out=np.zeros_like(normals_world), where=length > 0)
    n_dot_l = unit @ (-LIGHT_DIRECTIONS.T)  # (T, 4): n . l_k with l_k = -d_k (towards the light)
    light = AMBIENT + DIFFUSE * np.maximum(n_dot_l, 0.0).sum(axis=1)
    return np.clip(light, 0.0, 1.0).astype(np.float32)  # clamp(ambient + k sum max(0, n.l), 0, 1)


def _fixed_weight(f: np.ndarray) -> np.ndarray:
    """Weights in [0, 1] as 8-bit fixed point ``round(256 f)`` in [0, 256], uint32."""
    return np.rint(f * np.float32(256.0)).astype(np.uint32)


def modulate_packed(packed: np.ndarray, factor: np.ndarray) -> np.ndarray:
    """Scale the RGB bytes of packed colors by ``factor`` in [0, 1]; alpha is kept.

    ``packed`` (n,) uint32, ``factor`` (n,) float. SWAR: ``c' = (c W + 128) >> 8`` per lane.
    """
    weight = _fixed_weight(np.asarray(factor, dtype=np.float32))
    rb = ((packed & _RB_MASK) * weight + np.uint32(0x00800080)) >> _U8 & _RB_MASK  # R, B lanes
    g = (((packed >> _U8) & np.uint32(0xFF)) * weight + np.uint32(0x80)) >> _U8  # G alone
    return rb | (g << _U8) | (packed & _ALPHA)


def pad_texture_wrap(texture_packed: np.ndarray) -> np.ndarray:
    """Add a one-texel border copied from the opposite edges (REPEAT wrap), ``(h+2, w+2)``.

    With the border, the four texels around any sample are neighbors in memory and need no
    modulo: ``sample_bilinear`` expects textures padded this way.
    """
    return np.pad(texture_packed, 1, mode="wrap")


def sample_bilinear(
    texture_padded: np.ndarray, u: np.ndarray, v: np.ndarray, uv_origin: str
) -> np.ndarray:
    """Bilinear texture lookup with wrap-around (REPEAT), returning packed RGBA ``(n,)``.

    Texel-center coordinates ``col = u w - 1/2`` and ``row = v' h - 1/2`` are computed in
    8-bit fixed point: ``(col + 1) * 256`` rounded to an int gives the padded column of the
    left texel (``>> 8``) and the weight of the right one (``& 255``, in 1/256).

    Parameters
    ----------
    texture_padded : (h + 2, w + 2) uint32, packed RGBA texels (row 0 = top of the image)
        with the wrap border of ``pad_texture_wrap``.
    u, v : (n,) float32 texture coordinates (u right, v per ``uv_origin``).
    uv_origin : ``"bottom"`` (v = 0 is the bottom row, trimesh/OpenGL) or ``"top"`` (glTF).
    """
    h, w = texture_padded.shape[0] - 2, texture_padded.shape[1] - 2
    if uv_origin == "bottom":
        v = np.float32(1.0) - v  # image rows go down
    u, v = u - np.floor(u), v - np.floor(v)  # REPEAT: keep the fractional part, in [0, 1)
    # (col + 1) 256 = u w 256 + 128, rounded to nearest (+ 0.5 before truncating)
    col_fixed = (u * np.float32(256 * w) + np.float32(128.5)).astype(np.int32)
    row_fixed = (v * np.float32(256 * h) + np.float32(128.5)).astype(np.int32)
    stride = w + 2
    # top-left texel in the padded image; intp indices: NumPy converts others before gathers
    index = (row_fixed >> 8).astype(np.intp) * stride + (col_fixed >> 8)
    wc, wr = (col_fixed & 255).astype(np.uint32), (row_fixed & 255).astype(np.uint32)
    flat = texture_padded.ravel()
    top = _lerp_packed(flat[index], flat[index + 1], wc)  # along u on the upper row
    below = index + stride
    bottom = _lerp_packed(flat[below], flat[below + 1], wc)  # along u on the lower row
    return _lerp_packed(top, bottom, wr)  # along v


def _lerp_packed(p: np.ndarray, q: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """Per-channel ``p + (q - p) W / 256`` of packed colors, as ``(p (256 - W) + q W) >> 8``."""
    inv = np.uint32(256) - weight
    rb = ((p & _RB_MASK) * inv + (q & _RB_MASK) * weight + np.uint32(0x00800080)) >> _U8
    ga = ((p >> _U8) & _RB_MASK) * inv + ((q >> _U8) & _RB_MASK) * weight + np.uint32(0x00800080)
    return (rb & _RB_MASK) | (ga & ~_RB_MASK)  # ga lanes are already shifted up by 8 bits


def sample_bilinear_fast(
    texture_padded: np.ndarray, u: np.ndarray, v: np.ndarray, uv_origin: str
) -> np.ndarray:
    """``sample_bilinear`` with in-place arithmetic: the same bits, fewer temporaries.

    The same fixed-point texel coordinates and the same three packed lerps, but every step
    writes into buffers allocated once per call (``out=``, augmented assignments), which
    roughly halves the memory traffic of the plain version. ``u`` and ``v`` are not modified.
    """
    h, w = texture_padded.shape[0] - 2, texture_padded.shape[1] - 2
    u = np.array(u, dtype=np.float32)  # working copies
    v = np.subtract(np.float32(1.0), v) if uv_origin == "bottom" else np.array(v, np.float32)
    fraction_base = np.floor(u)
    u -= fraction_base  # REPEAT: u - floor(u) in [0, 1)
    np.floor(v, out=fraction_base)
    v -= fraction_base
    u *= np.float32(256 * w)
    u += np.float32(128.5)  # (col + 1) 256 + 0.5, truncated below
    v *= np.float32(256 * h)
    v += np.float32(128.5)
    col_fixed, row_fixed = u.astype(np.int32), v.astype(np.int32)
    stride = w + 2
    index = (row_fixed >> 8).astype(np.intp)
    index *= stride
    index += col_fixed >> 8  # top-left texel in the padded image
    col_fixed &= 255
    row_fixed &= 255
    wc, wr = col_fixed.view(np.uint32), row_fixed.view(np.uint32)  # weights in [0, 255]
    inv_c, inv_r = np.uint32(256) - wc, np.uint32(256) - wr
    flat = texture_padded.ravel()
    scratch = np.empty(len(index), dtype=np.uint32)
    top = _lerp_packed_into(flat.take(index), flat.take(index + 1), wc, inv_c, scratch)
    index += stride  # the row below
    left = flat.take(index)
    index += 1
    bottom = _lerp_packed_into(left, flat.take(index), wc, inv_c, scratch)
    return _lerp_packed_into(top, bottom, wr, inv_r, scratch)


_HALF_LANES = np.uint32(0x00800080)  # 128 in each 16-bit lane: round to nearest


def _lerp_packed_into(
    p: np.ndarray, q: np.ndarray, weight: np.ndarray, inv: np.ndarray, scratch: np.ndarray
) -> np.ndarray:
    """``_lerp_packed(p, q, weight)`` (``inv = 256 - weight``) computed in place: the result
    is written into ``p`` and returned; ``q`` and ``scratch`` are overwritten."""
    np.right_shift(p, _U8, out=scratch)
    scratch &= _RB_MASK
    scratch *= inv  # (G, A) of p times (256 - W)
    ga = np.right_shift(q, _U8)
    ga &= _RB_MASK
    ga *= weight
    ga += scratch
    ga += _HALF_LANES
    ga &= ~_RB_MASK  # (G, A) lanes, already shifted up by 8 bits
    p &= _RB_MASK
    p *= inv
    q &= _RB_MASK
    q *= weight
    p += q
    p += _HALF_LANES
    p >>= _U8
    p &= _RB_MASK  # (R, B) lanes
    p |= ga
    return p


def modulate_packed_inplace(packed: np.ndarray, factor: np.ndarray) -> None:
    """``packed[:] = modulate_packed(packed, factor)`` with fewer temporaries."""
    weight = _fixed_weight(np.asarray(factor, dtype=np.float32))
    g = np.right_shift(packed, _U8)
    g &= np.uint32(0xFF)
    g *= weight
    g += np.uint32(0x80)
    g >>= _U8
    g <<= _U8  # G lane
    alpha = packed & _ALPHA
    packed &= _RB_MASK
    packed *= weight
    packed += _HALF_LANES
    packed >>= _U8
    packed &= _RB_MASK  # R, B lanes
    packed |= g
    packed |= alpha


def shade_pixels(
    materials: MaterialTable,
    visible: VisiblePixels,
    triangle: np.ndarray,
    uv_planes: AttributePlanes | None,
    color_planes: AttributePlanes | None,
    light: np.ndarray | None,
    settings: RenderSettings = DEFAULT_SETTINGS,
) -> np.ndarray:
    """Deferred shading of visible pixels, returning packed RGBA ``(n,)`` uint32, alpha 255.

    Parameters
    ----------
    materials : the scene's ``MaterialTable``.
    visible : the resolved pixels (``visible.winner`` indexes the attribute planes).
    triangle : (n,) int64, each pixel's triangle: its row in ``materials`` (the scene's
        global id, or a candidate's index in ``materials.of_triangles(candidates)``).
    uv_planes, color_planes : interpolators of uvs and vertex colors of the rasterized
        triangles, or None when no mesh is textured / vertex-colored.
    light : (n,) float32 light factor per pixel (1 = unlit), or None if nothing is lit.
    settings : ``fast_shading`` selects the kernels (same bits), ``light_all_above`` and
        ``sample_all_above`` when the fast ones work on every pixel.
    """
    fast = settings.fast_shading
    kind = materials.tri_kind[triangle]
    textured_meshes = [i for i, t in enumerate(materials.textures) if t is not None]
    if fast and len(textured_meshes) == 1 and len(kind) and kind.min() == TEXTURED:
        # every pixel samples the one texture (TEXTURED is the largest kind): no selections
        uvs = _needed(uv_planes, "uv_planes")
        packed = _textured_colors(materials, textured_meshes[0], visible, uvs, color_planes, fast)
        return _lit_and_opaque(packed, light, settings)
    packed = materials.tri_base_packed[triangle]  # flat triangles: one gather
    blended = np.flatnonzero(kind == VERTEX_COLOR)
    if len(blended):  # premultiplied base * sum_k b_k c_k
        colors = _needed(color_planes, "color_planes")
        color = colors.evaluate(visible.subset(blended)).T * np.float32(255.0)
        packed[blended] = pack_rgba(np.clip(np.rint(color), 0, 255).astype(np.uint8))
    is_textured = kind == TEXTURED
    if fast and len(textured_meshes) == 1:
        if np.count_nonzero(is_textured) >= settings.sample_all_above * len(kind):
            # mostly one texture: sample it at every pixel (no subset gathers, no scatter)
            # and keep the samples of the textured pixels only
            uvs = _needed(uv_planes, "uv_planes")
            mesh = textured_meshes[0]
            texel = _textured_colors(materials, mesh, visible, uvs, color_planes, fast)
            np.copyto(packed, texel, where=is_textured)
            return _lit_and_opaque(packed, light, settings)
    textured = np.flatnonzero(is_textured)
    if len(textured):
        uvs = _needed(uv_planes, "uv_planes")
        mesh_of_pixel = materials.tri_mesh[triangle[textured]] if len(textured_meshes) > 1 else None
        for mesh in textured_meshes:  # one texture at a time
            sel = textured if mesh_of_pixel is None else textured[mesh_of_pixel == mesh]
            if len(sel):
                subset = visible if len(sel) == len(triangle) else visible.subset(sel)
                packed[sel] = _textured_colors(materials, mesh, subset, uvs, color_planes, fast)
    return _lit_and_opaque(packed, light, settings)


def _needed(planes: AttributePlanes | None, name: str) -> AttributePlanes:
    """``planes``, which the caller passes whenever a pixel of that kind is visible."""
    if planes is None:
        raise ValueError(f"shade_pixels: {name} is None but a visible pixel needs it")
    return planes


def _lit_and_opaque(
    packed: np.ndarray, light: np.ndarray | None, settings: RenderSettings
) -> np.ndarray:
    """Apply the light factors to packed colors (in place) and set alpha 255."""
    if light is not None:
        is_lit = light < 1.0
        n_lit = np.count_nonzero(is_lit)
        if settings.fast_shading and n_lit >= settings.light_all_above * len(light):
            modulate_packed_inplace(packed, light)  # W = 256 where light == 1: unchanged
        else:
            lit = np.flatnonzero(is_lit)
            packed[lit] = modulate_packed(packed[lit], light[lit])
    packed |= _ALPHA  # alpha 255 where drawn
    return packed


def _textured_colors(
    materials: MaterialTable,
    mesh: int,
    visible: VisiblePixels,
    uv_planes: AttributePlanes,
    color_planes: AttributePlanes | None,
    fast: bool,
) -> np.ndarray:
    """Packed colors of the pixels of one textured mesh: texture * base (* vertex color)."""
    u, v = uv_planes.evaluate(visible)
    sample = sample_bilinear_fast if fast else sample_bilinear
    texel = sample(materials.textures[mesh], u, v, materials.uv_origins[mesh])
    if materials.has_vertex_colors[mesh]:
        factor = (
            _needed(color_planes, "color_planes").evaluate(visible).T
        )  # premultiplied base * vertex color, (n, 4)
    elif materials.base_colors[mesh].tolist() == [1.0, 1.0, 1.0, 1.0]:
        return texel  # the common case: a plain textured mesh
    else:
        factor = materials.base_colors[mesh]
    color = unpack_rgba(texel).astype(np.float32) * factor  # texture * base * vertex color
    return pack_rgba(np.clip(np.rint(color), 0, 255).astype(np.uint8))
