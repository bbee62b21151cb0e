"""Reading the z-buffer back, and vertex attributes at the visible pixels (stages 7-8).

After the depth test (stage 6, ``render.raster``) every covered pixel of the z-buffer holds
the 64-bit key ``(float32 depth bits << 32) | triangle`` of its nearest fragment.

* ``resolve_depth`` / ``visible_from_keys`` (stage 8): the covered pixels, their winning
  triangle (the low 32 bits) and depth (the high 32 bits) as :class:`VisiblePixels`.
* :class:`AttributePlanes` (built per triangle in stage 7, evaluated per pixel in stage 8):
  perspective-correct vertex attributes (uvs, vertex colors, Gouraud light). The triangle
  setup of stage 4 gives per triangle the plane functions ``q_k = b_k / z`` and
  ``w = 1 / z``, affine in pixel coordinates (``render.raster.plane_coefficients``); any
  attribute ``a`` then has ``a / z`` affine too, so one plane per attribute and a
  multiplication by the pixel's depth give ``a`` exactly where a textbook divides
  ``sum_k (l_k / z_k) a_k`` by ``sum_k l_k / z_k``.
* ``winning_triangles``: the triangles that own at least one pixel (stage 7 builds shading
  inputs for those only when a frame has very many candidates).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass

import numpy as np

from render.camera import Camera
from render.settings import DEFAULT_SETTINGS

#: an empty z-buffer key: larger than any (depth bits << 32) | triangle
EMPTY_KEY = np.uint64(0xFFFFFFFFFFFFFFFF)
_LOW32 = np.uint64(0xFFFFFFFF)


@dataclass
class VisiblePixels:
    """The resolved z-buffer: one entry per covered pixel.

    pixel : (n,) int64 flat index ``row * W + col``.
    winner : (n,) int64 index of the nearest triangle (the id stored in its z-buffer key).
    depth : (n,) float32 z-depth in meters.
    camera : the camera (for pixel-center coordinates).
    center_tables : read pixel centers from cached tables (``RenderSettings.pixel_center_tables``).
    """

    pixel: np.ndarray
    winner: np.ndarray
    depth: np.ndarray
    camera: Camera
    center_tables: bool = DEFAULT_SETTINGS.pixel_center_tables

    def subset(self, sel: np.ndarray) -> VisiblePixels:
        """The entries ``sel`` (an index array)."""
        return VisiblePixels(
            self.pixel[sel], self.winner[sel], self.depth[sel], self.camera, self.center_tables
        )

    def centered_coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """Pixel-center coordinates relative to the principal point, float32 ``(n,)`` each:
        ``xc = col + 0.5 - cx`` and ``yc = row + 0.5 - cy`` (read-only arrays).

        With ``center_tables`` they are read from per-camera tables of every pixel
        (a slice for a run of consecutive pixels, else a gather), else computed from
        ``divmod(pixel, W)``; both give the same values.
        """
        if not self.center_tables:
            row, col = np.divmod(self.pixel.astype(np.int32), np.int32(self.camera.width))
            xc = col.astype(np.float32) + np.float32(0.5 - self.camera.cx)
            yc = row.astype(np.float32) + np.float32(0.5 - self.camera.cy)
            return xc, yc
        xc_table, yc_table = pixel_center_tables(self.camera)
        pixel = self.pixel
        if len(pixel) and pixel[-1] - pixel[0] == len(pixel) - 1:  # consecutive: no gather
            run = slice(int(pixel[0]), int(pixel[-1]) + 1)
            return xc_table[run], yc_table[run]
        return xc_table.take(pixel), yc_table.take(pixel)


_CENTER_TABLES: dict = {}


def pixel_center_tables(camera: Camera) -> tuple[np.ndarray, np.ndarray]:
    """``(xc, yc)`` float32 ``(H * W,)`` of every pixel (flat index ``row W + col``), cached
    per image size and principal point (read-only): ``col + 0.5 - cx`` and ``row + 0.5 - cy``
    exactly as ``centered_coordinates`` computes them."""
    key = (camera.height, camera.width, camera.cx, camera.cy)
    tables = _CENTER_TABLES.get(key)
    if tables is None:
        cols = np.arange(camera.width, dtype=np.int32).astype(np.float32)
        rows = np.arange(camera.height, dtype=np.int32).astype(np.float32)
        xc_row = cols + np.float32(0.5 - camera.cx)  # xc of one image row
        yc_col = rows + np.float32(0.5 - camera.cy)  # yc of each row
        tables = (np.tile(xc_row, camera.height), np.repeat(yc_col, camera.width))
        for table in tables:
            table.flags.writeable = False
        if len(_CENTER_TABLES) >= 8:  # a few cameras at most: keep the cache small
            _CENTER_TABLES.clear()
        _CENTER_TABLES[key] = tables
    return tables


def resolve_depth(
    zkey: np.ndarray,
    camera: Camera,
    band: slice | None = None,
    center_tables: bool = DEFAULT_SETTINGS.pixel_center_tables,
) -> VisiblePixels:
    """Read the z-buffer back: covered pixels, winning triangle (low 32 bits of the key)
    and its depth (high 32 bits: the float32 depth's bit pattern).

    ``band`` restricts the read to a slice of flat pixel indices (a band of rows);
    ``center_tables`` is passed on to the ``VisiblePixels``.
    """
    start = 0 if band is None else band.start
    keys = zkey if band is None else zkey[band]
    covered = keys != EMPTY_KEY
    if np.count_nonzero(covered) == len(keys):  # every pixel drawn (the usual band indoors)
        pixel = np.arange(len(keys))
    else:
        pixel = np.flatnonzero(covered)
        keys = keys[pixel]
    halves = keys.view(np.uint32).reshape(-1, 2)  # little endian: (low, high) words
    if sys.byteorder == "big":
        halves = halves[:, ::-1]
    winner = halves[:, 0].astype(np.int64)  # the triangle id
    depth = halves[:, 1].view(np.float32)  # the depth bits
    pixel += start
    return VisiblePixels(pixel, winner, depth, camera, center_tables)


def visible_from_keys(
    keys: np.ndarray,
    pixel: np.ndarray,
    camera: Camera,
    id_offset: int = 0,
    center_tables: bool = DEFAULT_SETTINGS.pixel_center_tables,
) -> VisiblePixels:
    """Pixels ``pixel`` (flat indices, each covered) with their z-buffer ``keys``: winner
    ``low 32 bits - id_offset`` and depth (high 32 bits), as ``resolve_depth`` reads them."""
    halves = np.ascontiguousarray(keys).view(np.uint32).reshape(-1, 2)  # (low, high) words
    if sys.byteorder == "big":
        halves = halves[:, ::-1]
    winner = halves[:, 0].astype(np.int64)  # the triangle id
    if id_offset:
        winner -= id_offset
    depth = halves[:, 1].view(np.float32)  # the depth bits
    return VisiblePixels(np.asarray(pixel, dtype=np.int64), winner, depth, camera, center_tables)


class AttributePlanes:
    """Perspective-correct interpolation of per-vertex attributes at pixel centers.

    Any attribute ``a`` with corner values ``a_k`` satisfies ``a / z = sum_k q_k a_k`` with
    ``q_k = b_k / z`` affine in pixel coordinates (``render.raster``'s docstring), and
    ``q_2 = w - q_0 - q_1``, so ``a / z`` is itself affine::

        plane(a / z) = (a_0 - a_2) plane(q_0) + (a_1 - a_2) plane(q_1) + a_2 plane(w)

    and ``a = plane(a / z)(px, py) * z``. Orthographic: ``q_k = b_k``, ``sum_k b_k = 1`` so
    ``plane(1) = (0, 0, 1)`` replaces ``plane(w)`` and no multiplication by z is needed.

    Parameters
    ----------
    planes : (3, 3, K) float64 plane functions ``(q_0, q_1, w)`` of K triangles.
    corner_values : (3, C, K) float, the attribute (C channels) at each triangle's corners.
    camera : the camera (pinhole or orthographic).
    row_of_triangle : (K',) row of each triangle id among the K (planes built for a subset).
    paired : evaluate two-channel attributes as one complex64
        (``RenderSettings.paired_attributes``; same bits as channel by channel).
    """

    def __init__(
        self,
        planes: np.ndarray,
        corner_values: np.ndarray,
        camera: Camera,
        row_of_triangle: np.ndarray | None = None,
        paired: bool = DEFAULT_SETTINGS.paired_attributes,
    ) -> None:
        a0, a1, a2 = (corner_values[k][:, None, :] for k in range(3))  # (C, 1, K)
        sum_plane = planes[2] if camera.is_pinhole else np.array([0.0, 0.0, 1.0])[:, None]
        attr = (a0 - a2) * planes[0] + (a1 - a2) * planes[1] + a2 * sum_plane  # (C, 3, K)
        # float32, each coefficient row contiguous for fast 1-D gathers
        self.coefficients = np.ascontiguousarray(attr, dtype=np.float32)
        self.multiply_by_depth = camera.is_pinhole
        self.row_of_triangle = row_of_triangle
        self.paired = None  # two channels (uvs) as one complex64 plane: c0 + i c1, (3, K)
        if paired and attr.shape[0] == 2:
            self.paired = self.coefficients[0] + np.complex64(1j) * self.coefficients[1]

    def evaluate(self, visible: VisiblePixels) -> np.ndarray:
        """Attribute values at the visible pixels, ``(C, n)`` float32 (channel-major).

        ``visible.winner`` indexes the K triangles, or, when ``row_of_triangle`` was given
        (planes built for a subset of triangles only), ``row_of_triangle[winner]`` does.
        """
        rows = visible.winner
        if self.row_of_triangle is not None:
            rows = self.row_of_triangle[rows]
        xc, yc = visible.centered_coordinates()
        if self.paired is not None:
            return self._evaluate_paired(self.paired, rows, xc, yc, visible.depth)
        n_channels = self.coefficients.shape[0]
        out = np.empty((n_channels, len(rows)), dtype=np.float32)
        for c in range(n_channels):
            a, b, k = (self.coefficients[c, j][rows] for j in range(3))
            np.multiply(a, xc, out=out[c])
            b *= yc  # b is a fresh gather: reuse it
            out[c] += b
            out[c] += k  # a/z = A (px - cx) + B (py - cy) + C
        if self.multiply_by_depth:
            out *= visible.depth  # a = (a / z) * z
        return out

    def _evaluate_paired(
        self,
        paired: np.ndarray,
        rows: np.ndarray,
        xc: np.ndarray,
        yc: np.ndarray,
        depth: np.ndarray,
    ) -> np.ndarray:
        """``evaluate`` of two channels at once: the same formula on ``c0 + i c1``.

        A complex64 times a float32 is two float32 products (the imaginary part of the
        float is 0, so no rounding differs): the same bits as the per-channel loop, with
        half the gathers and passes. Returns a ``(2, n)`` float32 view (rows strided).
        """
        a, b, k = (paired[j].take(rows) for j in range(3))
        a *= xc
        b *= yc
        a += b
        a += k  # a/z = A (px - cx) + B (py - cy) + C, both channels
        if self.multiply_by_depth:
            a *= depth  # a = (a / z) * z
        return a.view(np.float32).reshape(len(rows), 2).T


def winning_triangles(zkey: np.ndarray, n_triangles: int) -> np.ndarray:
    """Sorted ids (``(k,)`` int64) of the triangles that won at least one pixel of ``zkey``."""
    keys = zkey[zkey != EMPTY_KEY]
    won = np.zeros(n_triangles, dtype=bool)
    won[(keys & _LOW32).astype(np.int64)] = True
    return np.flatnonzero(won)
