"""Debug lines drawn over a rendered color frame, depth-tested against its depth buffer.

The engine's ``DebugLineRender`` (Habitat's ``sim.get_debug_line_render()``) collects world
segments with a color at each end; this module draws them into one camera's ``rgba`` frame
using that frame's ``depth`` (z-depth, 0 = nothing drawn), as Habitat's ``flushLines`` does:

1. **Camera frame and near clip.** Endpoints go to the camera frame
   (``camera_from_world = world_from_camera^-1``); a segment is cut where it crosses the near
   plane ``z = -near`` (the part behind the camera is dropped).
2. **Samples.** Each segment is sampled at ``t_k = k / n`` with ``n = ceil(2 L) + 1`` for a
   projected length of ``L`` pixels (two samples per pixel). The sample is the camera-frame
   point ``a + t (b - a)``, projected exactly (so the line is straight and its depth
   ``z = -z_camera`` is exact); its color is ``c_a + t (c_b - c_a)`` (perspective-correct, as
   a GPU interpolates).
3. **Width.** Each sample covers a ``w x w`` square of pixels around it,
   ``w = max(1, round(line_width))``.
4. **Resolve.** Per pixel the nearest sample wins (ties: the earlier segment, then the
   earlier sample).
5. **Depth test and blend.** A sample is *visible* where nothing was drawn or
   ``z <= depth + DEPTH_TOLERANCE``; it is blended with its alpha ``a``:
   ``out = floor(c a + dst (1 - a) + 1/2)`` (8-bit channels). Hidden samples are blended
   with ``a * OCCLUDED_OPACITY`` (Habitat draws occluded lines again at opacity 0.1, so a
   line behind a wall shows faintly). Lines do not write depth.

:func:`draw_lines` is vectorized over all samples; :func:`draw_lines_reference` is the same,
one sample at a time in plain Python (tests check they agree bit for bit); one switch,
``draw_lines(..., reference=True)``, selects it.
"""

from __future__ import annotations

import math

import numpy as np

from render.camera import Camera, invert_rigid

__all__ = ["DEPTH_TOLERANCE", "OCCLUDED_OPACITY", "draw_lines", "draw_lines_reference"]

#: meters: a line sample this far behind the surface still counts as visible (lines drawn
#: on a surface, e.g. a box around an object's face, do not flicker)
DEPTH_TOLERANCE = 1e-3
#: the opacity factor of line samples hidden by geometry (Habitat's second pass: 0.1)
OCCLUDED_OPACITY = 0.1


def _clip_parameters(za: np.ndarray, zb: np.ndarray, near: float) -> tuple[np.ndarray, np.ndarray]:
    """Parameters ``(t0, t1)`` of the part of each segment in front of the near plane
    (``z_camera <= -near``); ``t0 > t1`` when nothing is in front."""
    in_a, in_b = za <= -near, zb <= -near
    with np.errstate(divide="ignore", invalid="ignore"):
        t_cross = (-near - za) / (zb - za)  # z(t) = za + t (zb - za) = -near
    t0 = np.where(in_a, 0.0, np.where(in_b, t_cross, 1.0))
    t1 = np.where(in_b, 1.0, np.where(in_a, t_cross, 0.0))
    return t0, t1


def _to_camera(points: np.ndarray, camera_from_world: np.ndarray) -> np.ndarray:
    """``R p + t`` written out per component (the same arithmetic for one point or many,
    so the reference path agrees bit for bit)."""
    rot, trans = camera_from_world[:3, :3], camera_from_world[:3, 3]
    x, y, z = points[:, 0:1], points[:, 1:2], points[:, 2:3]
    return x * rot[:, 0] + y * rot[:, 1] + z * rot[:, 2] + trans


def _project(camera: Camera, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(px, py, z)`` of camera-frame points ``(N, 3)`` (module :mod:`render.camera`)."""
    pixels, depth = camera.project(points)
    return pixels[:, 0], pixels[:, 1], depth


def _samples(
    camera: Camera,
    a: np.ndarray,
    b: np.ndarray,
    color_a: np.ndarray,
    color_b: np.ndarray,
) -> tuple[np.ndarray, ...]:
    """Stage 1-2 for all segments: per sample its pixel coordinates, depth, RGBA color
    (floats in [0, 1]) and the (segment, sample) order key."""
    t0, t1 = _clip_parameters(a[:, 2], b[:, 2], camera.near)
    keep = t0 <= t1
    a, b, color_a, color_b, t0, t1 = (x[keep] for x in (a, b, color_a, color_b, t0, t1))
    start = a + t0[:, None] * (b - a)
    end = a + t1[:, None] * (b - a)
    ps, pys, _ = _project(camera, start)
    pe, pye, _ = _project(camera, end)
    length = np.hypot(pe - ps, pye - pys)
    n = np.ceil(2.0 * np.nan_to_num(length, posinf=0.0)).astype(np.int64) + 1
    n = np.minimum(n, 4 * (camera.width + camera.height))  # bounded however long
    segment = np.repeat(np.arange(len(n)), n + 1)
    first = np.cumsum(n + 1) - (n + 1)
    k = np.arange(len(segment)) - first[segment]
    s = k / n[segment]  # sample parameter on the clipped segment
    t = t0[segment] + s * (t1[segment] - t0[segment])  # ... and on the original one
    points = a[segment] + t[:, None] * (b - a)[segment]
    px, py, z = _project(camera, points)
    colors = color_a[segment] + t[:, None] * (color_b - color_a)[segment]
    order = np.nonzero(keep)[0][segment] * (1 << 20) + k
    return px, py, z, colors, order


def _brush(line_width: float) -> np.ndarray:
    """Pixel offsets ``(m, 2)`` (drow, dcol) of a ``w x w`` square, ``w = max(1, round(width))``."""
    w = max(1, int(round(float(line_width))))
    offsets = np.arange(w) - (w - 1) // 2
    drow, dcol = np.meshgrid(offsets, offsets, indexing="ij")
    return np.stack([drow.ravel(), dcol.ravel()], axis=1)


def _blend(dst: np.ndarray, color: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """``floor(c a + dst (1 - a) + 1/2)`` per channel (c in 0..255)."""
    src = color[..., :3] * 255.0
    return np.floor(src * alpha[..., None] + dst * (1.0 - alpha[..., None]) + 0.5)


def draw_lines(
    rgba: np.ndarray,
    depth: np.ndarray,
    camera: Camera,
    world_from_camera: np.ndarray,
    starts: np.ndarray,
    ends: np.ndarray,
    start_colors: np.ndarray,
    end_colors: np.ndarray,
    line_width: float = 1.0,
    reference: bool = False,
) -> None:
    """Draw world segments into ``rgba`` (in place), depth-tested against ``depth``.

    Parameters
    ----------
    rgba : (H, W, 4) uint8 frame, written in place (alpha stays 255).
    depth : (H, W) float32 z-depth of the frame, 0 where nothing is drawn (read only).
    camera, world_from_camera : the camera and its (4, 4) pose that rendered the frame.
    starts, ends : (N, 3) float, world frame, meters.
    start_colors, end_colors : (N, 4) float RGBA in [0, 1] (Magnum's ``Color4``).
    line_width : pixels (Habitat's ``set_line_width``).
    reference : True: :func:`draw_lines_reference` (plain loops, same pixels).
    """
    if reference:
        draw_lines_reference(
            rgba, depth, camera, world_from_camera, starts, ends, start_colors, end_colors,
            line_width,
        )  # fmt: skip
        return
    if len(starts) == 0:
        return
    camera_from_world = invert_rigid(world_from_camera)
    a = _to_camera(np.asarray(starts, np.float64), camera_from_world)
    b = _to_camera(np.asarray(ends, np.float64), camera_from_world)
    ca, cb = np.asarray(start_colors, np.float64), np.asarray(end_colors, np.float64)
    px, py, z, colors, order = _samples(camera, a, b, ca, cb)
    # stage 3: the brush around each sample
    brush = _brush(line_width)
    rows = (np.floor(py).astype(np.int64)[:, None] + brush[None, :, 0]).ravel()
    cols = (np.floor(px).astype(np.int64)[:, None] + brush[None, :, 1]).ravel()
    sample = np.repeat(np.arange(len(z)), len(brush))
    inside = (rows >= 0) & (rows < camera.height) & (cols >= 0) & (cols < camera.width)
    rows, cols, sample = rows[inside], cols[inside], sample[inside]
    if len(sample) == 0:
        return
    # stage 4: nearest sample per pixel (ties: segment, then sample order)
    pixel = rows * camera.width + cols
    winner_order = np.lexsort((order[sample], z[sample], pixel))
    pixel, sample = pixel[winner_order], sample[winner_order]
    first = np.ones(len(pixel), bool)
    first[1:] = pixel[1:] != pixel[:-1]
    pixel, sample = pixel[first], sample[first]
    # stage 5: depth test and blend
    r, c = np.divmod(pixel, camera.width)
    surface = depth[r, c].astype(np.float64)
    visible = (surface == 0.0) | (z[sample] <= surface + DEPTH_TOLERANCE)
    alpha = colors[sample, 3] * np.where(visible, 1.0, OCCLUDED_OPACITY)
    rgba[r, c, :3] = _blend(rgba[r, c, :3].astype(np.float64), colors[sample], alpha)


def draw_lines_reference(
    rgba: np.ndarray,
    depth: np.ndarray,
    camera: Camera,
    world_from_camera: np.ndarray,
    starts: np.ndarray,
    ends: np.ndarray,
    start_colors: np.ndarray,
    end_colors: np.ndarray,
    line_width: float = 1.0,
) -> None:
    """Mirrors :func:`draw_lines`, one segment, sample and pixel at a time."""
    camera_from_world = invert_rigid(world_from_camera)
    best: dict[tuple[int, int], tuple[float, int, float, np.ndarray]] = {}
    brush = [(int(dr), int(dc)) for dr, dc in _brush(line_width)]
    for index in range(len(starts)):
        a = _to_camera(np.asarray(starts[index : index + 1], np.float64), camera_from_world)[0]
        b = _to_camera(np.asarray(ends[index : index + 1], np.float64), camera_from_world)[0]
        ca = np.asarray(start_colors[index], np.float64)
        cb = np.asarray(end_colors[index], np.float64)
        t0, t1 = (float(v[0]) for v in _clip_parameters(a[2:3], b[2:3], camera.near))
        if t0 > t1:
            continue  # behind the camera
        (ps, pys, _), (pe, pye, _) = (_project(camera, (a + t * (b - a))[None]) for t in (t0, t1))
        length = float(np.hypot(pe[0] - ps[0], pye[0] - pys[0]))
        n = int(math.ceil(2.0 * length)) + 1 if math.isfinite(length) else 1
        n = min(n, 4 * (camera.width + camera.height))
        for k in range(n + 1):
            t = t0 + (k / n) * (t1 - t0)
            px, py, z = (float(v[0]) for v in _project(camera, (a + t * (b - a))[None]))
            color = ca + t * (cb - ca)
            order = index * (1 << 20) + k
            for dr, dc in brush:
                row, col = math.floor(py) + dr, math.floor(px) + dc
                if not (0 <= row < camera.height and 0 <= col < camera.width):
                    continue
                current = best.get((row, col))
                if current is None or (z, order) < (current[0], current[1]):
                    best[(row, col)] = (z, order, float(color[3]), color)
    for (row, col), (z, _, alpha, color) in best.items():
        surface = float(depth[row, col])
        visible = surface == 0.0 or z <= surface + DEPTH_TOLERANCE
        alpha = alpha * (1.0 if visible else OCCLUDED_OPACITY)
        for channel in range(3):
            dst = float(rgba[row, col, channel])
            value = color[channel] * 255.0 * alpha + dst * (1.0 - alpha) + 0.5
            rgba[row, col, channel] = math.floor(value)
