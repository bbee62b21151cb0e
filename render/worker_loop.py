"""The render worker process's side: its state and the loop that serves the caller's pipe.

:func:`serve_fd` is the worker's entry point (``python -c`` started by
:class:`render.worker.RenderProcess`). The worker holds its own copy of the scene
(:class:`render.views.SplitScene`), one :class:`render.views.LayeredView` per view key and
the shared block that view renders into (:mod:`render.worker_jobs`); it runs the same view
code as the caller's process, so a view gives the same bits wherever it is rendered.
Messages: ``("lights", {token: Lights})``, ``("meshes", static, moving)`` (None:
unchanged), ``("forget", keys)``, ``("frame", static_poses, moving_poses, [(job,
block_name)])`` (replied ``("done", [(key, timings, n_fragments)])``) and ``("stop",)``; an
exception while handling one is replied as ``("error", exception, traceback)``.
"""

from __future__ import annotations

import pickle
import traceback
from multiprocessing import resource_tracker, shared_memory
from multiprocessing.connection import Connection
from typing import Any

import numpy as np

from render import lights as _lights
from render.scene import RenderMesh
from render.views import LayeredView, SplitScene
from render.worker_jobs import WorkerJob, frame_on_block

__all__ = ["serve_fd"]


# ------------------------------------------------------------------------------------------
# The worker process
# ------------------------------------------------------------------------------------------
class _Worker:
    """The worker's state: the scene, the light setups by token, views and their blocks."""

    def __init__(self) -> None:
        self.scene = SplitScene()
        self.lights: dict[int, _lights.Lights] = {}
        self.views: dict[int, LayeredView] = {}
        self.blocks: dict[int, shared_memory.SharedMemory] = {}

    def meshes(self, encoded: list[dict]) -> list[RenderMesh]:
        """RenderMesh objects from their fields; ``lights`` is a token (see ``_encode``)."""
        meshes = []
        for fields in encoded:
            fields = dict(fields)
            token = fields.pop("lights_token")
            fields["lights"] = None if token is None else self._light(token)
            meshes.append(RenderMesh(**fields))
        return meshes

    def _light(self, token: int) -> _lights.Lights:
        return _lights.DEFAULT_LIGHTS if token == 0 else self.lights[token]

    def handle(self, message: tuple) -> tuple | None:
        kind = message[0]
        if kind == "lights":
            self.lights.update(message[1])
        elif kind == "meshes":
            static, moving = message[1], message[2]
            self.scene.set_meshes(
                None if static is None else self.meshes(static),
                None if moving is None else self.meshes(moving),
            )
        elif kind == "forget":
            for key in message[1]:
                self.views.pop(key, None)
                block = self.blocks.pop(key, None)
                if block is not None:
                    block.close()
        elif kind == "frame":
            _, static_poses, moving_poses, jobs = message
            self.scene.set_poses(static_poses, moving_poses)
            return ("done", [self.render(job, block_name) for job, block_name in jobs])
        else:
            raise ValueError(f"unknown message {kind!r}")
        return None

    def render(self, job: WorkerJob, block_name: str) -> tuple[int, dict, int]:
        """Render ``job`` into its shared block (attached at the first job of its key)."""
        key, camera = job.key, job.camera
        view = self.views.get(key)
        if view is None or self.blocks[key].name != block_name:
            block = shared_memory.SharedMemory(name=block_name)
            _untrack(block)  # the caller owns (and unlinks) it
            self.blocks[key] = block
            view = self.views[key] = LayeredView()
            view.out = frame_on_block(block.buf, camera.resolution)
            view.out.zkey = np.empty(camera.height * camera.width, np.uint64)
        frame = view.render(
            job.mode, self.scene, camera, job.world_from_camera, job.rows, job.ids, job.settings
        )
        return key, frame.timings, frame.n_fragments


def _untrack(block: shared_memory.SharedMemory) -> None:
    """Attaching registers a block with the resource tracker, which would unlink it when
    this process exits (Python < 3.13): the creator owns it."""
    try:
        resource_tracker.unregister(block._name, "shared_memory")  # type: ignore[attr-defined]  # noqa: SLF001
    except (AttributeError, KeyError, ValueError):
        pass


def serve_fd(fd: int) -> None:
    """Entry point of the worker process: serve the pipe end ``fd``."""
    _serve(Connection(fd))


def _serve(conn: Any) -> None:
    """The worker's loop: handle messages until ``("stop",)`` or the caller is gone."""
    worker = _Worker()
    while True:
        try:
            message = conn.recv()
        except (EOFError, OSError):
            break
        if message[0] == "stop":
            break
        try:
            reply = worker.handle(message)
        except BaseException as error:  # noqa: BLE001 - reported to the caller
            reply = ("error", _picklable(error), traceback.format_exc())
        if reply is not None or message[0] == "frame":
            conn.send(reply)
    for block in worker.blocks.values():
        block.close()


def _picklable(error: BaseException) -> BaseException:
    try:
        pickle.loads(pickle.dumps(error))
        return error
    except Exception:  # noqa: BLE001 - any exception that does not travel
        return RuntimeError(f"{type(error).__name__}: {error}")
