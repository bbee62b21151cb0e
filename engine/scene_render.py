"""From the scene graph to sensor observations: the engine side of rendering.

The renderer (:mod:`render`) knows nothing of scene nodes; it takes :class:`render.RenderMesh`
arrays and camera poses. This module bridges the two, once per observation:

1. **Gather**: walk the scene graph from the root; every node's :class:`Drawable` s become
   render meshes posed by the node's world matrix (``world_from_mesh = node.world_matrix()``).
   Each drawable is *static* (the stage, STATIC objects: the ``static_drawables`` callback
   names them) or *moving* (everything else).
2. **Cache**: two :class:`render.RenderScene` s, the static meshes and the moving ones, are
   rebuilt only when the set of drawables or their static/moving split changes (an object
   added or removed, a motion type changed); otherwise only the poses are updated. The
   full scene (static meshes first, then the moving ones) is built when first needed.
3. **Group**: sensors whose camera intrinsics and pose are equal share one rasterization
   (the tutorial's 1st-person color and depth cameras are one render).
4. **Render**: per group, with :func:`render.render_frame`, or, when nothing static changed
   since the group's previous frame, by drawing only the moving meshes over the group's
   kept static frame (:func:`render.render_over_layer`: bit for bit the same image).
   Independent groups render on a thread pool (NumPy releases the GIL in its large
   operations; the tutorial's 1st- and 3rd-person cameras use both cores).
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
``static_layer`` (False: every frame is a full render) and ``threads`` (1: one thread).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from engine.scene_node import Drawable, SceneNode
from engine.sensors import CameraSensor, SensorSubType, SensorType
from render import shade
from render.camera import Camera
from render.frame import FrameBuffers, StaticLayer, render_frame, render_over_layer
from render.scene import RenderMesh, RenderScene
from render.shade import Lights

__all__ = ["SceneRenderer", "default_render_threads"]


def default_render_threads() -> int:
    """Render threads by default: ``RIGIDSIM_RENDER_THREADS`` if set, else min(2, cores)."""
    value = os.environ.get("RIGIDSIM_RENDER_THREADS", "")
    if value:
        threads = int(value)
        if threads < 1:
            raise ValueError(f"RIGIDSIM_RENDER_THREADS must be >= 1, got {value!r}")
        return threads
    return max(1, min(2, os.cpu_count() or 1))


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


@dataclass
class _GroupState:
    """What one group of sensors keeps between frames: buffers, its static layer and the
    signature of its previous frame."""

    buffers: FrameBuffers | None = None
    static_buffers: FrameBuffers | None = None
    layer: StaticLayer | None = None
    layer_signature: tuple | None = None
    last_signature: tuple | None = None


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
    """

    def __init__(
        self,
        root: SceneNode,
        static_drawables: Callable[[], set[int]] | None = None,
        lights_for: Callable[[str], Lights | None] | None = None,
        static_layer: bool = True,
        threads: int | None = None,
    ) -> None:
        self.root = root
        self.static_drawables = static_drawables
        self.lights_for = lights_for
        self.static_layer = static_layer
        self.threads = default_render_threads() if threads is None else int(threads)
        self._scene_key: tuple = ()
        self._drawables: list[Drawable] = []  # keeps the key's ids alive (no reuse)
        self._lights: list[Lights | None] = []  # the same for the drawables' light setups
        self._static_scene = RenderScene([])
        self._moving_scene = RenderScene([])
        self._full_scene: RenderScene | None = None
        self._n_static = 0
        self._static_version = 0
        self._groups: dict[tuple, _GroupState] = {}
        self._pool: ThreadPoolExecutor | None = None
        self._pool_size = 0
        #: how the last observation rendered each group: "full", "new layer" or "layer"
        self.last_modes: dict[tuple, str] = {}

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
            if key[:n_static] != self._scene_key[: self._n_static] or n_static != self._n_static:
                self._static_version += 1  # the static layers of every group are stale
                self._static_scene = RenderScene(meshes[:n_static])
            self._moving_scene = RenderScene(meshes[n_static:])
            self._full_scene = None
            self._scene_key, self._drawables, self._n_static = key, drawables, n_static
            self._lights = lights
        for index, pose in enumerate(poses):
            if index < self._n_static:
                self._static_scene.world_from_mesh[index] = pose
            else:
                self._moving_scene.world_from_mesh[index - self._n_static] = pose
        if self._full_scene is not None:
            self._set_full_poses(self._full_scene)
        return self._static_scene.world_from_mesh.tobytes()

    def _full(self) -> RenderScene:
        """The scene of every drawable, static ones first (built when first needed)."""
        if self._full_scene is None:
            self._full_scene = RenderScene(self._static_scene.meshes + self._moving_scene.meshes)
            self._set_full_poses(self._full_scene)
        return self._full_scene

    def _set_full_poses(self, full_scene: RenderScene) -> None:
        full_scene.world_from_mesh[: self._n_static] = self._static_scene.world_from_mesh
        full_scene.world_from_mesh[self._n_static :] = self._moving_scene.world_from_mesh

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
        self.last_modes = {}
        groups: dict[tuple, list[CameraSensor]] = {}
        for sensor in sensors:
            pose = sensor.world_from_camera()
            key = (sensor.camera_key(), pose.tobytes())  # equal intrinsics and pose: share
            groups.setdefault(key, []).append(sensor)
        lights = _light_signature()
        jobs = []
        for (camera_key, pose_bytes), members in groups.items():
            name = tuple(sensor.uuid for sensor in members)
            signature = (self._static_version, static_poses, camera_key, pose_bytes, lights)
            # per sensor objects: agents may reuse uuids (the signature keeps it exact anyway)
            state = self._groups.setdefault(tuple(map(id, members)), _GroupState())
            mode = self._choose_mode(state, signature)
            pose = np.frombuffer(pose_bytes).reshape(4, 4)
            jobs.append((state, mode, members, pose, signature))
            self.last_modes[name] = mode
        if any(job[1] == "full" for job in jobs):
            self._full()  # built here, not on the pool's threads
        if self.threads > 1 and len(jobs) > 1:
            results = list(self._thread_pool().map(lambda job: self._render_group(*job), jobs))
        else:
            results = [self._render_group(*job) for job in jobs]
        observations: dict[str, np.ndarray] = {}
        for part in results:
            observations.update(part)
        return {sensor.uuid: observations[sensor.uuid] for sensor in sensors}

    def _choose_mode(self, state: _GroupState, signature: tuple) -> str:
        """How to render a group: ``"layer"`` (over its valid static layer), ``"new layer"``
        (second frame with this signature: keep a static layer first) or ``"full"``."""
        if self.static_layer and state.layer is not None and state.layer_signature == signature:
            return "layer"
        state.layer = state.layer_signature = None  # stale: free its memory
        if self.static_layer and state.last_signature == signature:
            return "new layer"
        return "full"

    def _thread_pool(self) -> ThreadPoolExecutor:
        if self._pool is None or self._pool_size != self.threads:
            if self._pool is not None:
                self._pool.shutdown()
            self._pool = ThreadPoolExecutor(self.threads, thread_name_prefix="rigidsim-render")
            self._pool_size = self.threads
        return self._pool

    def _render_group(
        self,
        state: _GroupState,
        mode: str,
        members: list[CameraSensor],
        pose: np.ndarray,
        signature: tuple,
    ) -> dict[str, np.ndarray]:
        """Render one group as ``mode`` says and copy each member's buffer.

        Runs on a pool thread: it touches only this group's state and reads the scenes.
        """
        camera = self._camera(members[0])
        if mode == "new layer":
            state.static_buffers = render_frame(
                self._static_scene, camera, pose, state.static_buffers, cull_back_faces=True
            )
            state.layer = StaticLayer.from_frame(state.static_buffers)
            state.layer_signature = signature
        if mode == "full":  # the full scene was built before the threads started
            frame = render_frame(self._full(), camera, pose, state.buffers, cull_back_faces=True)
        elif state.layer is not None:  # "layer" and "new layer" have a valid static layer
            frame = render_over_layer(
                state.layer, self._moving_scene, camera, pose, state.buffers, cull_back_faces=True
            )
        else:
            raise RuntimeError(f"render mode {mode!r} without a static layer")
        state.buffers, state.last_signature = frame, signature
        return {sensor.uuid: _buffer_for(sensor.spec.sensor_type, frame) for sensor in members}

    def close(self) -> None:
        """Stop the render threads (a new observation starts them again)."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None


def _buffer_for(sensor_type: SensorType, frame: FrameBuffers) -> np.ndarray:
    """A fresh copy of the buffer a sensor type reads."""
    if sensor_type is SensorType.COLOR:
        return frame.rgba.copy()
    if sensor_type is SensorType.DEPTH:
        return frame.depth.copy()
    return frame.ids.copy()
