"""Packed 8-bit RGBA arithmetic: the fixed-point color kernels of the fast shading path.

Colors travel packed as one ``uint32`` per pixel (``R | G << 8 | B << 16 | A << 24``: the
bytes R, G, B, A in memory) so that gathers are 1-D and cheap. Bilinear filtering and
lighting of packed colors use the classic SWAR trick of software renderers ("SIMD within a
register"): the channel pairs (R, B) and (G, A) are masked into two 16-bit lanes of a
uint32 and multiplied by an 8-bit fixed-point weight ``W = round(256 f)`` at once::

    c' = ((p & 0x00FF00FF) * W + 0x00800080) >> 8 & 0x00FF00FF     (R and B together)

Weights are quantized to 1/256 (like GPU texture units): a result may differ from the
exact float formula (``render.reference.fragment_color``) by one level out of 255.

Two versions of each kernel: the plain one (``sample_bilinear``, ``modulate_packed``) reads
like its formula; the ``_fast`` / ``_inplace`` one computes the same bits with fewer
temporaries (``RenderSettings.fast_shading`` selects; ``tests/render/test_shade.py``
checks they agree bit for bit).
"""

from __future__ import annotations

import numpy as np

_RB_MASK = np.uint32(0x00FF00FF)  # lanes holding R and B
_ALPHA = np.uint32(0xFF000000)
_U8 = np.uint32(8)


def pack_rgba(rgba: np.ndarray) -> np.ndarray:
    """Pack ``(..., 4)`` uint8 RGBA into ``(...)`` uint32 (bytes R, G, B, A in memory)."""
    rgba = np.ascontiguousarray(rgba, dtype=np.uint8)
    return rgba.view("<u4")[..., 0].astype(np.uint32)


def unpack_rgba(packed: np.ndarray) -> np.ndarray:
    """Inverse of ``pack_rgba``: ``(...)`` uint32 to ``(..., 4)`` uint8."""
    packed = np.ascontiguousarray(packed, dtype="<u4")
    return packed[..., None].view(np.uint8)


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
