"""What the tutorial's sections share: the context they run in and the result they return.

The sections of Habitat's managed rigid object tutorial (MIT License, Copyright (c) Meta
Platforms, Inc. and its affiliates) run in order on one simulator; the clamp of
``kinematic_update`` is reused by the two velocity-control sections and the sphere template
of ``basics`` by ``dynamic_control``. :class:`TutorialContext` carries the simulator and those
hand-overs; every section returns a :class:`SectionResult` with its frame count, simulated
world time and a small dict of physical outcomes that the tests check.

Outcomes are plain JSON values in the world frame: positions in meters as ``[x, y, z]``,
rotations as quaternions ``[x, y, z, w]``.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from engine import mn
from engine.tutorial.recording import SectionRecorder, SectionTimings, VideoSpec
from engine.tutorial.scene_setup import FRAME_DT


@dataclass
class SectionResult:
    """What one section did: frames, world seconds, outcomes, timings, video path."""

    name: str
    frames: int
    world_time: float
    outcomes: dict[str, Any]
    timings: SectionTimings
    video_path: str | None = None
    observations: list[dict[str, np.ndarray]] = field(default_factory=list)


@dataclass
class TutorialContext:
    """The simulator, its data folder and the objects that sections hand to each other.

    Attributes
    ----------
    sim : Simulator
        The tutorial's simulator, agent 0 placed by ``place_agent``.
    data_path : str
        The demo data folder (Habitat's ``data``).
    new_recorder : callable
        ``new_recorder(video)`` returns the :class:`SectionRecorder` of the next section;
        ``video`` is None for a section without a video.
    rng : random.Random
        Source of the navmesh section's random turns (seeded: runs are reproducible).
    shared : dict
        Hand-overs between sections (``sphere_template_id``, ``clamp_obj``, ``locobot``).
    """

    sim: Any
    data_path: str
    new_recorder: Callable[[VideoSpec | None], SectionRecorder]
    rng: random.Random
    shared: dict[str, Any] = field(default_factory=dict)

    @property
    def obj_templates_mgr(self) -> Any:
        """The physics object attributes manager (``sim.get_object_template_manager()``)."""
        return self.sim.get_object_template_manager()

    @property
    def rigid_obj_mgr(self) -> Any:
        """The rigid object manager (``sim.get_rigid_object_manager()``)."""
        return self.sim.get_rigid_object_manager()


def simulate(recorder: SectionRecorder, dt: float = 1.0) -> int:
    """Simulate ``dt`` world seconds at 60 Hz to the nearest fixed timestep (the tutorial's
    ``simulate``); return the number of frames (``step_physics`` calls) it took."""
    sim = recorder.sim
    frames_before = recorder.frames
    start_time = sim.get_world_time()
    while sim.get_world_time() < start_time + dt:
        recorder.step(FRAME_DT)
    return recorder.frames - frames_before


def finish(
    name: str, recorder: SectionRecorder, start_time: float, outcomes: dict
) -> SectionResult:
    """Close the section's recorder (finishing its video) and package its result."""
    video_path = recorder.close()
    return SectionResult(
        name=name,
        frames=recorder.frames,
        world_time=recorder.sim.get_world_time() - start_time,
        outcomes=outcomes,
        timings=recorder.timings,
        video_path=video_path,
        observations=recorder.observations,
    )


def vec(value: Any) -> list[float]:
    """A Vector3-like value as a plain list of floats."""
    return [float(c) for c in np.asarray(value, dtype=np.float64).reshape(-1)]


def quat(value: mn.Quaternion) -> list[float]:
    """A quaternion as ``[x, y, z, w]`` floats."""
    return vec(value.xyzw)


def pose(obj: Any) -> dict[str, list[float]]:
    """An object's translation (its center of mass, m), rotation ``[x, y, z, w]`` and the
    half sizes of its local AABB (m, object axes: a sphere's radius, a can's radius and
    half height)."""
    half_extents = (np.asarray(obj.aabb.max, np.float64) - np.asarray(obj.aabb.min, np.float64)) / 2
    return {
        "translation": vec(obj.translation),
        "rotation": quat(obj.rotation),
        "half_extents": vec(half_extents),
    }


def world_y_extent(obj: Any) -> tuple[float, float]:
    """Lowest and highest world y of the corners of the object's local AABB, m.

    ``obj.aabb`` is in the object's local frame; each corner ``p`` goes to the world as
    ``y_world = R[1, :] . p + t_y`` with ``(R, t)`` the object's transformation.
    """
    lo, hi = np.asarray(obj.aabb.min, np.float64), np.asarray(obj.aabb.max, np.float64)
    # the 8 corners (x, y, z) with each coordinate either lo or hi: (8, 3)
    corners = np.array(np.meshgrid(*np.stack([lo, hi], axis=1), indexing="ij")).reshape(3, -1).T
    world_from_local = np.asarray(obj.transformation, dtype=np.float64)
    corner_y = corners @ world_from_local[1, :3] + world_from_local[1, 3]
    return float(corner_y.min()), float(corner_y.max())
