"""Where and when the camera groups of one observation render: this process, its threads
and the render worker process.

:class:`engine.sensors.scene_render.SceneRenderer` turns the scene graph into render jobs, one
:class:`RenderJob` per group of sensors that share a camera and pose. Rendered one after
the other in this process they give the observation; :class:`RenderScheduler` gives the
same bits faster on two cores, in five steps (inside stage 4 of the bridge):

* **Place**: a new group renders in this process, or, when a worker process is allowed
  (``processes = 1``), the frame has several groups and this one is not the first and at
  least ``process_min_pixels`` large, in the worker (:class:`render.worker.RenderProcess`,
  started at the first such frame). A group keeps its place while it exists.
* **Submit**: the worker gets the meshes when they changed (versions of the static and
  moving parts), then this frame's poses and one :class:`render.worker.WorkerJob` per
  group, the :class:`render.settings.RenderSettings` inside. It starts at once.
* **Render here**: the groups of this process, on a thread pool when there are several
  (``threads``), and the top ``split`` rows of each full render the worker shares
  (``share_full_renders``): both processes rasterize and shade only their rows. Each
  frame is copied out while the worker may still be rendering.
* **Collect**: wait for the worker's frames, copy them out (below the split rows of a
  shared render).
* **Balance**: move the split row so that both processes finish together
  (:func:`engine.sensors.frame_sharing.next_split`).

A worker that dies (or an error in the pipe) is a :class:`render.worker.WorkerLost`: its
groups are rendered here from then on, with a warning (**crash fallback**). Threads alone
barely help: the renderer's many cache-sized NumPy passes hold the GIL most of the time (two
render threads measured 6 % faster than one); the worker has its own interpreter.
"""

from __future__ import annotations

import itertools
import time
import warnings
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from engine.sensors.cameras import CameraSensor
from engine.sensors.frame_sharing import copy_out, copy_rows, next_split, rows_there
from render.camera import Camera
from render.frame import FrameBuffers, band_rows, render_frame
from render.settings import DEFAULT_SETTINGS, RenderSettings
from render.views import LayeredView, SplitScene
from render.worker import RenderProcess, WorkerJob, WorkerLost

__all__ = ["GroupState", "RenderJob", "RenderScheduler"]

_VIEW_KEYS = itertools.count(1)


@dataclass
class GroupState:
    """What one group of sensors keeps between frames: where it renders (here: its
    :class:`render.views.LayeredView`; or in the worker process under ``key``), whether a
    static layer is kept and its signature, and the signature of its previous frame."""

    remote: bool = False
    view: LayeredView = field(default_factory=LayeredView)
    key: int = field(default_factory=lambda: next(_VIEW_KEYS))
    has_layer: bool = False
    layer_signature: tuple | None = None
    last_signature: tuple | None = None
    split: int = 0  # full renders of a worker's group: rows 0 .. split - 1 render here
    tile: FrameBuffers | None = None  # ... into these buffers
    tile_rows: int = 0  # this frame's rows rendered here (0: the worker renders all)
    ids: bool = True  # a sensor of the group reads the semantic ids


@dataclass
class RenderJob:
    """One group's render of this frame.

    Attributes
    ----------
    state : the group's :class:`GroupState`.
    mode : ``"full"``, ``"new layer"`` or ``"layer"`` (``render.views.MODES``).
    members : the group's sensors (they read its rgba, depth or ids).
    camera : the group's camera.
    world_from_camera : (4, 4) float64 pose.
    signature : what the group's static layer depends on (kept after the render).
    settings : the render settings.
    """

    state: GroupState
    mode: str
    members: list[CameraSensor]
    camera: Camera
    world_from_camera: np.ndarray
    signature: tuple
    settings: RenderSettings = DEFAULT_SETTINGS

    def render_here(self, scene: SplitScene) -> FrameBuffers:
        """Render the group in this process as ``mode`` says (its view's reused buffers).

        May run on a pool thread: it touches only this group's state and reads the scene.
        """
        state, mode = self.state, self.mode
        if mode == "layer" and state.view.layer is None:  # its layer was in the worker
            mode = "full"
        if mode == "full":
            scene.full()
        frame = state.view.render(
            mode, scene, self.camera, self.world_from_camera, ids=state.ids, settings=self.settings
        )
        state.has_layer = state.view.layer is not None
        state.last_signature = self.signature
        return frame

    def worker_job(self) -> WorkerJob:
        """This render as the worker's job (below the split rows of a shared render)."""
        rows = rows_there(self.state.split, self.mode, self.camera)
        return WorkerJob(
            self.state.key,
            self.mode,
            self.camera,
            self.world_from_camera,
            rows,
            self.state.ids,
            self.settings,
        )


class RenderScheduler:
    """Renders a frame's :class:`RenderJob` s here, on threads and in the worker process.

    Parameters
    ----------
    scene : the static and moving meshes (the caller updates them before each frame).
    threads : groups rendered in this process run on a pool of this many threads (1: none).
    processes : 1: a render worker process for groups after the first; 0: none.
    """

    def __init__(self, scene: SplitScene, threads: int, processes: int) -> None:
        self.scene = scene
        self.threads = threads
        self.processes = processes
        #: groups smaller than this (pixels) always render in this process: small frames
        #: cost less than the round trip to the worker
        self.process_min_pixels = 65_536
        #: a full render of the worker's group is shared: its top rows are shaded here too
        #: (balanced from frame to frame) when this process would otherwise wait
        self.share_full_renders = True
        self._pool: ThreadPoolExecutor | None = None
        self._pool_size = 0
        self._worker: RenderProcess | None = None
        self._worker_versions: tuple[int, int] = (-1, -1)  # (static, moving) it holds
        self._remote_states: list[GroupState] = []  # the groups placed in the worker

    def new_group(
        self, index: int, n_groups: int, resolution: tuple[int, int], ids: bool
    ) -> GroupState:
        """Place: the state of a new group, placed here or in the worker process
        (``index`` of ``n_groups`` of this frame; ``ids``: a sensor reads the ids)."""
        height, width = resolution
        remote = (
            self.processes > 0
            and n_groups > 1
            and index > 0
            and height * width >= self.process_min_pixels
        )
        state = GroupState(remote=remote, ids=ids)
        if remote:
            self._remote_states.append(state)
        return state

    def render(
        self, jobs: list[RenderJob], versions: tuple[int, int]
    ) -> list[dict[str, np.ndarray]]:
        """Submit, render here, collect, balance: every job's observations (uuid -> fresh
        array), in the order of ``jobs``.

        ``versions``: the (static, moving) mesh versions of ``scene``; the worker gets the
        meshes of a part again when its version changed.
        """
        remote = [job for job in jobs if job.state.remote]
        if remote and self.processes == 0:  # switched off: render them here from now on
            self._stop_worker(remote)
            remote = []
        if remote:
            try:
                self._submit(remote, versions)
            except WorkerLost as error:
                self._lose_worker(error, remote)
                remote = []
        local = [job for job in jobs if not job.state.remote]
        for job in remote:
            job.state.tile_rows = job.state.split if self._shares(job) else 0
        start = time.perf_counter()
        outputs = self._render_local_part(local, remote)
        busy_here = time.perf_counter() - start
        if remote:
            self._collect(remote, outputs, busy_here)
        return [outputs[id(job.state)] for job in jobs]

    def start(
        self, jobs: list[RenderJob], versions: tuple[int, int]
    ) -> Callable[[], list[dict[str, np.ndarray]]]:
        """Asynchronous rendering: place every group in the worker, submit them now (the
        worker renders while this process goes on) and return the function that collects
        the observations (in the order of ``jobs``). A group moved to the worker stays there
        and starts with a full render (its layer, if any, was here)."""
        for job in jobs:
            state = job.state
            if not state.remote:
                state.remote, state.has_layer, state.layer_signature = True, False, None
                self._remote_states.append(state)
                job.mode = "full"
            state.tile_rows = 0  # no row sharing: this process is busy with the physics
        self._submit(jobs, versions)

        def finish() -> list[dict[str, np.ndarray]]:
            outputs: dict[int, dict[str, np.ndarray]] = {}
            self._collect(jobs, outputs, 0.0)
            return [outputs[id(job.state)] for job in jobs]

        return finish

    @staticmethod
    def _shares(job: RenderJob) -> bool:
        """A full render of the worker's whose top rows render here."""
        return job.mode == "full" and job.state.split > 0

    def _render_local_part(
        self, local: list[RenderJob], remote: list[RenderJob]
    ) -> dict[int, dict[str, np.ndarray]]:
        """Render here: this process's groups and the top rows of shared renders, copied out
        (by ``id`` of the group state). On an error the worker's reply is taken first."""
        outputs: dict[int, dict[str, np.ndarray]] = {}
        try:
            for job, frame in zip(local, self._render_all_here(local), strict=True):
                outputs[id(job.state)] = copy_out(job.members, frame)
            for job in remote:
                if job.state.tile_rows:  # the top rows now, the worker's when they come
                    rows = job.state.tile_rows
                    outputs[id(job.state)] = copy_out(job.members, self._render_tile(job), rows)
        except BaseException:
            if remote and self._worker is not None:  # keep the worker in step
                try:
                    self._worker.collect()
                except Exception:  # noqa: BLE001, S110 - the first error is the one to see
                    pass
            raise
        return outputs

    def _collect(
        self, remote: list[RenderJob], outputs: dict[int, dict[str, np.ndarray]], busy_here: float
    ) -> None:
        """Collect and balance: the worker's frames into ``outputs``, then the balance; a lost
        worker's groups are rendered here."""
        worker = self._worker
        assert worker is not None  # remote jobs exist only with a live worker
        asked = time.perf_counter()
        try:
            collected = worker.collect()
            waited = time.perf_counter() - asked
        except WorkerLost as error:
            self._lose_worker(error, remote)
            collected, waited = {}, 0.0
            for job in remote:
                job.state.tile_rows = 0
                outputs[id(job.state)] = copy_out(job.members, job.render_here(self.scene))
        for job in remote:
            state = job.state
            if state.key not in collected:
                continue
            frame = collected[state.key]
            if state.tile_rows:  # below the rows rendered here
                copy_rows(job.members, frame, outputs[id(state)], state.tile_rows)
            else:
                outputs[id(state)] = copy_out(job.members, frame)
            state.last_signature = job.signature
        self._balance(remote, collected, busy_here, waited)

    def _render_tile(self, job: RenderJob) -> FrameBuffers:
        """The top ``split`` rows of a full render the worker shares."""
        state = job.state
        state.tile = render_frame(
            self.scene.full(),
            job.camera,
            job.world_from_camera,
            state.tile,
            True,
            (0, state.split),
            state.ids,
            job.settings,
        )
        return state.tile

    def _balance(
        self, remote: list[RenderJob], collected: dict, busy_here: float, waited: float = 0.0
    ) -> None:
        """Balance: move the split row of the worker's first full render so that both
        processes finish together (:func:`engine.sensors.frame_sharing.next_split`)."""
        full = [job for job in remote if job.mode == "full" and job.state.key in collected]
        if not full or not self.share_full_renders:
            return
        job = full[0]
        timings = collected[job.state.key].timings
        job.state.split = next_split(
            job.state.split, job.camera, timings, busy_here, waited, job.settings
        )

    def _render_all_here(self, local: list[RenderJob]) -> list[FrameBuffers]:
        """Render groups in this process, on the thread pool when there are several."""
        if any(job.mode == "full" for job in local):
            self.scene.full()  # built here, not on the pool's threads
        if self.threads > 1 and len(local) > 1:
            return list(self._thread_pool().map(lambda job: job.render_here(self.scene), local))
        return [job.render_here(self.scene) for job in local]

    def _submit(self, remote: list[RenderJob], versions: tuple[int, int]) -> None:
        """Submit: send the worker what changed (meshes) and its jobs of this frame."""
        if self._worker is None:
            self._worker = RenderProcess()
            self._worker_versions = (-1, -1)
        (static_version, moving_version), (sent_static, sent_moving) = (
            versions,
            self._worker_versions,
        )
        if (static_version, moving_version) != (sent_static, sent_moving):
            self._worker.set_meshes(
                self.scene.static.meshes if static_version != sent_static else None,
                self.scene.moving.meshes if moving_version != sent_moving else None,
            )
            self._worker_versions = (static_version, moving_version)
        for job in remote:
            job.state.has_layer = job.mode != "full"
            if job.state.split % band_rows(job.camera, job.settings):
                job.state.split = 0  # the settings changed the band size: start again
        self._worker.submit(
            self.scene.static.world_from_mesh,
            self.scene.moving.world_from_mesh,
            [job.worker_job() for job in remote],
        )

    def _lose_worker(self, error: Exception, remote: list[RenderJob]) -> None:
        """Crash fallback: render the worker's groups here (full renders) from now on."""
        warnings.warn(
            f"rigidsim: the render worker process failed ({error}); rendering in this "
            "process from now on",
            RuntimeWarning,
            stacklevel=5,
        )
        self._stop_worker(remote)
        self.processes = 0

    def _stop_worker(self, remote: list[RenderJob]) -> None:
        """Close the worker; its groups render here, starting with a full render."""
        for state in self._remote_states:
            state.remote, state.has_layer, state.layer_signature = False, False, None
        self._remote_states = []
        for job in remote:
            job.mode = "full"
        if self._worker is not None:
            self._worker.close()
            self._worker = None

    def _thread_pool(self) -> ThreadPoolExecutor:
        if self._pool is None or self._pool_size != self.threads:
            if self._pool is not None:
                self._pool.shutdown()
            self._pool = ThreadPoolExecutor(self.threads, thread_name_prefix="rigidsim-render")
            self._pool_size = self.threads
        return self._pool

    def close(self) -> None:
        """Stop the render threads and the worker process (the next frame starts them
        again; the layers the worker kept are gone)."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None
        if self._worker is not None:
            for state in self._remote_states:
                state.has_layer, state.layer_signature = False, None
            self._worker.close()
            self._worker = None
