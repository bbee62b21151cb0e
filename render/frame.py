"""``render_frame``: the whole rendering pipeline of one camera image, on one screen.

Stages: (1) vertices to the camera frame, (2) frustum culling with vertex outcodes; then,
per batch of ``settings.triangle_batch`` triangles, (3) back-face culling (optional) and near-plane
clipping, (4) triangle setup (perspective-correct plane functions) and projection,
(5) scanline spans, (6) fragments and depth test into a 64-bit z-buffer; finally
(7) shading setup (attribute planes, light factors) for the triangles that drew fragments
and (8) per band of rows: resolve (winning triangle and depth per pixel), deferred shading,
semantic ids (stages 7-8 live in ``render.deferred``). See ``render.cull``, ``render.raster``,
``render.resolve`` and ``render.shade`` for the equations; ``FrameBuffers.timings`` reports
the wall time of each stage.

Outputs follow Habitat's sensors: ``rgba (H, W, 4) uint8`` (alpha 255 where drawn, the
background ``BACKGROUND_RGBA`` = opaque black elsewhere), ``depth (H, W) float32`` z-depth
in meters (0 where nothing is drawn), ``ids (H, W) uint32`` semantic ids (0 where nothing
is drawn). Row 0 is the top of the image. Both faces of every triangle are drawn unless
``cull_back_faces=True``.

Static layers: ``StaticLayer.from_frame(render_frame(static_meshes, ...))`` keeps a frame of
the meshes that do not move; ``render_over_layer(layer, moving_meshes, ...)`` then rasterizes
only the moving meshes, depth-tested against the kept depths, and returns bit for bit what
``render_frame(static_meshes + moving_meshes, ...)`` returns (same camera, pose, culling).

Settings: ``settings`` (a frozen :class:`render.settings.RenderSettings`) sizes the batches,
chunks and bands and selects the fast or the plain kernels; every choice gives the same
pixels.

Performance: pass a ``RenderScene`` (built once, poses updated per frame) rather than a list
of meshes, and pass the previous ``FrameBuffers`` back as ``buffers`` to reuse its memory
(the returned arrays are then overwritten by the next call: copy them to keep them).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from render import cull, raster, resolve
from render.buffers import FrameBuffers
from render.camera import Camera, invert_rigid
from render.deferred import (
    BACKGROUND_RGBA,
    ShadingInputs,
    triangle_corners,
    write_band,
    write_pixels,
)
from render.scene import RenderMesh, RenderScene
from render.settings import DEFAULT_SETTINGS, RenderSettings

_HIGH32 = np.uint64(0xFFFFFFFF00000000)

__all__ = [
    "BACKGROUND_RGBA",
    "FrameBuffers",
    "RenderMesh",
    "RenderScene",
    "RenderSettings",
    "StaticLayer",
    "render_frame",
    "render_over_layer",
]


def render_frame(
    meshes: RenderScene | Sequence[RenderMesh],
    camera: Camera,
    world_from_camera: np.ndarray,
    buffers: FrameBuffers | None = None,
    cull_back_faces: bool = False,
    rows: tuple[int, int] | None = None,
    ids: bool = True,
    settings: RenderSettings = DEFAULT_SETTINGS,
) -> FrameBuffers:
    """Render color, depth and semantic ids of ``meshes`` seen by ``camera``.

    Parameters
    ----------
    meshes : a ``RenderScene`` (fast: cached arrays) or a list of ``RenderMesh``.
    camera : intrinsics and clip planes.
    world_from_camera : (4, 4) float64 camera pose (camera looks down its local -Z, +Y up).
    buffers : buffers of a previous call with the same resolution to reuse, or None.
    cull_back_faces : skip triangles whose counter-clockwise front faces away from the eye.
    rows : ``(first, end)``: rasterize, shade and write only image rows ``first .. end - 1``
        (whole bands of ``band_rows(camera, settings)`` rows, or the last row), leaving the
        other rows of the buffers untouched. Every row is rasterized on its own (its spans and depth
        tests depend on no other row), so these rows get exactly the pixels of a whole
        frame: two processes can each render a part of one frame.
    ids : also write the semantic ids (False: ``ids`` keeps what it held; for cameras
        without a semantic sensor, one gather and one write a pixel fewer).
    settings : batch, chunk and band sizes and the kernels (same pixels for all).

    Returns
    -------
    FrameBuffers with ``rgba``, ``depth``, ``ids`` filled (``buffers`` itself if given).
    """
    if not isinstance(camera, Camera):
        raise TypeError(f"camera must be a render.Camera, got {type(camera).__name__}")
    _check_settings(settings)
    bands = _row_bands(camera, settings) if rows is None else _bands_of_rows(camera, rows, settings)
    rows = None if rows is None else (int(rows[0]), int(rows[1]))  # checked just above
    scene = meshes if isinstance(meshes, RenderScene) else RenderScene(meshes)
    camera_from_world = invert_rigid(world_from_camera)
    out = _prepare_buffers(buffers, camera)
    clock = _StageClock(out.timings)
    # the z-buffer of the rows drawn (the others are neither written nor read)
    zkey_drawn = out.zkey
    if rows is not None:
        zkey_drawn = out.zkey[rows[0] * camera.width : rows[1] * camera.width]
    zkey_drawn.fill(resolve.EMPTY_KEY)
    vertices_camera, tri_index, drawn = _rasterize_scene(
        scene, camera, camera_from_world, cull_back_faces, out, clock, 0, rows, settings
    )
    # --- 7. shading inputs (attribute planes, light) of the triangles that can own pixels
    if len(tri_index) <= settings.refine_used_above:
        used = np.arange(len(tri_index))  # few candidates: planes for all, no indirection
    else:
        used = np.flatnonzero(drawn)
        if len(used) > settings.refine_used_above:  # many small triangles: the pixel winners
            used = resolve.winning_triangles(zkey_drawn, len(tri_index))
    shading = ShadingInputs.build(
        scene, camera, camera_from_world, vertices_camera, tri_index, used, ids, settings
    )
    clock.lap("shade setup")
    # --- 8. resolve and deferred shading, one band of rows at a time (cache-sized)
    for band in bands:
        visible = resolve.resolve_depth(out.zkey, camera, band, settings.pixel_center_tables)
        write_band(out, shading, visible, band)
    clock.lap("shade")
    return out


@dataclass
class StaticLayer:
    """A rendered frame of the static meshes, kept to draw moving meshes over it.

    Valid only for the camera (intrinsics and pose), the static meshes and their poses and
    the lights it was rendered with: the caller decides when that holds (the engine checks
    it exactly, see ``engine.sensors.scene_render``). ``render_over_layer`` then rasterizes only the
    moving meshes, depth-tested against ``seed``.

    Attributes
    ----------
    rgba, depth, ids : copies of the static frame's buffers.
    seed : (H * W,) uint64 z-buffer to start from: ``depth bits << 32`` (id 0) where a
        static mesh is drawn, ``resolve.EMPTY_KEY`` elsewhere.
    """

    rgba: np.ndarray
    depth: np.ndarray
    ids: np.ndarray
    seed: np.ndarray

    @classmethod
    def from_frame(cls, frame: FrameBuffers) -> StaticLayer:
        """The layer of a frame just rendered by ``render_frame`` (its buffers are copied)."""
        drawn = frame.zkey != resolve.EMPTY_KEY
        seed = np.where(drawn, frame.zkey & _HIGH32, resolve.EMPTY_KEY)  # keep the depth bits
        return cls(frame.rgba.copy(), frame.depth.copy(), frame.ids.copy(), seed)

    @property
    def resolution(self) -> tuple[int, int]:
        """``(H, W)`` of the layer."""
        return self.depth.shape


def render_over_layer(
    layer: StaticLayer,
    meshes: RenderScene | Sequence[RenderMesh],
    camera: Camera,
    world_from_camera: np.ndarray,
    buffers: FrameBuffers | None = None,
    cull_back_faces: bool = False,
    settings: RenderSettings = DEFAULT_SETTINGS,
) -> FrameBuffers:
    """Draw ``meshes`` over a static layer: the frame ``render_frame`` gives for the layer's
    static meshes followed by ``meshes``, bit for bit.

    Only ``meshes`` are rasterized; their fragments are depth-tested against the layer's
    depths (``layer.seed``). On equal depths the static pixel wins, as the lower triangle
    index wins in ``render_frame`` (static meshes come first). Every pixel a moving mesh
    won is shaded exactly as ``render_frame`` shades it (shading depends only on the pixel
    and its triangle); every other pixel is the layer's.

    Parameters are those of ``render_frame``, plus ``layer`` (from ``StaticLayer.from_frame``
    of a ``render_frame`` of the static meshes with the same camera, pose and culling).
    """
    if not isinstance(layer, StaticLayer):
        raise TypeError(f"layer must be a StaticLayer, got {type(layer).__name__}")
    if not isinstance(camera, Camera):
        raise TypeError(f"camera must be a render.Camera, got {type(camera).__name__}")
    if layer.resolution != camera.resolution:
        raise ValueError(
            f"layer resolution {layer.resolution} differs from the camera's {camera.resolution}"
        )
    _check_settings(settings)
    scene = meshes if isinstance(meshes, RenderScene) else RenderScene(meshes)
    camera_from_world = invert_rigid(world_from_camera)
    out = _prepare_buffers(buffers, camera)
    clock = _StageClock(out.timings)
    np.copyto(out.zkey, layer.seed)
    # --- 1-6 for the moving meshes only; ids start at 1 so that id 0 (static) wins ties
    vertices_camera, tri_index, drawn = _rasterize_scene(
        scene, camera, camera_from_world, cull_back_faces, out, clock, 1, None, settings
    )
    np.copyto(out.rgba, layer.rgba)
    np.copyto(out.depth, layer.depth)
    np.copyto(out.ids, layer.ids)
    changed = np.flatnonzero(out.zkey != layer.seed)  # pixels a moving mesh won
    clock.lap("layer")
    if len(changed) == 0:
        return out
    # --- 7. shading inputs of the candidates that drew fragments
    few = len(tri_index) <= settings.refine_used_above
    used = np.arange(len(tri_index)) if few else np.flatnonzero(drawn)
    shading = ShadingInputs.build(
        scene, camera, camera_from_world, vertices_camera, tri_index, used, True, settings
    )
    clock.lap("shade setup")
    # --- 8. resolve and shade the changed pixels, a cache-sized run at a time
    run = settings.shade_band_pixels
    for start in range(0, len(changed), run):
        pixel = changed[start : start + run]
        visible = resolve.visible_from_keys(
            out.zkey[pixel], pixel, camera, 1, settings.pixel_center_tables
        )
        write_pixels(out, shading, visible)
    clock.lap("shade")
    return out


def _rasterize_scene(
    scene: RenderScene,
    camera: Camera,
    camera_from_world: np.ndarray,
    cull_back_faces: bool,
    out: FrameBuffers,
    clock: _StageClock,
    key_offset: int,
    rows: tuple[int, int] | None,
    settings: RenderSettings,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Stages 1-6: depth-test every fragment of ``scene`` into ``out.zkey`` (not cleared).

    The key of a fragment of candidate ``k`` carries the id ``k + key_offset``; ``rows``
    ``(first, end)`` limits the fragments to those image rows (None: all). Returns the
    camera-frame vertices ``(3, V)``, the candidate triangles ``tri_index (K,)`` (global
    ids) and ``drawn (K,)`` bool (candidates that produced fragments).
    """
    # --- 1. vertex stage: mesh-local -> world -> camera frame
    vertices_camera = scene.vertices_in_camera(camera_from_world)
    clock.lap("transform")
    # --- 2. primitive assembly and frustum culling (vertex outcodes), hidden meshes
    outcodes = cull.vertex_outcodes(vertices_camera, camera)
    keep = cull.triangles_in_frustum(outcodes, scene.materials.faces)
    if not scene.visible.all():
        keep &= scene.visible[scene.materials.tri_mesh]
    tri_index = np.flatnonzero(keep)  # the K candidate triangles; z-buffer keys index them
    clock.lap("cull")
    # --- 3-6. per batch of triangles: back faces, near clipping, setup, spans, depth test
    out.n_fragments = 0
    drawn = np.zeros(len(tri_index), dtype=bool)  # candidates that produced fragments
    batch = settings.triangle_batch
    for start in range(0, len(tri_index), batch):
        source = np.arange(start, min(start + batch, len(tri_index)))
        tri = triangle_corners(vertices_camera, scene, tri_index[source])  # (3, 3, n) camera frame
        out.n_fragments += _rasterize(
            tri,
            source,
            camera,
            cull_back_faces,
            out,
            drawn,
            clock,
            key_offset,
            rows,
            settings.fragment_chunk,
        )
    return vertices_camera, tri_index, drawn


def _rasterize(
    tri: np.ndarray,
    source: np.ndarray,
    camera: Camera,
    cull_back_faces: bool,
    out: FrameBuffers,
    drawn: np.ndarray,
    clock: _StageClock,
    key_offset: int = 0,
    rows: tuple[int, int] | None = None,
    fragment_chunk: int = DEFAULT_SETTINGS.fragment_chunk,
) -> int:
    """Stages 3-6 for one batch: depth-test its fragments into ``out.zkey``.

    ``tri`` (3, 3, n) camera-frame corners; ``source`` (n,) their candidate ids (stored in
    the z-buffer keys, plus ``key_offset``); ``drawn`` (K,) bool is set for candidates that
    produced fragments. Returns the number of fragments.
    """
    if cull_back_faces:
        facing = cull.front_facing(tri, camera)
        tri, source = tri[:, :, facing], source[facing]
    # --- 3. near clipping: pieces remember their source (index into the batch)
    pieces, piece_of = cull.clip_near(tri, np.arange(len(source)), camera.near)
    clock.lap("assemble + clip")
    # --- 4. triangle setup: corners to pixels, drop pieces whose bounding box holds no
    #        pixel center, plane functions of the sources still in use
    screen = raster.project_triangles(pieces, camera)
    hit = raster.bounding_box_has_pixel_centers(screen, camera.height, camera.width)
    screen, piece_of = screen[:, :, hit], piece_of[hit]
    in_use = np.zeros(len(source), dtype=bool)
    in_use[piece_of] = True
    tri, source, piece_of = tri[:, :, in_use], source[in_use], (np.cumsum(in_use) - 1)[piece_of]
    planes, valid = raster.plane_coefficients(tri, camera)
    usable = valid[piece_of]
    screen, piece_of = screen[:, :, usable], piece_of[usable]
    clock.lap("setup")
    # --- 5. scanline spans under the top-left fill rule
    spans = raster.scanline_spans(screen, camera.height, camera.width, rows)
    drawn[source[piece_of[spans.triangle]]] = True
    clock.lap("spans")
    # --- 6. fragments and depth test (keys carry the candidate id)
    far_test = bool(np.any(tri[:, 2] < -camera.far))  # some corner beyond the far plane
    key_id = source + key_offset if key_offset else source
    n_fragments = raster.depth_test_spans(
        spans, planes, piece_of, camera, out.zkey, key_id, far_test, fragment_chunk
    )
    clock.lap("fragments")
    return n_fragments


def _prepare_buffers(buffers: FrameBuffers | None, camera: Camera) -> FrameBuffers:
    """Reuse ``buffers`` when its resolution matches ``camera``, else allocate new ones."""
    if buffers is not None and not isinstance(buffers, FrameBuffers):
        raise TypeError(f"buffers must be FrameBuffers or None, got {type(buffers).__name__}")
    if buffers is None or buffers.depth.shape != camera.resolution:
        buffers = FrameBuffers.allocate(camera)
    buffers.timings = {}
    return buffers


def _check_settings(settings: object) -> None:
    if not isinstance(settings, RenderSettings):
        raise TypeError(f"settings must be a render.RenderSettings, got {settings!r}")


def band_rows(camera: Camera, settings: RenderSettings = DEFAULT_SETTINGS) -> int:
    """Image rows per shading band: ``settings.shade_band_pixels // W`` (at least 1)."""
    return max(1, settings.shade_band_pixels // camera.width)


def _bands_of_rows(camera: Camera, rows: tuple[int, int], settings: RenderSettings) -> list[slice]:
    """The bands of ``_row_bands`` covering image rows ``first .. end - 1`` exactly."""
    first, end = (int(r) for r in rows)
    step = band_rows(camera, settings)
    aligned = all(r % step == 0 or r == camera.height for r in (first, end))
    if not (0 <= first <= end <= camera.height and aligned):
        raise ValueError(
            f"rows must be (first, end) with 0 <= first <= end <= {camera.height}, each a "
            f"multiple of {step} rows (a shading band) or the last row; got {rows!r}"
        )
    width = camera.width
    bands = _row_bands(camera, settings)
    return [band for band in bands if first * width <= band.start < end * width]


def _row_bands(camera: Camera, settings: RenderSettings) -> list[slice]:
    """Flat-index slices of whole image rows, about ``settings.shade_band_pixels`` each."""
    rows_per_band = band_rows(camera, settings)
    n_pixels = camera.height * camera.width
    step = rows_per_band * camera.width
    return [slice(start, min(start + step, n_pixels)) for start in range(0, n_pixels, step)]


class _StageClock:
    """Accumulates per-stage wall times (ms) into a dict."""

    def __init__(self, timings: dict) -> None:
        self.timings, self.last = timings, time.perf_counter()

    def lap(self, stage: str) -> None:
        now = time.perf_counter()
        self.timings[stage] = self.timings.get(stage, 0.0) + (now - self.last) * 1e3
        self.last = now
