"""Teaching overlays: what the viewer draws on top of the meshes, from public queries only.

Each overlay is a switch of :class:`OverlaySwitches` and a function of public queries a user
has, returning plain arrays (world frame, meters):

====================  ===========================================  ===============================
overlay               reads                                        returns
====================  ===========================================  ===============================
``contacts``          ``sim.get_physics_contact_points()``,        normals ``(k, 2, 3)`` from
                      ``sim.get_physics_time_step()``              the point on B, length
                                                                   ~ impulse; points ``(k, 3)``
``aabbs``             each object's ``aabb`` (local) and           box edges ``(12 n, 2, 3)``;
                      ``transformation``                           broad-phase pairs ``(p, 2, 3)``
``sleeping``          each object's ``awake`` and                  ``{object_id: colour}`` of
                      ``motion_type``, the contact points          the sleeping ones, by island
``navmesh``           ``pathfinder.build_navmesh_vertices`` and    vertices, faces, colours
                      ``build_navmesh_vertex_indices`` per island  (:func:`navmesh_mesh`)
``path``              ``pathfinder.find_path(ShortestPath)``       polyline segments ``(p, 2, 3)``
``velocity``          each object's ``velocity_control``           segments to the target pose
                      (``is_active``, ``integrate_transform``)     ``(c, 2, 3)``, targets ``(c, 3)``
``agents``            agents' nodes and sensor specifications      :func:`agent_segments`
====================  ===========================================  ===============================

Contact conventions are Habitat's (Bullet's): ``contact_normal_on_b_in_ws`` points from body B
towards body A, and ``normal_force`` is the last step's normal impulse over the fixed step, so
the impulse drawn is ``normal_force * h`` (N s).

Sleeping islands: two DYNAMIC objects touching (a contact point between them) are in one
island; STATIC and KINEMATIC objects and the stage do not join islands (Bullet's rule:
a box resting on the floor does not tie every other box on the floor to it). Each island of
sleeping objects gets one colour; awake objects keep their own.

:func:`capture_frame` runs the switched-on overlays and reads the poses: one :class:`Frame`
per call, the unit both the live viewer and the replay recorder draw.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from engine.physics import MotionType
from engine.viewer.settings import (
    CONTACT_LENGTH_PER_IMPULSE,
    CONTACT_MAX_LENGTH,
    CONTACT_MIN_LENGTH,
    ISLAND_COLORS,
    NAVMESH_COLORS,
    NAVMESH_LIFT,
    PATH_LIFT,
    VELOCITY_HORIZON,
)
from engine.viewer.world_view import Part, agent_segments, part_poses
from navmesh import ShortestPath

__all__ = [
    "POINT_OVERLAYS",
    "SEGMENT_OVERLAYS",
    "Frame",
    "OverlaySwitches",
    "aabb_boxes",
    "aabb_edges",
    "broad_phase_pairs",
    "capture_frame",
    "contact_normals",
    "navmesh_mesh",
    "path_segments",
    "sleeping_tints",
    "velocity_targets",
]

#: the overlays drawn as line segments, in drawing order
SEGMENT_OVERLAYS = ("contacts", "aabbs", "pairs", "velocity", "agents", "path")
#: the overlays drawn as points
POINT_OVERLAYS = ("contact_points", "velocity_targets")

_EMPTY_SEGMENTS = np.zeros((0, 2, 3), dtype=np.float32)
_EMPTY_POINTS = np.zeros((0, 3), dtype=np.float32)


@dataclass
class OverlaySwitches:
    """Which teaching overlays are drawn; each a switch a student turns on or off.

    ``path_goal`` is where the ``path`` overlay leads agent 0 (``find_path`` from the agent's
    position); the overlay draws nothing without a goal or a loaded navmesh.
    """

    contacts: bool = True
    aabbs: bool = False
    sleeping: bool = True
    navmesh: bool = False
    path: bool = False
    velocity: bool = True
    agents: bool = True
    path_goal: Any = None

    def __post_init__(self) -> None:
        for name in ("contacts", "aabbs", "sleeping", "navmesh", "path", "velocity", "agents"):
            value = getattr(self, name)
            if not isinstance(value, bool):
                raise TypeError(f"overlay switch {name} must be True or False, got {value!r}")
        if self.path_goal is not None:
            goal = np.asarray(self.path_goal, dtype=np.float64)
            if goal.shape != (3,) or not np.all(np.isfinite(goal)):
                raise ValueError(f"path_goal must be a finite 3-vector, got {self.path_goal!r}")
            self.path_goal = goal


@dataclass
class Frame:
    """What is drawn at one instant: poses, sleeping tints and overlay geometry.

    Attributes
    ----------
    time : float
        World time, s (``sim.get_world_time()``).
    poses : dict[str, (4, 4) float32]
        World-from-node matrix of every part, keyed by :attr:`Part.key`.
    tints : dict[int, int]
        Packed colour of each sleeping object, keyed by object id (awake ones are absent).
    segments : dict[str, (k, 2, 3) float32]
        Line overlays keyed by name (:data:`SEGMENT_OVERLAYS`), world frame, meters.
    points : dict[str, (k, 3) float32]
        Point overlays keyed by name (:data:`POINT_OVERLAYS`).
    n_contacts : int
        Contact points the simulator reported (whether or not they are drawn).
    """

    time: float
    poses: dict[str, np.ndarray]
    tints: dict[int, int] = field(default_factory=dict)
    segments: dict[str, np.ndarray] = field(default_factory=dict)
    points: dict[str, np.ndarray] = field(default_factory=dict)
    n_contacts: int = 0


# ----------------------------------------------------------------------------------------------
# contacts
# ----------------------------------------------------------------------------------------------
def contact_normals(contacts: list, time_step: float) -> tuple[np.ndarray, np.ndarray]:
    """Normals ``(k, 2, 3)`` drawn from each contact point on B, scaled by its impulse.

    Each is drawn as the push body B receives: from ``position_on_b_in_ws`` along
    ``-contact_normal_on_b_in_ws`` (that normal points from B towards A, so B is pushed the
    other way). For a can on the floor (A the stage, B the can) the arrow points up into
    the can. ``length = clip(CONTACT_MIN_LENGTH + CONTACT_LENGTH_PER_IMPULSE * normal_force
    * h, CONTACT_MIN_LENGTH, CONTACT_MAX_LENGTH)`` meters; the points ``(k, 3)`` are
    ``position_on_b_in_ws``.
    """
    if not contacts:
        return _EMPTY_SEGMENTS, _EMPTY_POINTS
    points = np.array([np.asarray(c.position_on_b_in_ws) for c in contacts], dtype=np.float64)
    normals = np.array([np.asarray(c.contact_normal_on_b_in_ws) for c in contacts])
    impulse = np.array([c.normal_force for c in contacts], dtype=np.float64) * time_step
    length = np.clip(
        CONTACT_MIN_LENGTH + CONTACT_LENGTH_PER_IMPULSE * impulse,
        CONTACT_MIN_LENGTH,
        CONTACT_MAX_LENGTH,
    )
    tips = points - normals * length[:, None]  # B is pushed along -n, n from B towards A
    return np.stack([points, tips], axis=1).astype(np.float32), points.astype(np.float32)


# ----------------------------------------------------------------------------------------------
# AABBs and broad-phase pairs
# ----------------------------------------------------------------------------------------------
# the 12 edges of a box as pairs of corner indices, corner i = (x bit 0, y bit 1, z bit 2)
_BOX_EDGES = np.array(
    [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]]
)
_CORNER_BITS = np.array([[(i >> axis) & 1 for axis in range(3)] for i in range(8)], dtype=bool)


def aabb_boxes(objects: list) -> tuple[np.ndarray, np.ndarray]:
    """World AABBs ``(n, 3)`` min and max of each object's render mesh.

    The object's ``aabb`` is in its local frame; its 8 corners go through ``transformation``
    and the world box is their min and max (what a broad phase tests).
    """
    lows, highs = [], []
    for obj in objects:
        box = obj.aabb
        low, high = np.asarray(box.min, dtype=np.float64), np.asarray(box.max, dtype=np.float64)
        corners = np.where(_CORNER_BITS, high, low)  # (8, 3) local
        matrix = np.asarray(obj.transformation, dtype=np.float64)
        world = corners @ matrix[:3, :3].T + matrix[:3, 3]
        lows.append(world.min(axis=0))
        highs.append(world.max(axis=0))
    if not lows:
        return np.zeros((0, 3)), np.zeros((0, 3))
    return np.array(lows), np.array(highs)


def aabb_edges(lows: np.ndarray, highs: np.ndarray) -> np.ndarray:
    """The 12 edges of each box ``(n, 3)`` min / max as ``(12 n, 2, 3)`` segments."""
    if len(lows) == 0:
        return _EMPTY_SEGMENTS
    corners = np.where(_CORNER_BITS[None], highs[:, None], lows[:, None])  # (n, 8, 3)
    return corners[:, _BOX_EDGES].reshape(-1, 2, 3).astype(np.float32)


def broad_phase_pairs(lows: np.ndarray, highs: np.ndarray) -> np.ndarray:
    """``(p, 2)`` index pairs ``i < j`` whose boxes overlap on all three axes.

    Boxes overlap when ``low_i <= high_j`` and ``low_j <= high_i`` on every axis; every pair
    is tested (n is a handful of objects in a lesson: n^2 is the honest baseline that a
    sweep-and-prune beats).
    """
    n = len(lows)
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64)
    overlap = np.all(
        (lows[:, None, :] <= highs[None, :, :]) & (lows[None, :, :] <= highs[:, None, :]), axis=2
    )
    i, j = np.nonzero(np.triu(overlap, k=1))
    return np.stack([i, j], axis=1)


# ----------------------------------------------------------------------------------------------
# sleeping islands
# ----------------------------------------------------------------------------------------------
def _find(parent: dict[int, int], i: int) -> int:
    """Root of ``i`` in a union-find forest, halving the path on the way."""
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


def sleeping_tints(objects: list, contacts: list) -> dict[int, int]:
    """Colour of each sleeping DYNAMIC object by its island, keyed by object id.

    Islands are the connected components of the graph "two DYNAMIC objects share a contact
    point" (union-find); islands are numbered in order of their smallest object id and take
    :data:`ISLAND_COLORS` in turn.
    """
    dynamic = {o.object_id for o in objects if o.motion_type == MotionType.DYNAMIC}
    parent = {i: i for i in dynamic}
    for c in contacts:
        a, b = c.object_id_a, c.object_id_b
        if a in dynamic and b in dynamic:
            parent[_find(parent, a)] = _find(parent, b)
    sleeping = sorted(o.object_id for o in objects if o.object_id in dynamic and not o.awake)
    island_of_root: dict[int, int] = {}
    tints = {}
    for object_id in sleeping:
        island = island_of_root.setdefault(_find(parent, object_id), len(island_of_root))
        tints[object_id] = ISLAND_COLORS[island % len(ISLAND_COLORS)]
    return tints


# ----------------------------------------------------------------------------------------------
# navmesh, path, velocity control
# ----------------------------------------------------------------------------------------------
def navmesh_mesh(pathfinder: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The navmesh as one coloured triangle mesh: vertices ``(V, 3)``, faces ``(F, 3)``,
    packed colours ``(V,)``, one :data:`NAVMESH_COLORS` entry per island, lifted by
    :data:`NAVMESH_LIFT`. Empty arrays when no navmesh is loaded."""
    if not pathfinder.is_loaded:
        return np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32), np.zeros(0, np.uint32)
    vertices, faces, colors = [], [], []
    offset = 0
    for island in range(pathfinder.num_islands):
        island_vertices = np.asarray(pathfinder.build_navmesh_vertices(island), dtype=np.float32)
        indices = np.asarray(pathfinder.build_navmesh_vertex_indices(island), dtype=np.uint32)
        vertices.append(island_vertices + np.array([0.0, NAVMESH_LIFT, 0.0], dtype=np.float32))
        faces.append(indices.reshape(-1, 3) + offset)
        colors.append(np.full(len(island_vertices), NAVMESH_COLORS[island % len(NAVMESH_COLORS)]))
        offset += len(island_vertices)
    if not vertices:
        return np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32), np.zeros(0, np.uint32)
    return (
        np.concatenate(vertices),
        np.concatenate(faces).astype(np.uint32),
        np.concatenate(colors).astype(np.uint32),
    )


def path_segments(pathfinder: Any, start: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """``find_path`` from ``start`` to ``goal`` as ``(p, 2, 3)`` segments lifted by
    :data:`PATH_LIFT`; empty when no navmesh is loaded or no path exists."""
    if not pathfinder.is_loaded:
        return _EMPTY_SEGMENTS
    query = ShortestPath()
    query.requested_start = np.asarray(start, dtype=np.float64)
    query.requested_end = np.asarray(goal, dtype=np.float64)
    if not pathfinder.find_path(query) or len(query.points) < 2:
        return _EMPTY_SEGMENTS
    points = np.asarray(query.points, dtype=np.float64) + np.array([0.0, PATH_LIFT, 0.0])
    return np.stack([points[:-1], points[1:]], axis=1).astype(np.float32)


def velocity_targets(objects: list) -> tuple[np.ndarray, np.ndarray]:
    """Segments ``(c, 2, 3)`` from each velocity-controlled object to its target, and the
    targets ``(c, 3)``: the translation ``integrate_transform`` reaches after
    :data:`VELOCITY_HORIZON` seconds at the commanded velocities."""
    starts, targets = [], []
    for obj in objects:
        control = obj.velocity_control
        if not control.is_active:
            continue
        state = obj.rigid_state
        target = control.integrate_transform(VELOCITY_HORIZON, state)
        starts.append(np.asarray(state.translation, dtype=np.float64))
        targets.append(np.asarray(target.translation, dtype=np.float64))
    if not starts:
        return _EMPTY_SEGMENTS, _EMPTY_POINTS
    starts_a, targets_a = np.array(starts), np.array(targets)
    return (
        np.stack([starts_a, targets_a], axis=1).astype(np.float32),
        targets_a.astype(np.float32),
    )


# ----------------------------------------------------------------------------------------------
# one frame
# ----------------------------------------------------------------------------------------------
def capture_frame(sim: Any, parts: list[Part], switches: OverlaySwitches) -> Frame:
    """Read poses and every switched-on overlay of ``sim`` into one :class:`Frame`.

    A switched-off overlay costs nothing: its query is not called.
    """
    frame = Frame(time=float(sim.get_world_time()), poses=part_poses(parts))
    needs_objects = switches.aabbs or switches.sleeping or switches.velocity
    objects = []
    if needs_objects:
        manager = sim.get_rigid_object_manager()
        objects = list(manager.get_objects_by_handle_substring("").values())
    contacts: list = []
    if switches.contacts or switches.sleeping:
        contacts = sim.get_physics_contact_points()
        frame.n_contacts = len(contacts)
    if switches.contacts:
        normals, points = contact_normals(contacts, float(sim.get_physics_time_step()))
        frame.segments["contacts"], frame.points["contact_points"] = normals, points
    if switches.aabbs:
        lows, highs = aabb_boxes(objects)
        frame.segments["aabbs"] = aabb_edges(lows, highs)
        pairs = broad_phase_pairs(lows, highs)
        centers = (lows + highs) / 2.0
        frame.segments["pairs"] = centers[pairs].reshape(-1, 2, 3).astype(np.float32)
    if switches.sleeping:
        frame.tints = sleeping_tints(objects, contacts)
    if switches.velocity:
        frame.segments["velocity"], frame.points["velocity_targets"] = velocity_targets(objects)
    if switches.agents:
        frame.segments["agents"] = agent_segments(sim)
    if switches.path and switches.path_goal is not None and sim.agents:
        start = np.asarray(sim.agents[0].get_state().position, dtype=np.float64)
        frame.segments["path"] = path_segments(sim.pathfinder, start, switches.path_goal)
    return frame
