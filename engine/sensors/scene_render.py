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
   (the tutorial's 1st-person color and depth cameras are one render): one
   :class:`engine.sensors.render_scheduler.RenderJob` per group.
4. **Render**: per group, with :func:`render.render_frame`, or, when nothing static changed
   since the group's previous frame, by drawing only the moving meshes over the group's
   kept static frame (:func:`render.render_over_layer`: bit for bit the same image); both
   in :class:`render.views.LayeredView`, with the renderer's ``settings``
   (:class:`render.settings.RenderSettings`). The plain loop renders the groups one after
   the other in this process; with threads or a render worker process, the
   :class:`engine.sensors.render_scheduler.RenderScheduler` places them (and shares full renders
   between the two processes): the same bits, tested.
5. **Copy**: each sensor gets a fresh copy of its buffer (COLOR -> rgba, DEPTH -> depth,
   SEMANTIC -> ids). Back faces are culled, as GPU renderers do: closed meshes look the same
   and cost about a third fewer fragments.

The static layer of a group is valid while its *signature* is unchanged: the identity,
material flags, light setups and exact world matrices (bytes) of every static drawable
(the simulator's ``set_light_setup`` makes new :class:`render.shade.Lights`) and the
camera's intrinsics and exact pose.
Comparing the matrices themselves (rather than trusting motion types) makes the check exact:
a STATIC object moved by hand, or carried by a moving node, simply invalidates the layer.
A layer is built at the second frame with the same signature (a moving camera never pays
for one). Mesh arrays are assumed not to be modified in place (as for ``RenderScene``).

Switches (attributes of :class:`SceneRenderer`, for teaching and the tests):
``static_layer`` (False: every frame is a full render), ``settings`` (the renderer's
kernels and working-set sizes), and, on ``scheduler``: ``processes`` (0: no worker process;
default 1 on two cores or more, ``RIGIDSIM_RENDER_PROCESSES=0`` turns it off),
``share_full_renders`` (False: the worker renders its groups alone), ``process_min_pixels``
and ``threads`` (the groups rendered in this process on a thread pool: 1, one thread).
``threads`` and ``processes`` are also attributes of the renderer (the same values).
"""

from __future__ import annotations

import os
from collections.abc import Callable

import numpy as np

from engine.scene.graph import Drawable, SceneNode
from engine.sensors.cameras import CameraSensor, SensorSubType
from engine.sensors.frame_sharing import buffer_name, copy_out
from engine.sensors.render_scheduler import GroupState, RenderJob, RenderScheduler
from render.camera import Camera
from render.lights import Lights
from render.scene import RenderMesh
from render.settings import DEFAULT_SETTINGS, RenderSettings
from render.views import SplitScene
from render.worker import WorkerLost

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
    settings : the :class:`render.settings.RenderSettings` of every render.
    """

    def __init__(
        self,
        root: SceneNode,
        static_drawables: Callable[[], set[int]] | None = None,
        lights_for: Callable[[str], Lights | None] | None = None,
        static_layer: bool = True,
        threads: int | None = None,
        processes: int | None = None,
        settings: RenderSettings = DEFAULT_SETTINGS,
    ) -> None:
        if not isinstance(settings, RenderSettings):
            raise TypeError(f"settings must be a render.RenderSettings, got {settings!r}")
        self.root = root
        self.static_drawables = static_drawables
        self.lights_for = lights_for
        self.static_layer = static_layer
        self.settings = settings
        self._scene_key: tuple = ()
        self._drawables: list[Drawable] = []  # keeps the key's ids alive (no reuse)
        self._lights: list[Lights | None] = []  # the same for the drawables' light setups
        self._scene = SplitScene()
        self._n_static = 0
        self._static_version = 0
        self._moving_version = 0
        self._groups: dict[tuple, GroupState] = {}
        self.scheduler = RenderScheduler(
            self._scene,
            default_render_threads() if threads is None else int(threads),
            default_render_processes() if processes is None else int(processes),
        )
        #: how the last observation rendered each group: "full", "new layer" or "layer"
        self.last_modes: dict[tuple, str] = {}
        #: where: "here", "worker" (the worker process) or "shared" (both)
        self.last_places: dict[tuple, str] = {}

    @property
    def threads(self) -> int:
        """Render threads of this process (``scheduler.threads``)."""
        return self.scheduler.threads

    @threads.setter
    def threads(self, value: int) -> None:
        self.scheduler.threads = int(value)

    @property
    def processes(self) -> int:
        """Render worker processes, 0 or 1 (``scheduler.processes``)."""
        return self.scheduler.processes

    @processes.setter
    def processes(self, value: int) -> None:
        self.scheduler.processes = int(value)

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
        return self.observe_later(sensors)()

    def observe_later(
        self, sensors: list[CameraSensor] | dict[str, CameraSensor]
    ) -> Callable[[], dict[str, np.ndarray]]:
        """Stages 1-3 now, stages 4-5 when the returned function is called.

        Every pose is copied now (the render scenes' poses, each group's camera pose), so
        the scene graph may move before the call (asynchronous rendering,
        :mod:`engine.sensors.async_render`); nothing else may use this renderer until then.
        """
        if isinstance(sensors, dict):
            sensors = list(sensors.values())
        static_poses = self._update_scenes()
        jobs = self._group(sensors, static_poses)
        self.last_modes = {_names(job): job.mode for job in jobs}
        versions = (self._static_version, self._moving_version)
        return lambda: self._render_jobs(jobs, list(sensors), versions)

    def observe_in_worker(
        self, sensors: list[CameraSensor]
    ) -> Callable[[], dict[str, np.ndarray]] | None:
        """Asynchronous rendering: stages 1-3 now and every group submitted to the render
        worker process at once (it renders while this process steps the physics); the
        returned function collects the observations. None when there is no worker
        (``processes = 0``) or it could not start: use :meth:`observe_later`."""
        if self.scheduler.processes == 0:
            return None
        static_poses = self._update_scenes()
        jobs = self._group(list(sensors), static_poses)
        self.last_modes = {_names(job): job.mode for job in jobs}
        versions = (self._static_version, self._moving_version)
        try:
            collect = self.scheduler.start(jobs, versions)
        except WorkerLost as error:
            self.scheduler._lose_worker(error, jobs)
            return lambda: self._render_jobs(jobs, list(sensors), versions)

        def finish() -> dict[str, np.ndarray]:
            observations: dict[str, np.ndarray] = {}
            for job, arrays in zip(jobs, collect(), strict=True):
                self.last_places[_names(job)] = "worker"
                observations.update(arrays)
            return {sensor.uuid: observations[sensor.uuid] for sensor in sensors}

        self.last_places = {}
        return finish

    def _render_jobs(
        self, jobs: list[RenderJob], sensors: list[CameraSensor], versions: tuple[int, int]
    ) -> dict[str, np.ndarray]:
        """Stages 4-5: render the groups and copy each sensor's buffer out."""
        if self.scheduler.threads > 1 or any(job.state.remote for job in jobs):
            per_group = self.scheduler.render(jobs, versions)
        else:  # the plain loop: one group after the other, here
            per_group = [copy_out(job.members, job.render_here(self._scene)) for job in jobs]
        observations: dict[str, np.ndarray] = {}
        self.last_places = {}
        for job, arrays in zip(jobs, per_group, strict=True):
            place = "shared" if job.state.tile_rows else "worker"
            self.last_places[_names(job)] = place if job.state.remote else "here"
            observations.update(arrays)
        return {sensor.uuid: observations[sensor.uuid] for sensor in sensors}

    def _group(self, sensors: list[CameraSensor], static_poses: bytes) -> list[RenderJob]:
        """Stage 3: one job per group of sensors with equal intrinsics and pose."""
        groups: dict[tuple, list[CameraSensor]] = {}
        for sensor in sensors:
            pose = sensor.world_from_camera()
            key = (sensor.camera_key(), pose.tobytes())  # equal intrinsics and pose: share
            groups.setdefault(key, []).append(sensor)
        jobs = []
        for index, ((camera_key, pose_bytes), members) in enumerate(groups.items()):
            signature = (self._static_version, static_poses, camera_key, pose_bytes)
            # per sensor objects: agents may reuse uuids (the signature keeps it exact anyway)
            state = self._groups.get(tuple(map(id, members)))
            if state is None:
                ids = any(buffer_name(sensor) == "ids" for sensor in members)
                state = self.scheduler.new_group(index, len(groups), camera_key[0], ids)
                self._groups[tuple(map(id, members))] = state
            mode = self._choose_mode(state, signature)
            pose = np.frombuffer(pose_bytes).reshape(4, 4)
            camera = self._camera(members[0])
            jobs.append(RenderJob(state, mode, members, camera, pose, signature, self.settings))
        return jobs

    def _choose_mode(self, state: GroupState, signature: tuple) -> str:
        """How to render a group: ``"layer"`` (over its valid static layer), ``"new layer"``
        (second frame with this signature: keep a static layer first) or ``"full"``."""
        if self.static_layer and state.has_layer and state.layer_signature == signature:
            return "layer"
        state.has_layer, state.layer_signature = False, None
        if self.static_layer and state.last_signature == signature:
            state.layer_signature = signature
            return "new layer"
        return "full"

    def close(self) -> None:
        """Stop the render threads and the worker process (a new observation starts them
        again)."""
        self.scheduler.close()


def _names(job: RenderJob) -> tuple[str, ...]:
    """The uuids of a job's sensors (the keys of ``last_modes`` and ``last_places``)."""
    return tuple(sensor.uuid for sensor in job.members)
