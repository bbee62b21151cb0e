"""What the caller and the render worker process exchange: jobs, the lost-worker error and
the shared memory blocks the worker renders into.

A :class:`WorkerJob` is one view to render this frame (its key, mode, camera, pose, rows and
:class:`render.settings.RenderSettings`); it travels pickled through the pipe. Each view's
frame lives in one ``multiprocessing.shared_memory`` block laid out as color
``(H, W, 4) uint8``, then depth ``(H, W) float32``, then ids ``(H, W) uint32``: 12 bytes a
pixel; both sides view it as :class:`render.frame.FrameBuffers` (:func:`frame_on_block`).
The caller's side is :mod:`render.worker`, the worker's loop :mod:`render.worker_loop`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from render.camera import Camera
from render.frame import FrameBuffers
from render.settings import DEFAULT_SETTINGS, RenderSettings

__all__ = ["WorkerJob", "WorkerLost", "block_size", "frame_on_block"]


class WorkerLost(RuntimeError):
    """The render worker process is gone (it died or was closed)."""


@dataclass(frozen=True)
class WorkerJob:
    """One view the worker renders this frame (``RenderProcess.submit``).

    Attributes
    ----------
    key : the view's key: its layers and shared block in the worker.
    mode : one of ``render.views.MODES``.
    camera : intrinsics and clip planes.
    world_from_camera : (4, 4) float64 pose.
    rows : a full render's rows to shade (``render_frame``'s ``rows``), None: all.
    ids : False when no sensor reads the semantic ids.
    settings : the :class:`RenderSettings` to render with (travels with the job).
    """

    key: int
    mode: str
    camera: Camera
    world_from_camera: np.ndarray
    rows: tuple[int, int] | None = None
    ids: bool = True
    settings: RenderSettings = DEFAULT_SETTINGS

    def __post_init__(self) -> None:
        if not isinstance(self.settings, RenderSettings):
            raise TypeError(f"WorkerJob.settings must be RenderSettings, got {self.settings!r}")
        pose = np.asarray(self.world_from_camera, np.float64)
        object.__setattr__(self, "world_from_camera", pose)


# ------------------------------------------------------------------------------------------
# Shared memory blocks: color (H, W, 4) uint8, depth (H, W) float32, ids (H, W) uint32
# ------------------------------------------------------------------------------------------
def block_size(resolution: tuple[int, int]) -> int:
    """Bytes of one view's block: 4 (color) + 4 (depth) + 4 (ids) per pixel."""
    height, width = resolution
    return height * width * 12


def frame_on_block(
    buffer: memoryview | None, resolution: tuple[int, int], zkey=None
) -> FrameBuffers:
    """FrameBuffers whose rgba, depth and ids are views of a shared block."""
    if buffer is None:  # SharedMemory.buf is None once the block is closed
        raise RuntimeError("render worker: the shared frame block is closed")
    height, width = resolution
    n = height * width
    rgba = np.ndarray((height, width, 4), np.uint8, buffer, 0)
    depth = np.ndarray((height, width), np.float32, buffer, 4 * n)
    ids = np.ndarray((height, width), np.uint32, buffer, 8 * n)
    if zkey is None:
        zkey = np.empty(0, np.uint64)
    return FrameBuffers(rgba, depth, ids, zkey)
