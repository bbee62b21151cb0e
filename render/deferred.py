"""Stages 7 and 8 of ``render_frame``: deferred shading of the visible pixels.

After rasterization (stages 1-6) the z-buffer holds, per pixel, the nearest candidate
triangle and its depth. Stage 7 (``ShadingInputs.build``) prepares, per candidate triangle,
what shading needs: its material rows (``MaterialTable.of_triangles``: pixels index them by
candidate), semantic id, perspective-correct attribute planes (uvs, vertex colors,
Gouraud light; ``render.resolve.AttributePlanes``) and flat light factors
(``render.lights``). Stage 8 (``write_band``) shades each band of resolved pixels once
(``render.shade.shade_pixels``) and writes color, depth and ids, the background where
nothing was drawn.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from render import cull, raster
from render.buffers import FrameBuffers
from render.packed_rgba import pack_rgba
from render.resolve import AttributePlanes, VisiblePixels
from render.scene import RenderScene
from render.settings import DEFAULT_SETTINGS, RenderSettings
from render.shade import MaterialTable, shade_pixels

#: color of pixels where nothing is drawn (opaque black, like Habitat's default clear color)
BACKGROUND_RGBA = (0, 0, 0, 255)
_BACKGROUND_PACKED = pack_rgba(np.array(BACKGROUND_RGBA, np.uint8))


def triangle_corners(
    vertices_camera: np.ndarray, scene: RenderScene, triangles: np.ndarray
) -> np.ndarray:
    """Camera-frame corners of global triangles ``triangles``: ``(3 corners, 3 coords, n)``."""
    return vertices_camera[:, scene.materials.faces[:, triangles]].transpose(1, 0, 2)


@dataclass
class ShadingInputs:
    """Per candidate triangle (K of them, global ids ``tri_index``): materials, semantic
    ids, attribute planes and light factors, all indexed by candidate.

    ``tri_light`` (K,) is the flat light factor (1 for unlit and Gouraud triangles);
    ``light_planes`` interpolates per-vertex light over the Gouraud triangles
    (``is_smooth`` (K,) marks them).
    """

    materials: MaterialTable  # of the candidates: row k is candidate k (tri_index[k])
    semantic: np.ndarray | None  # (K,) semantic id of each candidate (None: no ids written)
    uv_planes: AttributePlanes | None
    color_planes: AttributePlanes | None
    tri_light: np.ndarray | None
    light_planes: AttributePlanes | None
    is_smooth: np.ndarray | None
    settings: RenderSettings = DEFAULT_SETTINGS  # the kernels shade_pixels uses

    @classmethod
    def build(
        cls,
        scene,
        camera,
        camera_from_world,
        vertices_camera,
        tri_index,
        used,
        ids=True,
        settings: RenderSettings = DEFAULT_SETTINGS,
    ):
        """For the candidates ``used`` (indices into the K candidates ``tri_index``; all of
        them, or those that can own pixels): attribute planes and light factors."""
        materials = scene.materials
        row_of = None  # candidate id -> row among the used triangles (None: identity)
        if len(used) < len(tri_index):
            row_of = np.zeros(len(tri_index), dtype=np.int64)
            row_of[used] = np.arange(len(used))
        tri = triangle_corners(vertices_camera, scene, tri_index[used])  # (3, 3, k)
        planes, _ = raster.plane_coefficients(tri, camera)
        corners = materials.faces[:, tri_index[used]]  # (3, k) global vertex ids

        def interpolator(values: np.ndarray | None) -> AttributePlanes | None:
            if values is None:  # values: (C, V) per-vertex attribute
                return None
            corner_values = values[:, corners].transpose(1, 0, 2)  # (3 corners, C, k)
            paired = settings.paired_attributes
            return AttributePlanes(planes, corner_values, camera, row_of, paired)

        tri_light = light_planes = is_smooth = None
        lit = scene.tri_lit[tri_index[used]]
        if lit.any():
            smooth = scene.tri_smooth[tri_index[used]]
            # flat: face normals, camera frame -> world frame: n_w = R_cw^T n_c
            normal_camera = np.array(cull.cross(tri[1] - tri[0], tri[2] - tri[0]))
            normal_world = (camera_from_world[:3, :3].T @ normal_camera).T  # (k, 3)
            # face centroids in the world (point lights): p_w = R_cw^T (p_c - t_cw)
            centroid_camera = (tri[0] + tri[1] + tri[2]) / 3.0  # (3, k)
            world_from_camera = np.linalg.inv(camera_from_world)
            centroid_world = (world_from_camera[:3, :3] @ centroid_camera).T + world_from_camera[
                :3, 3
            ]
            factors = scene.face_light_factors(
                tri_index[used], normal_world, centroid_world, world_from_camera
            )
            tri_light = np.ones(len(tri_index), dtype=np.float32)
            tri_light[used] = np.where(lit & ~smooth, factors, 1.0)
            if smooth.any():  # Gouraud: light per vertex, interpolated
                light_planes = interpolator(scene.vertex_light_factors(world_from_camera))
                is_smooth = np.zeros(len(tri_index), dtype=bool)
                is_smooth[used] = smooth
        return cls(
            materials.of_triangles(tri_index),
            scene.tri_semantic[tri_index] if ids else None,
            interpolator(materials.uvs),
            interpolator(materials.vertex_colors),
            tri_light,
            light_planes,
            is_smooth,
            settings,
        )

    def pixel_light(self, visible: VisiblePixels) -> np.ndarray | None:
        """Light factor of each visible pixel ``(n,)`` float32, or None if nothing is lit."""
        if self.tri_light is None:
            return None
        light = self.tri_light[visible.winner]
        if self.light_planes is not None and self.is_smooth is not None:  # set together
            sel = np.flatnonzero(self.is_smooth[visible.winner])
            gouraud = self.light_planes.evaluate(visible.subset(sel))[0]
            light[sel] = np.clip(gouraud, 0.0, 1.0)
        return light


def write_band(
    out: FrameBuffers,
    shading: ShadingInputs,
    visible: VisiblePixels,
    band: slice,
) -> None:
    """Shade the visible pixels of one band and write rgba, depth and ids there."""
    rgba_packed = out.rgba.reshape(-1, 4).view("<u4")[:, 0]  # one packed RGBA per pixel
    depth_flat, ids_flat = out.depth.reshape(-1), out.ids.reshape(-1)
    n_covered = len(visible.pixel)
    if n_covered < band.stop - band.start:  # background first where nothing is drawn
        rgba_packed[band], depth_flat[band] = _BACKGROUND_PACKED, 0.0
        if shading.semantic is not None:
            ids_flat[band] = 0
        if n_covered == 0:
            return
    where = band if n_covered == band.stop - band.start else visible.pixel  # slice: no scatter
    write_pixels(out, shading, visible, where)


def write_pixels(
    out: FrameBuffers,
    shading: ShadingInputs,
    visible: VisiblePixels,
    where: slice | np.ndarray | None = None,
) -> None:
    """Shade ``visible`` pixels and write rgba, depth and ids at ``where`` (default: their
    flat indices ``visible.pixel``)."""
    rgba_packed = out.rgba.reshape(-1, 4).view("<u4")[:, 0]  # one packed RGBA per pixel
    depth_flat, ids_flat = out.depth.reshape(-1), out.ids.reshape(-1)
    candidate = visible.winner  # the candidate triangle of each covered pixel
    light = shading.pixel_light(visible)
    packed = shade_pixels(
        shading.materials,
        visible,
        candidate,
        shading.uv_planes,
        shading.color_planes,
        light,
        shading.settings,
    )
    where = visible.pixel if where is None else where
    rgba_packed[where], depth_flat[where] = packed, visible.depth
    if shading.semantic is not None:
        ids_flat[where] = shading.semantic[candidate]
