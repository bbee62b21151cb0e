"""Videos from sensor observations, mirroring ``habitat_sim.utils.viz_utils``.

Pipeline of ``make_video``: for every observation dict, ``make_video_frame`` turns the
primary observation into an RGB(A) ``PIL.Image`` with ``observation_to_image``, pastes the
overlays (each on a border frame from ``border_frames_from_overlay``), resizes to
``video_dims``; the frames are encoded to ``<video_file>.mp4`` with imageio-ffmpeg (H.264),
falling back to an animated GIF beside it when no mp4 encoder works; ``display_video`` then
shows the file inline in a notebook (HTML5 ``<video>`` / ``<img>``) or prints its path.

Conversions (Habitat's)::

    depth    -> gray  uint8(clip(d, 0, depth_clip) / depth_clip * 255)
    semantic -> RGBA  D3_40_COLORS_RGB[id % 40]
    color    -> the RGBA / RGB array as is

Overlay settings are dicts with ``obs`` (observation key), ``type`` (``"color"``,
``"depth"``, ``"semantic"``), ``dims`` (width, height), ``pos`` (x, y of the top-left corner),
``border`` (pixels) and optionally ``border_color`` (RGB, default gray 150).
Nothing here blocks or needs a display: headless runs just get the file path printed.

Two paths, same pixels: ``make_video_frame`` composes with PIL (the readable reference,
Habitat's code); ``compose_video_frame`` composes the same frame with NumPy slicing (only
the overlays' resampling stays PIL's ``Image.resize``, the one kernel that defines their
pixels), about 3x cheaper, and ``make_video`` uses it unless given its own
``observation_to_image`` or ``video_dims`` (tests prove the two agree bit for bit).
Encoding lives in :mod:`render.encode` (re-exported here): ``BackgroundVideoWriter``
composes and encodes on a background thread, so that the caller (simulation, rendering)
goes on while ffmpeg works; ``save_video`` streams through one.
"""

from __future__ import annotations

import base64
import sys
from collections import deque
from collections.abc import Iterable, Sequence
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from typing import Any

import numpy as np
from PIL import Image

from render.encode import (  # re-exported: the encoding half of this module's API
    PROGRESS_BAR_MIN_FRAMES as PROGRESS_BAR_MIN_FRAMES,
)
from render.encode import X264_CRF as X264_CRF
from render.encode import X264_PRESET as X264_PRESET
from render.encode import X264_THREADS as X264_THREADS
from render.encode import BackgroundVideoWriter as BackgroundVideoWriter
from render.encode import _to_even_frame as _to_even_frame
from render.encode import check_fps, check_frame_size
from render.encode import mp4_options as mp4_options
from render.encode import save_video as save_video
from render.settings import check_pixel_budget

#: 40 category colors (d3's category20 followed by category20b), id % 40 indexes them
_D3_40_HEX = (
    "1f77b4 aec7e8 ff7f0e ffbb78 2ca02c 98df8a d62728 ff9896 9467bd c5b0d5 "
    "8c564b c49c94 e377c2 f7b6d2 7f7f7f c7c7c7 bcbd22 dbdb8d 17becf 9edae5 "
    "393b79 5254a3 6b6ecf 9c9ede 637939 8ca252 b5cf6b cedb9c 8c6d31 bd9e39 "
    "e7ba52 e7cb94 843c39 ad494a d6616b e7969c 7b4173 a55194 ce6dbd de9ed6"
).split()
D3_40_COLORS_RGB = np.array(
    [[int(h[i : i + 2], 16) for i in (0, 2, 4)] for h in _D3_40_HEX], np.uint8
)
#: threads composing video frames with overlays in ``make_video``
COMPOSE_THREADS = 2


def is_notebook() -> bool:
    """True when running inside a Jupyter kernel (not a plain script or IPython console)."""
    ipython_module = sys.modules.get("IPython")
    if ipython_module is None:
        return False
    try:
        shell = ipython_module.get_ipython()
        return shell is not None and "IPKernelApp" in shell.config
    except (AttributeError, TypeError, KeyError):
        return False


def depth_to_rgb(depth_image: np.ndarray, clip_max: float = 10.0) -> np.ndarray:
    """Depth (meters) to an (H, W) uint8 gray image: ``uint8(clip(d, 0, max) / max * 255)``."""
    if not np.isfinite(clip_max) or clip_max <= 0:
        raise ValueError(f"clip_max must be finite and > 0, got {clip_max!r}")
    # the float64 formula above in one buffer: clip (converting to float64), / max, * 255
    normalized = np.clip(
        np.asarray(depth_image), 0.0, clip_max, out=np.empty(np.shape(depth_image))
    )
    normalized /= clip_max
    normalized *= 255
    return normalized.astype(np.uint8)


def semantic_to_rgb(semantic_image: np.ndarray) -> Image.Image:
    """Semantic ids (H, W) to an RGBA ``PIL.Image``: color ``D3_40_COLORS_RGB[id % 40]``."""
    ids = np.asarray(semantic_image).astype(np.int64)
    image = Image.new("P", (ids.shape[1], ids.shape[0]))
    image.putpalette(D3_40_COLORS_RGB.flatten().tolist())
    image.putdata((ids.flatten() % 40).astype(np.uint8))
    return image.convert("RGBA")


def observation_to_image(
    observation_image: np.ndarray, observation_type: str, depth_clip: float | None = 10.0
) -> Image.Image | None:
    """A ``PIL.Image`` of one observation (``"color"``, ``"depth"`` or ``"semantic"``).

    Returns None (and prints a message) for an unsupported type, like Habitat.
    """
    if observation_type == "color":
        return Image.fromarray(np.uint8(observation_image))
    if observation_type == "depth":
        clip = 10.0 if depth_clip is None else depth_clip
        return Image.fromarray(depth_to_rgb(observation_image, clip_max=clip))
    if observation_type == "semantic":
        return semantic_to_rgb(observation_image)
    print(f"observation_to_image: unsupported observation type {observation_type!r}")
    return None


_observation_to_image = observation_to_image  # the default, for make_video's path choice


def border_frames_from_overlay(
    overlay_settings: Sequence[dict] | None, observation_to_image=observation_to_image
) -> list[Image.Image]:
    """One solid border image per overlay: ``(dims + 2 border)`` pixels of ``border_color``."""
    frames = []
    for overlay in overlay_settings or []:
        width, height = overlay["dims"]
        border = overlay["border"]
        color = np.asarray(overlay.get("border_color", (150, 150, 150)))
        frame = np.empty((height + 2 * border, width + 2 * border, 3), np.uint8)
        frame[:, :] = color
        frames.append(observation_to_image(frame, "color"))
    return frames


def make_video_frame(
    ob: dict,
    primary_obs: str,
    primary_obs_type: str,
    video_dims: tuple[int, int] | None,
    overlay_settings: Sequence[dict] | None = None,
    observation_to_image=observation_to_image,
) -> Image.Image:
    """Compose one video frame: the primary image, bordered overlays, optional resize."""
    frame = observation_to_image(ob[primary_obs], primary_obs_type)
    if frame is None:
        raise RuntimeError("make_video_frame: aborting, primary image processing failed.")
    borders = border_frames_from_overlay(overlay_settings, observation_to_image)
    for overlay, border_frame in zip(overlay_settings or [], borders, strict=True):
        image = observation_to_image(ob[overlay["obs"]], overlay["type"])
        if image is None:
            raise RuntimeError(
                f"make_video_frame: overlay image processing failed on {overlay['obs']!r}."
            )
        x, y = overlay["pos"]
        frame.paste(border_frame, box=(x - overlay["border"], y - overlay["border"]))
        frame.paste(image.resize(tuple(overlay["dims"])), box=(x, y))
    if video_dims is not None:
        frame = frame.resize(_check_dims(video_dims, "video_dims"))
    return frame


def _check_dims(dims, name: str) -> tuple[int, int]:
    """``(width, height)`` as two positive ints within the pixel budget, else ValueError."""
    if isinstance(dims, str | bytes):  # bytes unpack to ints: b"\x01\x01" is not (1, 1)
        raise ValueError(f"{name} must be (width, height), got {dims!r}")
    try:
        width, height = dims
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be (width, height), got {dims!r}") from None
    for n in (width, height):
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n <= 0:
            raise ValueError(f"{name} must be two positive ints, got {dims!r}")
    check_pixel_budget(height, width, name)
    return int(width), int(height)


def compose_video_frame(
    ob: dict,
    primary_obs: str,
    primary_obs_type: str,
    overlay_settings: Sequence[dict] | None = None,
    depth_clip: float | None = 10.0,
) -> np.ndarray:
    """``np.asarray(make_video_frame(ob, ..., video_dims=None))`` composed with NumPy.

    The primary image becomes an array in its PIL mode's layout (``(H, W, 4)`` RGBA,
    ``(H, W, 3)`` RGB or ``(H, W)`` gray); each overlay's border and resized image are
    written into it as ``Image.paste`` would (converted to the frame's mode, clipped to the
    frame). A gray (depth) primary with overlays takes the PIL path (PIL's gray conversion).
    """
    clip = 10.0 if depth_clip is None else depth_clip
    frame = _primary_array(ob[primary_obs], primary_obs_type, clip)
    if frame is None:
        raise RuntimeError("make_video_frame: aborting, primary image processing failed.")
    if not overlay_settings:
        return frame
    if frame.ndim != 3 or frame.shape[2] not in (3, 4):  # gray frame: PIL's conversions
        to_image = partial(observation_to_image, depth_clip=depth_clip)
        return np.asarray(
            make_video_frame(ob, primary_obs, primary_obs_type, None, overlay_settings, to_image)
        )
    for overlay in overlay_settings:
        width, height = overlay["dims"]
        border = overlay["border"]
        x, y = overlay["pos"]
        color = np.asarray(overlay.get("border_color", (150, 150, 150)))
        border_frame = np.empty((height + 2 * border, width + 2 * border, 3), np.uint8)
        border_frame[:, :] = color
        _paste(frame, border_frame, x - border, y - border)
        resized = _resized_overlay(ob[overlay["obs"]], overlay["type"], (width, height), clip)
        if resized is None:
            raise RuntimeError(
                f"make_video_frame: overlay image processing failed on {overlay['obs']!r}."
            )
        _paste(frame, resized, x, y)
    return frame


def _resized_overlay(
    observation: np.ndarray, kind: str, dims: tuple[int, int], clip: float
) -> np.ndarray | None:
    """The pixels of ``observation_to_image(observation, kind).resize(dims)`` (None for an
    unsupported ``kind``).

    PIL resizes an RGBA image premultiplied by its alpha (mode ``RGBa``) and divides it back
    after; with every alpha 255 both steps are the identity. An opaque RGBA color
    observation (every rendered frame) is therefore read as RGB (alpha dropped while
    unpacking) and resized as RGB, which PIL pastes back with alpha 255: the same pixels
    in about 60 % of the time.
    """
    pixels = np.asarray(observation)
    if kind == "color" and _is_opaque_rgba(pixels):
        height, width = pixels.shape[:2]
        opaque = Image.frombytes("RGB", (width, height), pixels, "raw", "RGBX")  # drop alpha
        return np.asarray(opaque.resize(dims))
    image = observation_to_image(observation, kind, depth_clip=clip)
    return None if image is None else np.asarray(image.resize(dims))


def _is_opaque_rgba(pixels: np.ndarray) -> bool:
    """A C-contiguous ``(H, W, 4)`` uint8 array whose alpha bytes are all 255."""
    if pixels.dtype != np.uint8 or pixels.ndim != 3 or pixels.shape[2] != 4:
        return False
    if not pixels.flags.c_contiguous:
        return False
    packed = pixels.view("<u4")  # alpha is the high byte of each little-endian pixel word
    return bool(packed.min(initial=0xFFFFFFFF) >= 0xFF000000)


def _primary_array(observation: np.ndarray, kind: str, clip: float) -> np.ndarray | None:
    """A fresh array of ``observation_to_image(observation, kind)``'s pixels, or None."""
    if kind == "color":
        return np.array(observation, dtype=np.uint8)  # one copy (np.uint8(...) made two)
    if kind == "depth":
        return depth_to_rgb(observation, clip_max=clip)
    if kind == "semantic":
        ids = np.asarray(observation).astype(np.int64)
        rgba = np.full(ids.shape + (4,), 255, np.uint8)
        rgba[..., :3] = D3_40_COLORS_RGB[ids % 40]  # the palette lookup of semantic_to_rgb
        return rgba
    observation_to_image(observation, kind)  # an unsupported kind: prints Habitat's message
    return None


def _paste(frame: np.ndarray, patch: np.ndarray, x: int, y: int) -> None:
    """``Image.paste(patch, box=(x, y))`` on an RGB(A) ``frame`` array, in place.

    The patch is converted to the frame's mode as PIL does: gray is replicated to R, G, B;
    an added alpha is 255; a dropped alpha is ignored. Parts outside the frame are clipped.
    """
    channels = frame.shape[2]
    if patch.ndim == 2:
        patch = patch[:, :, None].repeat(3, axis=2)  # L -> RGB: gray replicated
    height, width = patch.shape[:2]
    top, left = max(y, 0), max(x, 0)
    bottom, right = min(y + height, frame.shape[0]), min(x + width, frame.shape[1])
    if bottom <= top or right <= left:
        return
    source = patch[top - y : bottom - y, left - x : right - x]
    target = frame[top:bottom, left:right]
    target[..., :3] = source[..., :3]
    if channels == 4:  # RGBA frame: the patch's alpha, or 255 for an RGB patch
        target[..., 3] = source[..., 3] if source.shape[2] == 4 else 255


def _in_order_on_threads(function, items: Iterable, threads: int, ahead: int = 4):
    """``map(function, items)`` computed on ``threads`` threads, at most ``threads + ahead``
    items in flight, results in order."""
    with ThreadPoolExecutor(threads, thread_name_prefix="rigidsim-compose") as pool:
        pending: deque = deque()
        for item in items:
            pending.append(pool.submit(function, item))
            if len(pending) > threads + ahead:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()


def display_video(video_file: str, height: int = 400) -> None:
    """Show a video inline in a notebook, else print its path. Never blocks or raises."""
    try:
        if not is_notebook():
            print(f"Video saved to {video_file}")
            return
        from IPython.display import HTML, display

        with open(video_file, "rb") as handle:
            data = base64.b64encode(handle.read()).decode("ascii")
        if video_file.endswith(".gif"):
            html = f'<img src="data:image/gif;base64,{data}" style="height: {height}px;"/>'
        else:
            html = (
                f'<video autoplay loop controls style="height: {height}px;">'
                f'<source src="data:video/mp4;base64,{data}" type="video/mp4"/></video>'
            )
        display(HTML(html))
    except Exception as error:  # noqa: BLE001 - displaying is best effort
        print(f"Video saved to {video_file} (could not display it: {error})")


def make_video(
    observations: Sequence[dict[str, Any]],
    primary_obs: str,
    primary_obs_type: str,
    video_file: str,
    fps: int = 60,
    open_vid: bool = True,
    video_dims: tuple[int, int] | None = None,
    overlay_settings: Sequence[dict] | None = None,
    depth_clip: float | None = 10.0,
    observation_to_image=observation_to_image,
) -> str:
    """Build a video from a list of observation dicts (Habitat's ``viz_utils.make_video``).

    Parameters
    ----------
    observations : list of ``{uuid: array}`` dicts, one per frame.
    primary_obs, primary_obs_type : key and type (``"color"``, ``"depth"``, ``"semantic"``)
        of the full-frame image.
    video_file : output path; ``.mp4`` is appended when missing.
    fps : frames per second. open_vid : call ``display_video`` when done.
    video_dims : (width, height) of the output, applied after overlays, or None.
    overlay_settings : list of overlay dicts (module docstring), or None.
    depth_clip : meters mapped to white in depth images.

    Returns
    -------
    The path written (an ``.gif`` beside it if mp4 encoding is unavailable).
    """
    if not isinstance(video_file, str) or not video_file:
        raise ValueError(f"video_file must be a non-empty path string, got {video_file!r}")
    if isinstance(observations, str | bytes | dict) or not hasattr(observations, "__len__"):
        raise TypeError(
            f"observations must be a list of observation dicts, got {type(observations).__name__}"
        )
    if len(observations) == 0:
        raise ValueError("make_video: observations is empty, there is no frame to encode")
    check_fps(fps)
    if video_dims is not None:
        check_frame_size(_check_dims(video_dims, "video_dims")[::-1], "make_video: video_dims")
    else:
        for index, ob in enumerate(observations):
            if not isinstance(ob, dict) or primary_obs not in ob:
                raise KeyError(f"make_video: frame {index} has no observation {primary_obs!r}")
            check_frame_size(
                np.shape(ob[primary_obs]), f"make_video: frame {index} {primary_obs!r}"
            )
    if not video_file.endswith(".mp4"):
        video_file += ".mp4"
    print(f"Encoding the video: {video_file}")
    to_image = partial(observation_to_image, depth_clip=depth_clip)
    use_numpy = video_dims is None and observation_to_image is _observation_to_image

    def compose(ob: dict) -> np.ndarray:
        if use_numpy:  # the same pixels, composed with NumPy
            return compose_video_frame(
                ob, primary_obs, primary_obs_type, overlay_settings, depth_clip
            )
        frame = make_video_frame(
            ob, primary_obs, primary_obs_type, video_dims, overlay_settings, to_image
        )
        return np.asarray(frame)

    def frames() -> Iterable[np.ndarray]:
        if use_numpy and overlay_settings:  # resizing overlays (PIL, GIL released): 2 threads
            return _in_order_on_threads(compose, observations, COMPOSE_THREADS)
        return map(compose, observations)

    written = save_video(video_file, frames, fps=fps, n_frames=len(observations))
    if open_vid:
        display_video(written)
    return written
