"""Shading: the color of each visible pixel from its triangle, attributes and material.

Shading is *deferred*: the rasterizer first finds, per pixel, the nearest triangle and its
depth; each visible pixel is then shaded exactly once here. Perspective-correct vertex
attributes (uvs, vertex colors) come from ``render.resolve.AttributePlanes``; ``b`` below
are the perspective-correct barycentrics of the pixel center.

Color of a pixel (all factors in [0, 1], RGBA)::

    color = base_color * vertex_color(b) * texture(uv(b)) * light

* ``vertex_color(b) = sum_k b_k c_k`` (1 if the mesh has no vertex colors).
* ``uv(b) = sum_k b_k uv_k``; ``texture`` samples bilinearly between the four nearest texel
  centers, wrapping (glTF's default REPEAT). Texel ``(i, j)`` has its center at
  ``u = (j + 0.5) / w`` and, for ``uv_origin="bottom"`` (trimesh and OpenGL: v = 0 is the
  bottom row of the image), ``v = 1 - (i + 0.5) / h``; for ``uv_origin="top"`` (the glTF
  file convention) ``v = (i + 0.5) / h``.
* ``light = 1`` for unlit meshes (Habitat draws the stage flat); for lit meshes the
  Lambert factor of their light setup (:mod:`render.lights`),
  ``clamp(ambient + sum_k c_k max(0, n . l_k), 0, 1)``, on the flat face normal, or, for
  meshes given vertex normals, computed per vertex and interpolated perspective-correctly
  (Gouraud shading). Alpha is never lit (drawn pixels always get alpha 255).

The colors are computed as packed 8-bit
RGBA with the fixed-point kernels of :mod:`render.packed_rgba` (within one level of 255 of
the float formula, the textbook version in :func:`render.reference.fragment_color`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from render.lights import (
    AMBIENT,
    DEFAULT_LIGHTS,
    DIFFUSE,
    LIGHT_DIRECTIONS,
    LIGHT_FRAMES,
    Lights,
    face_light_factors,
    lambert_factors,
)
from render.packed_rgba import (
    modulate_packed,
    modulate_packed_inplace,
    pack_rgba,
    pad_texture_wrap,
    sample_bilinear,
    sample_bilinear_fast,
    unpack_rgba,
)
from render.resolve import AttributePlanes, VisiblePixels
from render.settings import DEFAULT_SETTINGS, RenderSettings

__all__ = [  # the light setups and packed colors are re-exported: render.shade.Lights ...
    "AMBIENT",
    "DEFAULT_LIGHTS",
    "DIFFUSE",
    "FLAT",
    "LIGHT_DIRECTIONS",
    "LIGHT_FRAMES",
    "Lights",
    "MaterialTable",
    "TEXTURED",
    "VERTEX_COLOR",
    "face_light_factors",
    "lambert_factors",
    "modulate_packed",
    "pack_rgba",
    "pad_texture_wrap",
    "sample_bilinear",
    "sample_bilinear_fast",
    "shade_pixels",
    "unpack_rgba",
]

_ALPHA = np.uint32(0xFF000000)

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
