"""What a view keeps between frames, and the scene split into static and moving meshes.

The caller's process and the render worker process (:mod:`render.worker`) run this same
code, so a view gives the same bits wherever it is rendered:

* :class:`LayeredView`: what one view (a camera and its pose, rendered every frame) keeps
  between frames, and the one function that renders it in a given *mode*: ``"full"``
  (:func:`render_frame` of every mesh), ``"new layer"`` (first render the static meshes and
  keep them as a :class:`StaticLayer`, then draw the moving ones over it) or ``"layer"``
  (draw the moving meshes over the kept layer). The caller decides the mode: it knows when
  the static meshes, the lights and the camera are unchanged.
* :class:`SplitScene`: the static and the moving meshes as two :class:`RenderScene` s, and
  the scene of all of them (static first) built when a full render needs it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from render.camera import Camera
from render.frame import FrameBuffers, StaticLayer, render_frame, render_over_layer
from render.scene import RenderMesh, RenderScene
from render.settings import DEFAULT_SETTINGS, RenderSettings

__all__ = ["MODES", "LayeredView", "SplitScene"]

#: how a view is rendered: every mesh, a new static layer plus the moving meshes, or the
#: moving meshes over the kept layer
MODES = ("full", "new layer", "layer")


class SplitScene:
    """The static meshes and the moving ones as two scenes; the full scene on demand.

    ``set_meshes`` rebuilds a part only when asked to; ``set_poses`` copies the poses in;
    ``full()`` is ``RenderScene(static.meshes + moving.meshes)`` with both parts' poses.
    """

    def __init__(self) -> None:
        self.static = RenderScene([])
        self.moving = RenderScene([])
        self._full: RenderScene | None = None

    def set_meshes(
        self, static: list[RenderMesh] | None = None, moving: list[RenderMesh] | None = None
    ) -> None:
        """Rebuild the static and/or moving scene (None: keep that part)."""
        if static is not None:
            self.static = RenderScene(static)
        if moving is not None:
            self.moving = RenderScene(moving)
        if static is not None or moving is not None:
            self._full = None

    def set_poses(self, static_poses: np.ndarray, moving_poses: np.ndarray) -> None:
        """Poses ``(n_static, 4, 4)`` and ``(n_moving, 4, 4)`` (float64) of the two parts."""
        self.static.world_from_mesh[...] = static_poses
        self.moving.world_from_mesh[...] = moving_poses
        if self._full is not None:
            self._set_full_poses()

    def full(self) -> RenderScene:
        """Every mesh, static ones first (built when first needed)."""
        if self._full is None:
            self._full = RenderScene(self.static.meshes + self.moving.meshes)
            self._set_full_poses()
        return self._full

    def _set_full_poses(self) -> None:
        full = self._full
        assert full is not None  # built by full() before its poses are set
        n_static = len(self.static.meshes)
        full.world_from_mesh[:n_static] = self.static.world_from_mesh
        full.world_from_mesh[n_static:] = self.moving.world_from_mesh


@dataclass
class LayeredView:
    """One view's buffers and static layer between frames (see the module docstring).

    ``out`` (optional) receives the frame's color, depth and ids instead of buffers of
    the view's own (the worker passes views of shared memory).
    """

    buffers: FrameBuffers | None = None
    static_buffers: FrameBuffers | None = None
    layer: StaticLayer | None = None
    out: FrameBuffers | None = field(default=None, repr=False)

    def render(
        self,
        mode: str,
        scene: SplitScene,
        camera: Camera,
        world_from_camera: np.ndarray,
        rows: tuple[int, int] | None = None,
        ids: bool = True,
        settings: RenderSettings = DEFAULT_SETTINGS,
    ) -> FrameBuffers:
        """Render the view as ``mode`` says; returns its (reused) buffers. ``rows``: only
        these image rows of a full render (``render_frame``'s ``rows``); ``ids``: False
        when no sensor reads the semantic ids (full renders then skip them); ``settings``:
        those of ``render_frame``."""
        if mode not in MODES:
            raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
        if mode == "layer" and self.layer is None:
            raise ValueError("mode 'layer' needs a static layer: render a 'new layer' first")
        if rows is not None and mode != "full":
            raise ValueError(f"rows are for full renders, not mode {mode!r}")
        buffers = self.buffers if self.out is None else self.out
        if mode == "full":
            self.layer = None  # stale: free its memory
            frame = render_frame(
                scene.full(),
                camera,
                world_from_camera,
                buffers,
                cull_back_faces=True,
                rows=rows,
                ids=ids,
                settings=settings,
            )
        else:
            if mode == "new layer":
                self.static_buffers = render_frame(
                    scene.static,
                    camera,
                    world_from_camera,
                    self.static_buffers,
                    True,
                    settings=settings,
                )
                self.layer = StaticLayer.from_frame(self.static_buffers)
            if self.layer is None:
                raise RuntimeError("no static layer to draw over")
            frame = render_over_layer(
                self.layer, scene.moving, camera, world_from_camera, buffers, True, settings
            )
        self.buffers = frame
        return frame
