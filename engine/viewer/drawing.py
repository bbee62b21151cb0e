"""Frames to k3d drawables: one k3d plot for the meshes and the overlays.

:class:`SceneDrawing` turns the :class:`~engine.viewer.world_view.Part` s into k3d meshes
(vertex colours, the node's world matrix as ``model_matrix``) and every overlay into one
k3d object: line segments (``k3d.lines`` with ``indices_type="segment"``) or points. It
draws a :class:`~engine.viewer.overlays.Frame` in two ways:

- :meth:`SceneDrawing.draw` sets the current values (the live viewer: the k3d widget in
  Jupyter, or the page of :mod:`engine.viewer.server`);
- :meth:`SceneDrawing.animate` sets k3d *time series*, ``{"<seconds>": value}`` per
  property, from a list of frames: the replay. k3d's time series keep the index arrays
  fixed, so every overlay is padded to the largest count over the frames with zero-length
  segments at the origin (nothing is drawn for them).

Names of the k3d objects are the scene description a page exposes: ``stage``, each object's
handle (``sphere_:0000``), ``agent`` parts, and the overlay names of
:data:`~engine.viewer.overlays.SEGMENT_OVERLAYS` / :data:`~engine.viewer.overlays.POINT_OVERLAYS`.
"""

from __future__ import annotations

from typing import Any

import k3d
import numpy as np

from engine.viewer.overlays import POINT_OVERLAYS, SEGMENT_OVERLAYS, Frame
from engine.viewer.settings import (
    AABB_COLOR,
    AGENT_COLOR,
    CONTACT_COLOR,
    CONTACT_POINT_COLOR,
    CONTACT_POINT_SIZE,
    LINE_WIDTH,
    NAVMESH_OPACITY,
    PAIR_COLOR,
    PATH_COLOR,
    VELOCITY_COLOR,
)
from engine.viewer.world_view import Part

__all__ = ["SceneDrawing", "time_key"]

SEGMENT_COLORS = {
    "contacts": CONTACT_COLOR,
    "aabbs": AABB_COLOR,
    "pairs": PAIR_COLOR,
    "velocity": VELOCITY_COLOR,
    "agents": AGENT_COLOR,
    "path": PATH_COLOR,
}
POINT_COLORS = {"contact_points": CONTACT_POINT_COLOR, "velocity_targets": VELOCITY_COLOR}


def time_key(seconds: float) -> str:
    """k3d's time-series key for ``seconds`` (a decimal string, to the microsecond)."""
    return f"{seconds:.6f}"


def _segment_arrays(segments: np.ndarray, capacity: int) -> tuple[np.ndarray, np.ndarray]:
    """``(2 c, 3)`` vertices and ``(c, 2)`` indices of ``segments`` padded to ``capacity``.

    Padding segments are zero-length at the origin (k3d draws nothing for them); a capacity
    of at least 1 keeps k3d away from empty buffers.
    """
    capacity = max(capacity, len(segments), 1)
    vertices = np.zeros((capacity, 2, 3), dtype=np.float32)
    vertices[: len(segments)] = segments
    indices = np.arange(2 * capacity, dtype=np.uint32).reshape(capacity, 2)
    return vertices.reshape(-1, 3), indices


def _point_arrays(points: np.ndarray, capacity: int) -> tuple[np.ndarray, np.ndarray]:
    """``(c, 3)`` positions and ``(c,)`` sizes: the padding points have size 0."""
    capacity = max(capacity, len(points), 1)
    positions = np.zeros((capacity, 3), dtype=np.float32)
    positions[: len(points)] = points
    sizes = np.zeros(capacity, dtype=np.float32)
    sizes[: len(points)] = CONTACT_POINT_SIZE
    return positions, sizes


class SceneDrawing:
    """The k3d plot of a scene: one mesh per part, one object per overlay.

    Parameters
    ----------
    parts : list of Part
        The meshes (from :func:`~engine.viewer.world_view.collect_parts`).
    names : dict[int, str]
        Object id -> name shown (the object's handle); the stage is ``"stage"``.
    navmesh : tuple of (V, 3) float32, (F, 3) uint32, (V,) uint32, or None
        The navmesh overlay's mesh (:func:`~engine.viewer.overlays.navmesh_mesh`).
    height : int
        Plot height in pixels inside a notebook.
    plot : k3d Plot or None
        Draw into this plot (its drawables are replaced) instead of a new one.
    """

    def __init__(
        self,
        parts: list[Part],
        names: dict[int, str],
        navmesh: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
        height: int = 480,
        plot: Any = None,
    ) -> None:
        self.parts = parts
        if plot is None:
            plot = k3d.plot(
                height=height,
                grid_visible=False,
                camera_up_axis="y",
                background_color=0xFFFFFF,
                time_interpolation=False,
                antialias=1,
                name="rigidsim viewer",
            )
        else:  # redraw into a plot already on screen: its widget stays live
            for drawable in list(plot.objects):
                plot -= drawable
        self.plot = plot
        self.meshes: dict[str, Any] = {}
        for part in parts:
            name = names.get(part.object_id, "stage" if part.object_id == 0 else part.key)
            mesh = k3d.mesh(
                part.vertices,
                part.faces,
                colors=part.colors,
                flat_shading=False,
                side="double",
                name=name,
            )
            self.meshes[part.key] = mesh
            self.plot += mesh
        self.navmesh = None
        if navmesh is not None and len(navmesh[0]) > 0:
            vertices, faces, colors = navmesh
            self.navmesh = k3d.mesh(
                vertices, faces, colors=colors, opacity=NAVMESH_OPACITY, side="double",
                name="navmesh",
            )  # fmt: skip
            self.plot += self.navmesh
        self.lines = {
            name: k3d.lines(
                *_segment_arrays(np.zeros((0, 2, 3), np.float32), 1),
                indices_type="segment",
                shader="thick",
                width=LINE_WIDTH,
                color=SEGMENT_COLORS[name],
                name=name,
            )
            for name in SEGMENT_OVERLAYS
        }
        self.points = {
            name: k3d.points(
                np.zeros((1, 3), np.float32),
                point_sizes=np.zeros(1, np.float32),
                color=POINT_COLORS[name],
                shader="3d",
                name=name,
            )
            for name in POINT_OVERLAYS
        }
        for drawable in [*self.lines.values(), *self.points.values()]:
            self.plot += drawable
        self._tinted: dict[str, int | None] = {key: None for key in self.meshes}
        self._drawn_poses: dict[str, np.ndarray] = {}

    # ------------------------------------------------------------------------------------------
    # live: current values
    # ------------------------------------------------------------------------------------------
    def draw(self, frame: Frame) -> None:
        """Show ``frame``: poses, sleeping tints and overlays as the current values."""
        for part in self.parts:
            mesh = self.meshes[part.key]
            pose = frame.poses[part.key]
            drawn = self._drawn_poses.get(part.key)
            if drawn is None or not np.array_equal(pose, drawn):  # moved: send the new pose
                mesh.model_matrix = pose
                self._drawn_poses[part.key] = pose
            tint = frame.tints.get(part.object_id)
            if tint != self._tinted[part.key]:  # only a change is sent to the browser
                mesh.colors = part.colors if tint is None else np.full_like(part.colors, tint)
                self._tinted[part.key] = tint
        for name, lines in self.lines.items():
            segments = frame.segments.get(name, np.zeros((0, 2, 3), np.float32))
            vertices, indices = _segment_arrays(segments, len(segments))
            with lines.hold_sync():
                lines.vertices, lines.indices = vertices, indices
                lines.visible = name in frame.segments  # a switched-off overlay is hidden
        for name, points in self.points.items():
            positions, sizes = _point_arrays(frame.points.get(name, np.zeros((0, 3))), 0)
            with points.hold_sync():
                points.positions, points.point_sizes = positions, sizes
                points.visible = name in frame.points

    # ------------------------------------------------------------------------------------------
    # replay: time series
    # ------------------------------------------------------------------------------------------
    def animate(self, frames: list[Frame]) -> None:
        """Set every drawable to a time series over ``frames`` (times from the first frame)."""
        if not frames:
            raise ValueError("a replay needs at least one frame, got none")
        t0 = frames[0].time
        keys = [time_key(frame.time - t0) for frame in frames]
        for part in self.parts:
            mesh = self.meshes[part.key]
            poses = [frame.poses[part.key] for frame in frames]
            if any(not np.array_equal(pose, poses[0]) for pose in poses):
                mesh.model_matrix = dict(zip(keys, poses, strict=True))
            else:
                mesh.model_matrix = poses[0]
            tints = [frame.tints.get(part.object_id) for frame in frames]
            if any(tint is not None for tint in tints):
                mesh.colors = {
                    key: part.colors if tint is None else np.full_like(part.colors, tint)
                    for key, tint in zip(keys, tints, strict=True)
                }
        for name, lines in self.lines.items():
            series = [f.segments.get(name, np.zeros((0, 2, 3), np.float32)) for f in frames]
            capacity = max(len(s) for s in series)
            arrays = [_segment_arrays(s, capacity) for s in series]
            lines.indices = arrays[0][1]
            lines.vertices = {key: v for key, (v, _) in zip(keys, arrays, strict=True)}
            lines.visible = any(name in f.segments for f in frames)
        for name, points in self.points.items():
            series = [f.points.get(name, np.zeros((0, 3), np.float32)) for f in frames]
            capacity = max(len(s) for s in series)
            arrays = [_point_arrays(s, capacity) for s in series]
            points.positions = {key: p for key, (p, _) in zip(keys, arrays, strict=True)}
            points.point_sizes = {key: s for key, (_, s) in zip(keys, arrays, strict=True)}
            points.visible = any(name in f.points for f in frames)

    def set_visible(self, name: str, visible: bool) -> None:
        """Show or hide one overlay drawable (``"navmesh"`` or an overlay name)."""
        drawable = {**self.lines, **self.points}.get(name)
        if name == "navmesh":
            drawable = self.navmesh
        if drawable is not None:
            drawable.visible = bool(visible)
