"""Habitat's ``DebugLineRender`` (``sim.get_debug_line_render()``): lines drawn into the next
color observations, for teaching and debugging (axes, paths, contact normals, boxes).

Lines are collected in world coordinates (each call's points go through the transform stack
first: ``push_transform(m)`` multiplies ``m`` onto it, ``pop_transform()`` removes the last)
and drawn, depth-tested, into every COLOR observation (pinhole, orthographic, fisheye and
equirectangular: :mod:`engine.sensors.line_overlay`) of the next ``get_sensor_observations`` /
``draw_observation`` call or asynchronous render, then forgotten, as Habitat's
immediate-mode lines are (:mod:`render.lines` draws them; hidden parts show faintly).
Colors are Magnum ``Color4`` / RGBA floats in [0, 1] (``Color3`` gets alpha 1).

Shapes (Habitat's construction): ``draw_box(min, max, color)`` the 12 edges of an axis-aligned
box; ``draw_circle(translation, radius, color, num_segments=24, normal=(0, 1, 0))`` a polygon
in the plane normal to ``normal``; ``draw_cone``; ``draw_axes(translation, scale, radius)``
red/green/blue X/Y/Z with arrow heads; ``draw_path_with_endpoint_circles(points, radius,
color, num_segments=24, normal=(0, 1, 0))`` a polyline with a circle around both ends, the
segments cut where they enter a circle.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from engine import mn

__all__ = ["DebugLineRender"]


def _color(value: Any) -> np.ndarray:
    """An RGBA float color (a 3-component color gets alpha 1)."""
    color = np.asarray(value, dtype=np.float64).reshape(-1)
    if color.shape == (3,):
        color = np.append(color, 1.0)
    if color.shape != (4,) or not np.all(np.isfinite(color)):
        raise ValueError(f"color must be RGB or RGBA floats, got {value!r}")
    return color


def _look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Magnum's ``Matrix4.look_at``: -Z from ``eye`` towards ``target``, ``up`` as +Y hint."""
    z = eye - target
    z = z / np.linalg.norm(z)
    x = np.cross(up, z)
    x = x / np.linalg.norm(x)
    matrix = np.eye(4)
    matrix[:3, 0], matrix[:3, 1], matrix[:3, 2], matrix[:3, 3] = x, np.cross(z, x), z, eye
    return matrix


def _perpendicular(normal: np.ndarray) -> np.ndarray:
    """Habitat's ``getRandomPerpVec``: a vector perpendicular to ``normal``."""
    if abs(normal[2]) < abs(normal[0]):
        return np.array([normal[1], -normal[0], 0.0])
    return np.array([0.0, -normal[2], normal[1]])


class DebugLineRender:
    """Collects debug lines for the next color observations (module docstring)."""

    def __init__(self) -> None:
        self._starts: list[np.ndarray] = []
        self._ends: list[np.ndarray] = []
        self._start_colors: list[np.ndarray] = []
        self._end_colors: list[np.ndarray] = []
        self._stack: list[np.ndarray] = []
        self._transform = np.eye(4)
        self.line_width = 1.0

    def set_line_width(self, width: float) -> None:
        if isinstance(width, bool) or not math.isfinite(float(width)) or float(width) <= 0:
            raise ValueError(f"line width must be a positive number, got {width!r}")
        self.line_width = float(width)

    def push_transform(self, transform: Any) -> None:
        """Multiply ``transform`` (4x4) onto the stack: later points are in its frame."""
        matrix = np.asarray(transform, dtype=np.float64)
        if matrix.shape != (4, 4) or not np.all(np.isfinite(matrix)):
            raise ValueError(f"transform must be a finite 4x4 matrix, got {transform!r}")
        self._stack.append(matrix)
        self._transform = self._transform @ matrix

    def pop_transform(self) -> None:
        if not self._stack:
            raise RuntimeError("pop_transform without a matching push_transform")
        self._stack.pop()
        self._transform = np.eye(4)
        for matrix in self._stack:
            self._transform = self._transform @ matrix

    def draw_transformed_line(
        self, from_pt: Any, to_pt: Any, from_color: Any, to_color: Any | None = None
    ) -> None:
        """A segment (through the transform stack), one color or one per end."""
        start = np.asarray(mn.to_vector3(from_pt, "fromPt"), dtype=np.float64)
        end = np.asarray(mn.to_vector3(to_pt, "toPt"), dtype=np.float64)
        color_a = _color(from_color)
        color_b = color_a if to_color is None else _color(to_color)
        rot, trans = self._transform[:3, :3], self._transform[:3, 3]
        self._starts.append(rot @ start + trans)
        self._ends.append(rot @ end + trans)
        self._start_colors.append(color_a)
        self._end_colors.append(color_b)

    def draw_box(self, min: Any, max: Any, color: Any) -> None:  # noqa: A002 - Habitat's names
        """The 12 edges of the box ``[min, max]``."""
        lo = np.asarray(mn.to_vector3(min, "min"))
        hi = np.asarray(mn.to_vector3(max, "max"))
        corners = [np.where([i & 1, i & 2, i & 4], hi, lo) for i in range(8)]
        for i in range(8):
            for bit in (1, 2, 4):  # one edge per axis from each corner without that bit
                if not i & bit:
                    self.draw_transformed_line(corners[i], corners[i | bit], color)

    def draw_circle(
        self,
        translation: Any,
        radius: float,
        color: Any,
        num_segments: int = 24,
        normal: Any = (0.0, 1.0, 0.0),
    ) -> None:
        """A ``num_segments``-gon of ``radius`` around ``translation``, normal to ``normal``."""
        center = np.asarray(mn.to_vector3(translation, "translation"))
        axis = np.asarray(mn.to_vector3(normal, "normal"))
        frame = _look_at(center, center + axis, _perpendicular(axis))
        self.push_transform(frame @ np.diag([radius, radius, 0.0, 1.0]))
        previous = np.array([1.0, 0.0, 0.0])
        for segment in range(1, int(num_segments) + 1):
            angle = math.radians(360.0 / num_segments * segment)
            point = np.array([math.cos(angle), math.sin(angle), 0.0])
            self.draw_transformed_line(previous, point, color)
            previous = point
        self.pop_transform()

    def draw_cone(
        self,
        translation: Any,
        apex: Any,
        radius: float,
        color: Any,
        num_segments: int = 12,
        normal: Any = (0.0, 1.0, 0.0),
    ) -> None:
        """A circle around ``translation`` with a line from each vertex to ``apex``."""
        self.draw_circle(translation, radius, color, num_segments, normal)
        center = np.asarray(mn.to_vector3(translation, "translation"))
        axis = np.asarray(mn.to_vector3(normal, "normal"))
        frame = _look_at(center, center + axis, _perpendicular(axis))
        tip = np.asarray(mn.to_vector3(apex, "apex"))
        for segment in range(1, int(num_segments) + 1):
            angle = math.radians(360.0 / num_segments * segment)
            local = np.array([radius * math.cos(angle), radius * math.sin(angle), 0.0])
            self.draw_transformed_line(frame[:3, :3] @ local + center, tip, color)

    def draw_axes(
        self, translation: Any, scale: Any = (1.0, 1.0, 1.0), radius: float = 0.05
    ) -> None:
        """X, Y, Z axes through ``translation`` in red, green, blue, with arrow heads."""
        position = np.asarray(mn.to_vector3(translation, "translation"))
        scales = np.asarray(mn.to_vector3(scale, "scale"))
        for k, color in enumerate(([1.0, 0, 0, 1], [0, 1.0, 0, 1], [0, 0, 1.0, 1])):
            axis = np.zeros(3)
            axis[k] = scales[k]
            self.draw_transformed_line(position - axis, position + axis, color)
            direction = axis / np.linalg.norm(axis)
            self.draw_cone(position + 0.9 * axis, position + axis, radius, color, 24, direction)

    def draw_path_with_endpoint_circles(
        self,
        points: Any,
        radius: float,
        color: Any,
        num_segments: int = 24,
        normal: Any = (0.0, 1.0, 0.0),
    ) -> None:
        """A polyline with a circle around both ends; segments stop at the circles."""
        path = [np.asarray(mn.to_vector3(p, "points")) for p in points]
        if len(path) < 2:
            raise ValueError("draw_path_with_endpoint_circles requires at least two points")
        end0, end1 = path[0], path[-1]
        self.draw_circle(end0, radius, color, num_segments, normal)
        self.draw_circle(end1, radius, color, num_segments, normal)
        for a, b in zip(path[:-1], path[1:], strict=True):
            piece = _outside_circle(a, b, end0, radius)
            piece = None if piece is None else _outside_circle(*piece, end1, radius)
            if piece is not None:
                self.draw_transformed_line(piece[0], piece[1], color)

    # -- for the simulator ----------------------------------------------------------------------
    def has_lines(self) -> bool:
        return bool(self._starts)

    def take_lines(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
        """The collected lines ``(starts, ends, start_colors, end_colors, width)``, cleared."""
        lines = tuple(
            np.array(x, dtype=np.float64).reshape(-1, n)
            for x, n in (
                (self._starts, 3),
                (self._ends, 3),
                (self._start_colors, 4),
                (self._end_colors, 4),
            )
        )
        self._starts, self._ends, self._start_colors, self._end_colors = [], [], [], []
        return (*lines, self.line_width)  # type: ignore[return-value]


def _outside_circle(
    a: np.ndarray, b: np.ndarray, center: np.ndarray, radius: float
) -> tuple[np.ndarray, np.ndarray] | None:
    """The part of segment ``ab`` outside the sphere ``|p - center| <= radius`` (the part
    from the endpoint outside to where it enters), None when both ends are inside."""
    inside_a = np.linalg.norm(a - center) <= radius
    inside_b = np.linalg.norm(b - center) <= radius
    if inside_a and inside_b:
        return None
    if not inside_a and not inside_b:
        return a, b
    outer, inner = (b, a) if inside_a else (a, b)
    # |outer + s (inner - outer) - center| = radius, the smaller root s in [0, 1]
    d, f = inner - outer, outer - center
    qa, qb, qc = d @ d, 2.0 * (f @ d), f @ f - radius * radius
    s = (-qb - math.sqrt(max(qb * qb - 4 * qa * qc, 0.0))) / (2 * qa)
    cut = outer + s * d
    return (cut, b) if inside_a else (a, cut)
