"""Rendering views of one scene in a worker process: the second core without the GIL.

NumPy releases the GIL only inside each of its operations; a renderer made of many
cache-sized passes (bands of 16k pixels, a few microseconds each) holds it most of the time,
so two render *threads* measured hardly faster than one (the tutorial's robot frames: 39 ms
of CPU per frame on one thread, 37 ms of wall time on two). A worker *process* has its own
interpreter and GIL: the caller renders one view while the worker renders another.

Pieces (plain arrays only, like the rest of :mod:`render`):

* :class:`LayeredView` and :class:`SplitScene` (:mod:`render.views`, re-exported here): what
  one view keeps between frames and how it is rendered in a *mode*, and the scene split into
  static and moving meshes. The caller's process and the worker run this same code, so a
  view gives the same bits wherever it is rendered.
* :class:`RenderProcess`: the caller's handle on one worker process: a fresh interpreter
  (``python -c``, talking over a ``multiprocessing`` pipe), so that, unlike the ``spawn``
  start method, a caller's script without ``if __name__ == "__main__"`` is not run again.
  The worker holds its own copy of the scene: the meshes are sent once when they change
  (``set_meshes``), then each frame sends only the mesh poses and, per view, the mode, the
  camera, its pose and the render settings (``submit`` of :class:`WorkerJob` s). The
  worker renders into a block of shared memory per view (``multiprocessing.shared_memory``:
  color, depth, ids) and replies; ``collect``
  returns :class:`FrameBuffers` views of those blocks, valid until the next ``submit``.
  A job may name ``rows`` of a full render (``render_frame``'s ``rows``): the worker
  rasterizes and shades only those rows, the caller renders the other rows of the same
  frame itself, and the two parts make the whole frame.
  Nothing is shared mutably: the worker never sees the caller's objects, only copies.
  This module is the caller's side.
* :class:`WorkerJob`, :class:`WorkerLost` and the shared block layout
  (:mod:`render.worker_jobs`, re-exported here): what the two sides exchange.
* ``serve_fd`` (:mod:`render.worker_loop`, re-exported here): the worker process's state
  and the loop that serves the pipe.

Bit-identical results: the worker unpickles exactly the caller's arrays (float64 poses,
meshes, :class:`Lights`), gets each view's :class:`render.settings.RenderSettings` inside
its :class:`WorkerJob` (no module state to mirror), keeps the identity of light setups
(``DEFAULT_LIGHTS`` maps to the worker's own, which selects the same formula) and runs the
same functions. ``tests/render/test_worker.py`` checks frames
of scenes mixing every material against in-process renders, bit for bit.

A worker that dies (killed, out of memory) raises :class:`WorkerLost` at the next call, so
that the caller can render locally instead; an exception raised while rendering (bad
input) is raised again in the caller.
"""

from __future__ import annotations

import multiprocessing
import os
import subprocess
import sys
import weakref
from multiprocessing import shared_memory
from typing import Any

import numpy as np

from render import lights as _lights
from render.frame import FrameBuffers
from render.scene import RenderMesh
from render.views import LayeredView, SplitScene
from render.worker_jobs import WorkerJob, WorkerLost, block_size, frame_on_block
from render.worker_loop import serve_fd

__all__ = [
    "LayeredView",
    "RenderProcess",
    "SplitScene",
    "WorkerJob",
    "WorkerLost",
    "serve_fd",
]


# ------------------------------------------------------------------------------------------
# The caller's handle
# ------------------------------------------------------------------------------------------
def _close_process(conn: Any, process: Any, blocks: dict, owner: int) -> None:
    """Stop the worker and free the shared blocks (also run by the finalizer); only in the
    process that started it (a forked child inherits the handle but must not stop it)."""
    if os.getpid() != owner:
        return
    try:
        conn.send(("stop",))
    except (OSError, ValueError):
        pass
    try:
        process.wait(timeout=5)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(timeout=5)
    conn.close()
    for block in blocks.values():
        _release(block)
    blocks.clear()


def _release(block: shared_memory.SharedMemory) -> None:
    """Unlink a block the caller created; close it unless arrays still view it (then the
    memory goes when they do)."""
    try:
        block.unlink()
    except FileNotFoundError:
        pass
    try:
        block.close()
    except BufferError:
        pass


class RenderProcess:
    """A render worker process and the scene it holds (see the module docstring).

    Usage per frame: ``set_meshes`` when the static or moving meshes changed, ``submit``
    the poses and views to render, do other work, then ``collect`` the frames.
    """

    def __init__(self) -> None:
        self._conn, child = multiprocessing.Pipe()
        environment = dict(os.environ)
        # the caller's import path (a notebook may have extended sys.path)
        environment["PYTHONPATH"] = os.pathsep.join(path for path in sys.path if path)
        command = f"from render.worker_loop import serve_fd; serve_fd({child.fileno()})"
        try:
            self._process = subprocess.Popen(
                [sys.executable, "-c", command], pass_fds=[child.fileno()], env=environment
            )
        finally:
            child.close()
        self._blocks: dict[int, shared_memory.SharedMemory] = {}
        self._resolutions: dict[int, tuple[int, int]] = {}
        self._lights: dict[int, _lights.Lights] = {}  # token -> Lights (kept alive)
        self._tokens: dict[int, int] = {}  # id(Lights) -> token
        self._pending: list[int] | None = None
        self._finalizer = weakref.finalize(
            self, _close_process, self._conn, self._process, self._blocks, os.getpid()
        )

    @property
    def alive(self) -> bool:
        return self._finalizer.alive and self._process.poll() is None

    def _send(self, message: tuple) -> None:
        if not self._finalizer.alive:
            raise WorkerLost("the render worker was closed")
        try:
            self._conn.send(message)
        except (OSError, ValueError) as error:
            raise WorkerLost(f"the render worker is gone ({error})") from error

    def _receive(self) -> tuple:
        try:
            while not self._conn.poll(1.0):
                if self._process.poll() is not None:
                    raise WorkerLost(
                        f"the render worker died (exit code {self._process.returncode})"
                    )
            return self._conn.recv()
        except (EOFError, OSError) as error:
            raise WorkerLost(f"the render worker is gone ({error})") from error

    def set_meshes(
        self, static: list[RenderMesh] | None = None, moving: list[RenderMesh] | None = None
    ) -> None:
        """Send the static and/or the moving meshes (None: unchanged) to the worker."""
        encoded = [None if part is None else self._encode(part) for part in (static, moving)]
        self._send(("meshes", *encoded))

    def _encode(self, meshes: list[RenderMesh]) -> list[dict]:
        """Mesh fields with light setups as tokens (0: ``DEFAULT_LIGHTS``), sending new
        setups first: identity (one group per setup object) survives the copy."""
        new = {}
        encoded = []
        for mesh in meshes:
            fields = {name: getattr(mesh, name) for name in mesh.__dataclass_fields__}
            lights = fields.pop("lights")
            if lights is None:
                token = None
            elif lights is _lights.DEFAULT_LIGHTS:
                token = 0
            else:
                token = self._tokens.get(id(lights))
                if token is None or self._lights[token] is not lights:
                    token = len(self._lights) + 1
                    self._tokens[id(lights)] = token
                    self._lights[token] = lights
                    new[token] = lights
            fields["lights_token"] = token
            encoded.append(fields)
        if new:
            self._send(("lights", new))
        return encoded

    def submit(
        self,
        static_poses: np.ndarray,
        moving_poses: np.ndarray,
        jobs: list[WorkerJob],
    ) -> None:
        """Start rendering ``jobs`` (one :class:`WorkerJob` per view, its settings with it)
        with the meshes at these poses. ``collect`` waits for the frames."""
        if self._pending is not None:
            raise RuntimeError("collect the previous frames before submitting new ones")
        for job in jobs:
            if not isinstance(job, WorkerJob):
                raise TypeError(f"RenderProcess.submit takes WorkerJob items, got {job!r}")
        message = [(job, self._block(job.key, job.camera.resolution).name) for job in jobs]
        self._send(("frame", static_poses, moving_poses, message))
        self._pending = [job.key for job in jobs]

    def _block(self, key: int, resolution: tuple[int, int]) -> shared_memory.SharedMemory:
        block = self._blocks.get(key)
        if block is not None and self._resolutions[key] != tuple(resolution):
            self.forget([key])
            block = None
        if block is None:
            block = shared_memory.SharedMemory(create=True, size=block_size(resolution))
            self._blocks[key] = block
            self._resolutions[key] = (int(resolution[0]), int(resolution[1]))
        return block

    def collect(self) -> dict[int, FrameBuffers]:
        """Wait for the submitted frames: view key -> FrameBuffers on the shared blocks
        (``zkey`` empty; valid until the next ``submit``; copy what you keep)."""
        if self._pending is None:
            raise RuntimeError("nothing was submitted")
        keys, self._pending = self._pending, None
        reply = self._receive()
        if reply[0] == "error":
            raise reply[1] from RuntimeError("in the render worker:\n" + reply[2])
        frames = {}
        for key, timings, n_fragments in reply[1]:
            frame = frame_on_block(self._blocks[key].buf, self._resolutions[key])
            frame.timings, frame.n_fragments = timings, n_fragments
            frames[key] = frame
        assert sorted(frames) == sorted(keys)
        return frames

    def forget(self, keys: list[int]) -> None:
        """Drop views (their layers and shared blocks) in the worker and here."""
        keys = [key for key in keys if key in self._blocks]
        if not keys:
            return
        self._send(("forget", keys))
        for key in keys:
            self._resolutions.pop(key)
            _release(self._blocks.pop(key))

    def close(self) -> None:
        """Stop the worker and free its shared memory (safe to call twice)."""
        self._finalizer()
