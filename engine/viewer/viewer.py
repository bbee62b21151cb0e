"""The live viewer: a simulator's world in 3D in the browser, with teaching overlays.

One line in a notebook opens it::

    viewer = Viewer(sim)          # reads the scene graph once
    viewer.show()                 # the k3d widget, in Jupyter (or viewer.serve() for a page)
    sim.step_physics(1 / 60)      # ...
    viewer.update()               # redraw: poses, contacts, islands, ...

``Viewer(sim, follow=True)`` (or :meth:`Viewer.follow`) redraws after every
``sim.step_physics`` call instead: it wraps that method **on this simulator instance only**
(an attribute in the instance's ``__dict__`` that shadows the class's method), and
:meth:`Viewer.unfollow` / :meth:`Viewer.close` deletes the attribute again. A simulator that
no viewer follows runs the class's method untouched, so a step that nobody watches costs
exactly what it cost before (the tests check that no overlay query runs then).

Overlays are switches (:class:`~engine.viewer.overlays.OverlaySwitches`), given as keyword
arguments (``Viewer(sim, aabbs=True, navmesh=True, path_goal=[x, y, z])``) or changed later
with :meth:`Viewer.set_overlays`. Every overlay reads public queries only (see
:mod:`engine.viewer.overlays`).

:meth:`Viewer.start_recording` keeps every drawn frame; :meth:`Viewer.replay` returns them
as a :class:`~engine.viewer.replay.Replay` (time slider, self-contained HTML).

Where the page is shown: :meth:`Viewer.show` returns k3d's Jupyter widget (live in
JupyterLab and Notebook 7); :meth:`Viewer.serve` starts
:class:`~engine.viewer.server.LiveServer` on 127.0.0.1 for a browser tab (or a notebook
whose frontend cannot run widgets), and :meth:`Viewer.close` stops it.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Any

import numpy as np

from engine.viewer.drawing import SceneDrawing
from engine.viewer.overlays import Frame, OverlaySwitches, capture_frame, navmesh_mesh
from engine.viewer.replay import Replay
from engine.viewer.server import LiveServer
from engine.viewer.settings import DEFAULT_HOST
from engine.viewer.world_view import collect_parts

__all__ = ["Viewer", "default_camera"]

_SWITCH_NAMES = tuple(f.name for f in fields(OverlaySwitches))


def default_camera(sim: Any) -> list[float] | None:
    """A k3d camera ``[eye, target, up]`` looking at the objects from where agent 0 stands.

    The target is the centre of the objects' translations. The eye starts at agent 0's head
    (its node plus the configured ``height``), inside the agent's room so that no wall hides
    the objects, and moves horizontally 1 m towards the target (half way when it is closer),
    past the agent's own frusta. Without agents the eye is 1.6 m back along +Z and 1.2 m up.
    None (fit the whole scene) when there are no objects.
    """
    objects = sim.get_rigid_object_manager().get_objects_by_handle_substring("").values()
    centers = np.array([np.asarray(o.translation, dtype=np.float64) for o in objects])
    if len(centers) == 0:
        return None
    target = centers.mean(axis=0)
    if sim.agents:
        agent = sim.agents[0]
        head = np.asarray(agent.get_state().position, dtype=np.float64)
        head = head + np.array([0.0, float(agent.agent_config.height), 0.0])
        toward = target - head
        toward[1] = 0.0  # move horizontally
        distance = float(np.linalg.norm(toward))
        eye = head + (toward / distance * min(1.0, distance / 2) if distance > 1e-6 else 0.0)
    else:
        eye = target + np.array([0.0, 1.2, 1.6])
    return [*eye.tolist(), *target.tolist(), 0.0, 1.0, 0.0]


class Viewer:
    """A 3D view of a :class:`~engine.simulator.simulator.Simulator` with switchable overlays.

    Parameters
    ----------
    sim : Simulator
        The simulator to show; its scene graph is read now and again whenever the set of
        objects changes.
    follow : bool
        Redraw after every ``sim.step_physics`` call (see the module docstring).
    camera : (9,) float or None
        ``[eye xyz, target xyz, up xyz]`` in world coordinates; None picks
        :func:`default_camera`.
    height : int
        Widget height in pixels in a notebook.
    **overlays
        Switches of :class:`~engine.viewer.overlays.OverlaySwitches` (``contacts``,
        ``aabbs``, ``sleeping``, ``navmesh``, ``path``, ``velocity``, ``agents``,
        ``path_goal``).
    """

    def __init__(
        self,
        sim: Any,
        follow: bool = False,
        camera: Any = None,
        height: int = 480,
        **overlays: Any,
    ) -> None:
        if not hasattr(sim, "get_active_scene_graph") or not hasattr(sim, "step_physics"):
            raise TypeError(f"Viewer needs a Simulator, got {type(sim).__name__}")
        unknown = sorted(set(overlays) - set(_SWITCH_NAMES))
        if unknown:
            raise TypeError(f"unknown overlay switch(es) {unknown}; known: {list(_SWITCH_NAMES)}")
        if isinstance(height, bool) or not isinstance(height, int) or height < 1:
            raise ValueError(f"height must be a positive int (pixels), got {height!r}")
        self.sim = sim
        self.switches = OverlaySwitches(**overlays)
        self.height = height
        self._camera = self._check_camera(camera)
        self._recording: list[Frame] | None = None
        self._server: LiveServer | None = None
        self._followed_sim: Any = None
        self.frame: Frame | None = None
        self._drawing: SceneDrawing | None = None
        self.rebuild()
        if follow:
            self.follow()

    # ------------------------------------------------------------------------------------------
    # building and drawing
    # ------------------------------------------------------------------------------------------
    @staticmethod
    def _check_camera(camera: Any) -> list[float] | None:
        if camera is None:
            return None
        values = np.asarray(camera, dtype=np.float64).reshape(-1)
        if values.shape != (9,) or not np.all(np.isfinite(values)):
            raise ValueError(f"camera must be 9 finite numbers (eye, target, up), got {camera!r}")
        return values.tolist()

    def rebuild(self) -> None:
        """Read the scene graph again and redraw (:meth:`update` calls it when objects were
        added or removed). The plot on screen is kept, its drawables replaced.

        A recording in progress starts over: its frames would not match the new parts.
        """
        if self._recording is not None:
            self._recording = []
        self.parts = collect_parts(self.sim)
        objects = self.sim.get_rigid_object_manager().get_objects_by_handle_substring("")
        self.names = {obj.object_id: handle for handle, obj in objects.items()}
        self.navmesh = navmesh_mesh(self.sim.pathfinder) if self.switches.navmesh else None
        shown = self._drawing.plot if self._drawing is not None else None
        self._drawing = SceneDrawing(self.parts, self.names, self.navmesh, self.height, shown)
        if shown is None:  # a new plot: aim its camera (a plot on screen keeps the student's)
            if self._camera is None:
                self._camera = default_camera(self.sim)
            if self._camera is not None:
                self._drawing.plot.camera_auto_fit = False
                self._drawing.plot.camera = self._camera
        self.update()

    def _object_ids(self) -> set[int]:
        """Ids of the simulator's objects now (to notice objects added or removed)."""
        manager = self.sim.get_rigid_object_manager()
        return {obj.object_id for obj in manager.get_objects_by_handle_substring("").values()}

    @property
    def drawing(self) -> SceneDrawing:
        """The k3d drawables of the scene (:class:`~engine.viewer.drawing.SceneDrawing`)."""
        assert self._drawing is not None  # built by __init__
        return self._drawing

    @property
    def plot(self) -> Any:
        """The k3d plot (a Jupyter widget)."""
        return self.drawing.plot

    def update(self) -> Frame:
        """Read the simulator now and redraw; returns the :class:`Frame` drawn.

        Objects added or removed since the last redraw are noticed and the scene is read
        again (:meth:`rebuild`).
        """
        if self._object_ids() != set(self.names):
            self.rebuild()
            assert self.frame is not None  # rebuild drew a frame
            return self.frame
        self.frame = capture_frame(self.sim, self.parts, self.switches)
        self.drawing.draw(self.frame)
        if self._recording is not None:
            self._recording.append(self.frame)
        if self._server is not None:
            self._server.publish()
        return self.frame

    def set_overlays(self, **switches: Any) -> None:
        """Turn overlays on or off, e.g. ``set_overlays(aabbs=True, contacts=False)``."""
        unknown = sorted(set(switches) - set(_SWITCH_NAMES))
        if unknown:
            raise TypeError(f"unknown overlay switch(es) {unknown}; known: {list(_SWITCH_NAMES)}")
        values = {name: getattr(self.switches, name) for name in _SWITCH_NAMES}
        values.update(switches)
        navmesh_was_on = self.switches.navmesh
        self.switches = OverlaySwitches(**values)
        if self.switches.navmesh != navmesh_was_on:
            self.rebuild()
        else:
            self.update()

    # ------------------------------------------------------------------------------------------
    # following step_physics
    # ------------------------------------------------------------------------------------------
    def follow(self) -> None:
        """Redraw after every ``step_physics`` of this simulator (instance attribute wrap)."""
        if self._followed_sim is not None:
            return
        sim = self.sim
        if "step_physics" in vars(sim):
            raise RuntimeError("another viewer already follows this simulator's step_physics")
        step_physics = type(sim).step_physics

        def step_and_draw(dt: float = 1.0 / 60.0) -> None:
            step_physics(sim, dt)
            self.update()

        sim.step_physics = step_and_draw
        self._followed_sim = sim

    def unfollow(self) -> None:
        """Stop redrawing on ``step_physics``: the simulator's own method is back."""
        if self._followed_sim is not None:
            vars(self._followed_sim).pop("step_physics", None)
            self._followed_sim = None

    # ------------------------------------------------------------------------------------------
    # display, recording, closing
    # ------------------------------------------------------------------------------------------
    def show(self) -> None:
        """Display the live k3d widget in Jupyter (the widget itself is :attr:`plot`)."""
        try:
            from IPython.display import display
        except ImportError as error:  # pragma: no cover - IPython comes with the extra
            raise RuntimeError("Viewer.show needs IPython (a notebook); use serve()") from error
        display(self.drawing.plot)

    def serve(self, host: str = DEFAULT_HOST, port: int = 0) -> str:
        """Serve the live page on ``host:port`` (127.0.0.1, a free port) and return its URL."""
        if self._server is None:
            self._server = LiveServer(self.drawing.plot, host=host, port=port)
            self._server.publish()
        return self._server.url

    def start_recording(self) -> None:
        """Keep every frame drawn from now on (the current one first)."""
        self._recording = [] if self.frame is None else [self.frame]

    def replay(self) -> Replay:
        """The frames recorded since :meth:`start_recording` as a :class:`Replay`."""
        if self._recording is None:
            raise RuntimeError("nothing recorded: call start_recording() before stepping")
        frames = list(self._recording)
        return Replay(self.parts, dict(self.names), frames, self.navmesh, self._camera)

    def close(self) -> None:
        """Stop following the simulator and stop the live server (if any)."""
        self.unfollow()
        if self._server is not None:
            self._server.close()
            self._server = None

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc_info: Any) -> None:
        self.close()

    def _ipython_display_(self) -> None:  # pragma: no cover - exercised inside Jupyter
        self.show()
