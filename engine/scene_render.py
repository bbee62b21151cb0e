"""From the scene graph to sensor observations: the engine side of rendering.

The renderer (:mod:`render`) knows nothing of scene nodes; it takes :class:`render.RenderMesh`
arrays and camera poses. This module bridges the two, once per observation:

1. **Gather**: walk the scene graph from the root; every node's :class:`Drawable` s become
   render meshes posed by the node's world matrix (``world_from_mesh = node.world_matrix()``).
   Each drawable is *static* (the stage, STATIC objects: the ``static_drawables`` callback
   names them) or *moving* (everything else).
2. **Cache**: two :class:`render.RenderScene` s, the static meshes and the moving ones
   (:class:`render.views.SplitScene`), are rebuilt only when the set of drawables or their
   static/moving split changes (an object added or removed, a motion type changed);
   otherwise only the poses are updated. The full scene (static meshes first, then the
   moving ones) is built when first needed.
3. **Group**: sensors whose camera intrinsics and pose are equal share one rasterization
   (the tutorial's 1st-person color and depth cameras are one render).
4. **Render**: per group, with :func:`render.render_frame`, or, when nothing static changed
   since the group's previous frame, by drawing only the moving meshes over the group's
   kept static frame (:func:`render.render_over_layer`: bit for bit the same image); both
   in :class:`render.views.LayeredView`. The first group renders in this process; the
   others (when at least ``process_min_pixels`` large) in a **render worker process**
   (:class:`render.worker.RenderProcess`, started at the first such frame), which holds its
   own copy of the meshes, gets the poses each frame and returns the frame through shared
   memory. Threads cannot do this: the renderer's many cache-sized NumPy passes hold the
   GIL most of the time (two render threads measured 6 % faster than one). A full render
   of a worker's group is **shared**: this process renders its top ``split`` rows and the
   worker the others (each rasterizes and shades only its rows), and ``split`` moves from frame
   to frame so that both processes finish together (the tutorial's robot: the 1st-person
   render here, the costlier 3rd-person one mostly there). Results do not depend on where
   or how a frame was split (tested bit for bit); a worker that dies is replaced by
   renders in this process, with a warning.
5. **Copy**: each sensor gets a fresh copy of its buffer (COLOR -> rgba, DEPTH -> depth,
   SEMANTIC -> ids). Back faces are culled, as GPU renderers do: closed meshes look the same
   and cost about a third fewer fragments.

The static layer of a group is valid while its *signature* is unchanged: the identity,
material flags and exact world matrices (bytes) of every static drawable, the camera's
intrinsics and exact pose, back-face culling, the drawables' light setups (the simulator's
``set_light_setup`` makes new :class:`render.shade.Lights`) and the defaults of
:mod:`render.shade`.
Comparing the matrices themselves (rather than trusting motion types) makes the check exact:
a STATIC object moved by hand, or carried by a moving node, simply invalidates the layer.
A layer is built at the second frame with the same signature (a moving camera never pays
for one). Mesh arrays are assumed not to be modified in place (as for ``RenderScene``).

Switches (attributes of :class:`SceneRenderer`, for teaching and the tests):
``static_layer`` (False: every frame is a full render), ``processes`` (0: no worker
process; default 1 on two cores or more, ``RIGIDSIM_RENDER_PROCESSES=0`` turns it off),
``share_full_renders`` (False: the worker renders its groups alone) and ``threads`` (the
groups rendered in this process on a thread pool: 1, one thread).
"""

from __future__ import annotations

import itertools
import os
import time
import warnings
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from engine.frame_sharing import buffer_name, copy_out, copy_rows, next_split, rows_there
from engine.scene_node import Drawable, SceneNode
from engine.sensors import CameraSensor, SensorSubType
from render import shade
from render.camera import Camera
from render.frame import FrameBuffers, render_frame
from render.scene import RenderMesh
from render.shade import Lights
from render.views import LayeredView, SplitScene
from render.worker import RenderProcess, WorkerLost

__all__ = ["SceneRenderer", "default_render_processes", "default_render_threads"]


def default_render_threads() -> int:
    """Render threads by default: ``RIGIDSIM_RENDER_THREADS`` if set, else min(2, cores)."""
    value = os.environ.get("RIGIDSIM_RENDER_THREADS", "")
    if value:
        threads = int(value)
        if threads < 1:
            raise ValueError(f"RIGIDSIM_RENDER_THREADS must be >= 1, got {value!r}")
        return threads
    return max(1, min(2, os.cpu_count() or 1))


def default_render_processes() -> int:
    """Render worker processes by default: ``RIGIDSIM_RENDER_PROCESSES`` if set (0 or 1),
    else 1 on a machine with two cores or more."""
    value = os.environ.get("RIGIDSIM_RENDER_PROCESSES", "")
    if value:
        processes = int(value)
        if processes not in (0, 1):
            raise ValueError(f"RIGIDSIM_RENDER_PROCESSES must be 0 or 1, got {value!r}")
        return processes
    return 1 if (os.cpu_count() or 1) >= 2 else 0


def _render_mesh(drawable: Drawable, lights: Lights | None = None) -> RenderMesh:
    """A drawable's mesh arrays as a :class:`render.RenderMesh` (pose set per frame), lit by
    ``lights`` (None: the renderer's default setup)."""
    mesh = drawable.mesh
    return RenderMesh(
        vertices=mesh.vertices,
        faces=mesh.faces,
        vertex_colors=mesh.vertex_colors,
        uvs=mesh.uvs if mesh.texture is not None else None,
        texture=mesh.texture,
        base_color=mesh.base_color,
        lit=bool(drawable.lit),
        semantic_id=int(drawable.semantic_id),
        lights=lights,
    )


def _light_signature() -> tuple:
    """The light setup the lit meshes are shaded with (part of a static layer's signature)."""
    return (shade.LIGHT_DIRECTIONS.tobytes(), float(shade.AMBIENT), float(shade.DIFFUSE))


_VIEW_KEYS = itertools.count(1)


@dataclass
class _GroupState:
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


class SceneRenderer:
    """Renders the sensors of agents from a scene graph root (see the module docstring).

    Parameters
    ----------
    root : the scene graph's root node.
    static_drawables : returns the ``id`` s of the drawables that are static (the stage,
        STATIC objects); None: every drawable is moving (no static layer).
    lights_for : light setup key -> :class:`render.shade.Lights` (the simulator's light
        setups); None: every lit mesh uses the renderer's default setup.
    static_layer : reuse a group's static frame while its signature is unchanged.
    threads : render independent sensor groups on this many threads (1: no pool).
    processes : 1: render all groups but the first in a worker process (started at the
        first frame with two groups of at least ``process_min_pixels`` pixels); 0: none.
    """

    #: groups smaller than this (pixels) always render in this process: small frames
    #: cost less than the round trip to the worker
    process_min_pixels = 65_536
    #: a full render of the worker's group is shared: its top rows are shaded here too
    #: (balanced from frame to frame) when this process would otherwise wait for the worker
    share_full_renders = True

    def __init__(
        self,
        root: SceneNode,
        static_drawables: Callable[[], set[int]] | None = None,
        lights_for: Callable[[str], Lights | None] | None = None,
        static_layer: bool = True,
        threads: int | None = None,
        processes: int | None = None,
    ) -> None:
        self.root = root
        self.static_drawables = static_drawables
        self.lights_for = lights_for
        self.static_layer = static_layer
        self.threads = default_render_threads() if threads is None else int(threads)
        self.processes = default_render_processes() if processes is None else int(processes)
        self._scene_key: tuple = ()
        self._drawables: list[Drawable] = []  # keeps the key's ids alive (no reuse)
        self._lights: list[Lights | None] = []  # the same for the drawables' light setups
        self._scene = SplitScene()
        self._n_static = 0
        self._static_version = 0
        self._moving_version = 0
        self._groups: dict[tuple, _GroupState] = {}
        self._pool: ThreadPoolExecutor | None = None
        self._pool_size = 0
        self._worker: RenderProcess | None = None
        self._worker_versions: tuple[int, int] = (-1, -1)  # (static, moving) it holds
        #: how the last observation rendered each group: "full", "new layer" or "layer"
        self.last_modes: dict[tuple, str] = {}
        #: where: "here" or "worker" (the worker process)
        self.last_places: dict[tuple, str] = {}

    # -- stages 1-2 ----------------------------------------------------------------------
    def _gather(self) -> tuple[list[Drawable], list[np.ndarray], list[bool]]:
        """Stage 1: every drawable under the root, its node's world matrix and whether it
        is static; static drawables first (stable order within each kind)."""
        static_ids = self.static_drawables() if self.static_drawables is not None else set()
        drawables, poses, is_static = [], [], []
        for node in self.root.descendants():
            if node.drawables:
                world = node.world_matrix()
                for drawable in node.drawables:
                    drawables.append(drawable)
                    poses.append(world)
                    is_static.append(id(drawable) in static_ids)
        order = sorted(range(len(drawables)), key=lambda i: not is_static[i])
        return (
            [drawables[i] for i in order],
            [poses[i] for i in order],
            [is_static[i] for i in order],
        )

    def _update_scenes(self) -> bytes:
        """Stage 2: rebuild the render scenes if drawables changed, else update poses.

        Returns the static drawables' world matrices as bytes (their exact poses)."""
        drawables, poses, is_static = self._gather()
        lights = [
            self.lights_for(d.light_setup_key) if self.lights_for else None for d in drawables
        ]
        # a new light setup is a new Lights object: its id changes the key (no id reuse while
        # self._lights keeps the previous ones alive)
        key = tuple(
            (id(d), id(d.mesh), d.lit, d.semantic_id, s, id(light))
            for d, s, light in zip(drawables, is_static, lights, strict=True)
        )
        if key != self._scene_key:
            n_static = sum(is_static)
            meshes = [_render_mesh(d, light) for d, light in zip(drawables, lights, strict=True)]
            static = None
            if key[:n_static] != self._scene_key[: self._n_static] or n_static != self._n_static:
                self._static_version += 1  # the static layers of every group are stale
                static = meshes[:n_static]
            self._scene.set_meshes(static=static, moving=meshes[n_static:])
            self._moving_version += 1
            self._scene_key, self._drawables, self._n_static = key, drawables, n_static
            self._lights = lights
        stacked = np.array(poses, dtype=np.float64).reshape(len(poses), 4, 4)
        self._scene.set_poses(stacked[: self._n_static], stacked[self._n_static :])
        return self._scene.static.world_from_mesh.tobytes()

    @staticmethod
    def _camera(sensor: CameraSensor) -> Camera:
        (height, width), hfov, near, far, subtype, ortho_scale = sensor.camera_key()
        kind = "orthographic" if subtype is SensorSubType.ORTHOGRAPHIC else "pinhole"
        return Camera(
            (height, width), hfov=hfov, near=near, far=far, subtype=kind, ortho_scale=ortho_scale
        )

    # -- stages 3-5 ----------------------------------------------------------------------
    def observe(
        self, sensors: list[CameraSensor] | dict[str, CameraSensor]
    ) -> dict[str, np.ndarray]:
        """Stages 3-5: one observation per sensor, keyed by uuid (fresh arrays).

        ``sensors`` is a list of sensors or an agent's ``sensors`` dict (uuid -> sensor).
        """
        if isinstance(sensors, dict):
            sensors = list(sensors.values())
        static_poses = self._update_scenes()
        self.last_modes, self.last_places = {}, {}
        groups: dict[tuple, list[CameraSensor]] = {}
        for sensor in sensors:
            pose = sensor.world_from_camera()
            key = (sensor.camera_key(), pose.tobytes())  # equal intrinsics and pose: share
            groups.setdefault(key, []).append(sensor)
        lights = _light_signature()
        jobs = []
        for index, ((camera_key, pose_bytes), members) in enumerate(groups.items()):
            name = tuple(sensor.uuid for sensor in members)
            signature = (self._static_version, static_poses, camera_key, pose_bytes, lights)
            # per sensor objects: agents may reuse uuids (the signature keeps it exact anyway)
            state = self._groups.get(tuple(map(id, members)))
            if state is None:
                state = self._groups[tuple(map(id, members))] = _GroupState(
                    remote=self._wants_worker(index, len(groups), camera_key[0]),
                    ids=any(buffer_name(sensor) == "ids" for sensor in members),
                )
            mode = self._choose_mode(state, signature)
            camera = self._camera(members[0])
            pose = np.frombuffer(pose_bytes).reshape(4, 4)
            jobs.append((state, mode, members, camera, pose, signature))
            self.last_modes[name] = mode
        observations: dict[str, np.ndarray] = {}
        for (state, _, members, *_), arrays in zip(jobs, self._render_jobs(jobs), strict=True):
            name = tuple(sensor.uuid for sensor in members)
            self.last_places[name] = "worker" if state.remote else "here"
            if state.remote and state.tile_rows:
                self.last_places[name] = "shared"
            observations.update(arrays)
        return {sensor.uuid: observations[sensor.uuid] for sensor in sensors}

    def _wants_worker(self, index: int, n_groups: int, resolution: tuple[int, int]) -> bool:
        """Where a new group renders: all groups but the first of a frame go to the worker
        process when there is one and they are large enough."""
        height, width = resolution
        return (
            self.processes > 0
            and n_groups > 1
            and index > 0
            and height * width >= self.process_min_pixels
        )

    def _render_jobs(self, jobs: list[tuple]) -> list[dict[str, np.ndarray]]:
        """Render every group: the worker's first (it starts at once), then this process's
        (on the thread pool when there are several), then wait for the worker's.

        Returns per group its members' observations (uuid -> fresh array). What this
        process rendered is copied out before waiting for the worker, which may still be
        rendering: the copies overlap its work. A full render shared with the worker gets
        its top rows from here and the rest from there.
        """
        remote = [job for job in jobs if job[0].remote]
        if remote and self.processes == 0:  # switched off: render them here from now on
            self._stop_worker(remote)
            remote = []
        if remote:
            try:
                self._submit(remote)
            except WorkerLost as error:
                self._lose_worker(error, remote)
                remote = []
        worker = self._worker
        assert worker is not None or not remote  # remote jobs exist only with a live worker
        local = [job for job in jobs if not job[0].remote]
        tiles = [job for job in remote if job[1] == "full" and job[0].split > 0]
        tiled = {id(job[0]) for job in tiles}
        for job in remote:
            job[0].tile_rows = job[0].split if id(job[0]) in tiled else 0
        start = time.perf_counter()
        outputs: dict[int, dict[str, np.ndarray]] = {}
        try:
            for job, frame in zip(local, self._render_all_here(local), strict=True):
                outputs[id(job[0])] = copy_out(job[2], frame)
            for job in tiles:  # the top rows now, the worker's rows when they come
                outputs[id(job[0])] = copy_out(job[2], self._render_tile(*job), job[0].split)
        except BaseException:
            if remote:  # keep the worker in step: take its reply before raising
                try:
                    worker.collect()  # type: ignore[union-attr]
                except Exception:  # noqa: BLE001, S110 - the first error is the one to see
                    pass
            raise
        busy_here = time.perf_counter() - start
        if remote:
            asked = time.perf_counter()
            try:
                collected = worker.collect()  # type: ignore[union-attr]
                waited = time.perf_counter() - asked
            except WorkerLost as error:
                self._lose_worker(error, remote)
                collected, waited = {}, 0.0
                for job in remote:
                    job[0].tile_rows = 0
                    outputs[id(job[0])] = copy_out(job[2], self._render_here(*job))
            for job in remote:
                if job[0].key not in collected:
                    continue
                frame, first = collected[job[0].key], job[0].tile_rows
                if first:  # below the rows rendered here
                    copy_rows(job[2], frame, outputs[id(job[0])], first)
                else:
                    outputs[id(job[0])] = copy_out(job[2], frame)
                job[0].last_signature = job[5]
            self._balance(remote, collected, busy_here, waited)
        return [outputs[id(job[0])] for job in jobs]

    def _render_tile(
        self, state: _GroupState, mode: str, members, camera: Camera, pose: np.ndarray, *_
    ) -> FrameBuffers:
        """The top ``state.split`` rows of a full render the worker shares."""
        state.tile = render_frame(
            self._scene.full(), camera, pose, state.tile, True, (0, state.split), state.ids
        )
        return state.tile

    def _balance(
        self, remote: list[tuple], collected: dict, busy_here: float, waited: float = 0.0
    ) -> None:
        """Move the split row of the worker's first full render so that both processes
        finish together (:func:`engine.frame_sharing.next_split`)."""
        full = [job for job in remote if job[1] == "full" and job[0].key in collected]
        if not full or not self.share_full_renders:
            return
        state, camera = full[0][0], full[0][3]
        timings = collected[state.key].timings
        state.split = next_split(state.split, camera, timings, busy_here, waited)

    def _render_all_here(self, local: list[tuple]) -> list[FrameBuffers]:
        """Render groups in this process, on the thread pool when there are several."""
        if any(job[1] == "full" for job in local):
            self._scene.full()  # built here, not on the pool's threads
        if self.threads > 1 and len(local) > 1:
            return list(self._thread_pool().map(lambda job: self._render_here(*job), local))
        return [self._render_here(*job) for job in local]

    def _submit(self, remote: list[tuple]) -> None:
        """Send the worker what changed (meshes) and its jobs of this frame."""
        if self._worker is None:
            self._worker = RenderProcess()
            self._worker_versions = (-1, -1)
        static_version, moving_version = self._static_version, self._moving_version
        sent_static, sent_moving = self._worker_versions
        if (static_version, moving_version) != (sent_static, sent_moving):
            self._worker.set_meshes(
                self._scene.static.meshes if static_version != sent_static else None,
                self._scene.moving.meshes if moving_version != sent_moving else None,
            )
            self._worker_versions = (static_version, moving_version)
        for state, mode, *_ in remote:
            state.has_layer = mode != "full"
        self._worker.submit(
            self._scene.static.world_from_mesh,
            self._scene.moving.world_from_mesh,
            [
                (state.key, mode, camera, pose, rows_there(state.split, mode, camera), state.ids)
                for state, mode, _, camera, pose, _ in remote
            ],
        )

    def _lose_worker(self, error: Exception, remote: list[tuple]) -> None:
        """The worker died: render its groups here (full renders) from now on."""
        warnings.warn(
            f"rigidsim: the render worker process failed ({error}); rendering in this "
            "process from now on",
            RuntimeWarning,
            stacklevel=4,
        )
        self._stop_worker(remote)
        self.processes = 0

    def _stop_worker(self, remote: list[tuple]) -> None:
        """Close the worker; its groups render here, starting with a full render."""
        for state in self._groups.values():
            if state.remote:
                state.remote, state.has_layer, state.layer_signature = False, False, None
        for job_index, job in enumerate(remote):
            state = job[0]
            remote[job_index] = (state, "full", *job[2:])
        if self._worker is not None:
            self._worker.close()
            self._worker = None

    def _choose_mode(self, state: _GroupState, signature: tuple) -> str:
        """How to render a group: ``"layer"`` (over its valid static layer), ``"new layer"``
        (second frame with this signature: keep a static layer first) or ``"full"``."""
        if self.static_layer and state.has_layer and state.layer_signature == signature:
            return "layer"
        state.has_layer, state.layer_signature = False, None
        if self.static_layer and state.last_signature == signature:
            state.layer_signature = signature
            return "new layer"
        return "full"

    def _thread_pool(self) -> ThreadPoolExecutor:
        if self._pool is None or self._pool_size != self.threads:
            if self._pool is not None:
                self._pool.shutdown()
            self._pool = ThreadPoolExecutor(self.threads, thread_name_prefix="rigidsim-render")
            self._pool_size = self.threads
        return self._pool

    def _render_here(
        self,
        state: _GroupState,
        mode: str,
        members: list[CameraSensor],
        camera: Camera,
        pose: np.ndarray,
        signature: tuple,
    ) -> FrameBuffers:
        """Render one group in this process as ``mode`` says.

        May run on a pool thread: it touches only this group's state and reads the scenes.
        """
        if mode == "layer" and state.view.layer is None:  # its layer was in the worker
            mode = "full"
        if mode == "full":
            self._scene.full()
        frame = state.view.render(mode, self._scene, camera, pose, ids=state.ids)
        state.has_layer = state.view.layer is not None
        state.last_signature = signature
        return frame

    def close(self) -> None:
        """Stop the render threads and the worker process (a new observation starts them
        again)."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None
        if self._worker is not None:
            for state in self._groups.values():
                state.has_layer, state.layer_signature = False, None
            self._worker.close()
            self._worker = None
