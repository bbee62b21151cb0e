"""Encoding frames to files: mp4 (H.264 through imageio-ffmpeg) or, failing that, a GIF.

``save_video`` streams uint8 frames (RGB, RGBA or gray) through a
:class:`BackgroundVideoWriter`: a thread takes each frame (optionally turning an item into
a frame first, the tutorial job's composing) and appends it to an imageio writer, so the
caller (simulation, rendering, composing) goes on while ffmpeg encodes in its own process.
H.264 with yuv420p needs even sides: odd frames lose their last row or column. ffmpeg gets
RGB, or RGBA as it is when the first frame is RGBA (ffmpeg drops alpha itself: no copy).
The encoder's settings are ``X264_PRESET``, ``X264_CRF`` and ``X264_THREADS`` (measured
below).

``render.video`` (composing frames, ``make_video``) builds on this module and re-exports it.
"""

from __future__ import annotations

import os
import queue
import threading
import time
from collections.abc import Callable, Iterable, Sized
from typing import Any

import imageio
import numpy as np
from tqdm.auto import tqdm

#: videos longer than this get a tqdm progress bar while encoding
PROGRESS_BAR_MIN_FRAMES = 100
#: x264's speed preset and quality (constant rate factor) for mp4 files. On 180 composed
#: frames of the tutorial's robot (544 x 720, moving 3rd-person camera, overlays):
#: ``medium`` (x264's default) 15.5 ms of encoder CPU a frame; ``veryfast`` crf 23 7.4 ms,
#: 331 KB, 34.8 dB PSNR; ``superfast`` crf 25 4.8 ms, 483 KB, 35.1 dB: the same quality for
#: a third less CPU, in files about 1.5x larger
X264_PRESET = "superfast"
X264_CRF = 25
#: x264 threads: one thread needed 10 % less CPU a frame than x264's own choice (4.4 against
#: 4.9 ms, the same file) and still encodes a frame in 3.6 ms, faster than frames come
X264_THREADS = 1


def mp4_options(fps: int) -> dict:
    """imageio writer options of rigidsim's mp4 files: H.264 (libx264, ``X264_PRESET``,
    ``X264_CRF``, ``X264_THREADS``), any frame size (``macro_block_size=1``: no resizing to
    multiples of 16)."""
    return {
        "fps": fps,
        "format": "FFMPEG",
        "macro_block_size": 1,
        "output_params": [
            *("-preset", X264_PRESET, "-crf", str(X264_CRF)),
            *("-threads", str(X264_THREADS)),
        ],
    }


class BackgroundVideoWriter:
    """An imageio writer fed from a background thread.

    ``append(item)`` queues ``item`` (at most ``max_queue`` wait; then ``append`` blocks)
    and returns; the thread turns it into a frame with ``prepare(item)`` (default: the
    item itself) and appends it to the file as ``save_video`` does (RGB, or RGBA when the
    first frame is, with even sides: ``_to_even_frame``). An
    error on the thread is raised by the next ``append`` or by ``close``.

    Attributes: ``busy_seconds`` (time the thread spent preparing and encoding) and
    ``wait_seconds`` (time callers were blocked in ``append`` and ``close``).
    """

    _STOP = object()

    def __init__(self, path: str, options: dict, prepare=None, max_queue: int = 8) -> None:
        self._writer = imageio.get_writer(path, mode="I", **options)
        self._prepare = prepare
        self._queue: queue.Queue = queue.Queue(max_queue)
        self._error: BaseException | None = None
        self._reported = False
        self.busy_seconds = 0.0
        self.wait_seconds = 0.0
        self.frames = 0
        self._channels: int | None = None  # 3 (RGB) or 4 (RGBA) bytes per pixel to ffmpeg
        self._ffmpeg = options.get("format") == "FFMPEG"  # GIFs always get RGB
        self._thread = threading.Thread(target=self._run, name="rigidsim-encoder", daemon=True)
        self._thread.start()

    def append(self, item: Any) -> None:
        """Queue one frame (or an item ``prepare`` turns into one)."""
        self._raise_error()
        start = time.perf_counter()
        self._queue.put(item)
        self.wait_seconds += time.perf_counter() - start
        self.frames += 1

    def _run(self) -> None:
        while True:
            item = self._queue.get()
            if item is self._STOP:
                return
            if self._error is not None:
                continue  # drain: the caller must never block on a dead writer
            start = time.perf_counter()
            try:
                frame = item if self._prepare is None else self._prepare(item)
                frame = np.asarray(frame)
                if self._channels is None:  # the first frame sets ffmpeg's input layout
                    rgba = self._ffmpeg and frame.ndim == 3 and frame.shape[2] == 4
                    self._channels = 4 if rgba else 3
                self._writer.append_data(_to_even_frame(frame, self._channels))
            except BaseException as error:  # noqa: BLE001 - re-raised on the caller's thread
                self._error = error
            self.busy_seconds += time.perf_counter() - start

    def _raise_error(self) -> None:
        """Raise the thread's error on the caller's thread, once."""
        if self._error is not None and not self._reported:
            self._reported = True
            raise self._error

    def close(self) -> None:
        """Wait for the queued frames, finish the file; raise a thread error if any."""
        start = time.perf_counter()
        if self._thread.is_alive():
            self._queue.put(self._STOP)
            self._thread.join()
        try:
            self._writer.close()
        finally:
            self.wait_seconds += time.perf_counter() - start
        self._raise_error()

    def __enter__(self) -> BackgroundVideoWriter:
        return self

    def __exit__(self, *exc_info: Any) -> None:
        if exc_info[0] is None:
            self.close()
        else:  # an error in the caller: stop the thread, keep the caller's error
            self._reported = True
            try:
                self.close()
            except Exception:  # noqa: BLE001, S110 - the caller's error is the one to see
                pass


def save_video(
    video_file: str,
    frames: Iterable[np.ndarray] | Callable[[], Iterable[np.ndarray]],
    fps: int = 60,
    n_frames: int | None = None,
) -> str:
    """Encode uint8 frames (RGB, RGBA or gray) to ``video_file`` (mp4), else to a GIF.

    ``frames`` may be a sequence or a callable returning a fresh iterator (so that the GIF
    fallback can start over without holding every frame in memory); ``n_frames`` (default
    ``len(frames)`` when available) enables the progress bar above
    ``PROGRESS_BAR_MIN_FRAMES``. Returns the path written (``.gif`` on fallback).
    """
    check_fps(fps)
    if isinstance(frames, Sized) and not callable(frames):
        for index, frame in enumerate(frames):  # type: ignore[arg-type]
            check_frame_size(np.shape(frame), f"save_video: frame {index}")
    make_frames = frames if callable(frames) else (lambda: iter(frames))
    if n_frames is None and isinstance(frames, Sized):
        n_frames = len(frames)
    if n_frames == 0:
        raise ValueError(f"save_video: no frames to write to {video_file!r}")
    try:
        _write_frames(video_file, make_frames(), n_frames, mp4_options(fps))
        return video_file
    except Exception as error:  # noqa: BLE001 - any encoder failure falls back to GIF
        gif_file = os.path.splitext(video_file)[0] + ".gif"
        print(f"mp4 encoding failed ({error}); writing {gif_file} instead")
        _write_frames(gif_file, make_frames(), n_frames, {"duration": 1000.0 / fps, "loop": 0})
        return gif_file


def check_fps(fps: object) -> float:
    """``fps`` as a float: a finite number > 0, else ValueError naming it (an encoder given
    a negative rate writes nothing, silently)."""
    if isinstance(fps, bool) or not isinstance(fps, int | float | np.integer | np.floating):
        raise ValueError(f"fps must be a number of frames per second > 0, got {fps!r}")
    if not np.isfinite(float(fps)) or float(fps) <= 0.0:
        raise ValueError(f"fps must be finite and > 0, got {fps!r}")
    return float(fps)


def check_frame_size(shape: tuple, what: str) -> None:
    """Refuse a frame H.264 cannot hold: it is cropped to even sides, so H and W >= 2."""
    if len(shape) < 2 or shape[0] < 2 or shape[1] < 2:
        raise ValueError(
            f"{what} has shape {tuple(shape)}; a video frame needs height and width >= 2 "
            "(frames are cropped to even sides)"
        )


def _write_frames(
    path: str, frames: Iterable[np.ndarray], n_frames: int | None, options: dict
) -> None:
    """Stream frames to an imageio writer, with a progress bar for long videos.

    The frames are produced on this thread while a background thread feeds the encoder.
    """
    show_bar = n_frames is not None and n_frames > PROGRESS_BAR_MIN_FRAMES
    with BackgroundVideoWriter(path, options) as writer:
        for frame in tqdm(
            frames, desc=f"Encoding video: {path}", total=n_frames, disable=not show_bar
        ):
            writer.append(frame)


def _to_even_frame(frame: np.ndarray, channels: int = 3) -> np.ndarray:
    """(H, W, ``channels``) uint8 with even H and W (H.264 with yuv420p needs them).

    ``channels`` 3 gives RGB (gray replicated, alpha dropped); 4 gives RGBA (alpha 255
    added to RGB and gray frames), which ffmpeg takes as ``rgba`` and converts to yuv420p
    itself, ignoring alpha: an RGBA frame then goes to the encoder without a copy.
    """
    if frame.ndim == 2:
        frame = np.repeat(frame[:, :, None], 3, axis=2)  # gray -> RGB
    if channels == 3:
        frame = frame[..., :3]  # drop alpha
    elif frame.shape[2] == 3:
        opaque = np.full(frame.shape[:2] + (1,), 255, np.uint8)
        frame = np.concatenate([frame, opaque], axis=2)  # RGB -> RGBA, alpha 255
    return np.ascontiguousarray(frame[: frame.shape[0] // 2 * 2, : frame.shape[1] // 2 * 2])
