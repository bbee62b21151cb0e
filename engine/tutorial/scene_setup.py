"""The tutorial's setup cell: configuration, agent placement and the ``simulate`` loop.

Port of the ``[setup]`` and ``[initialize]`` blocks of Habitat-sim's
``examples/tutorials/nb_python/managed_rigid_object_tutorial.py`` (MIT License,
Copyright (c) Meta Platforms, Inc. and its affiliates). The code keeps Habitat's names and
structure so that a Habitat user recognizes every line; the differences are:

- ``import engine as habitat_sim`` and ``from engine import mn`` replace ``habitat_sim`` and
  ``magnum``;
- the scene is the demo apartment of :mod:`engine.demo.datasets` (same coordinates as Habitat's
  ``apartment_1.glb``);
- the resolution is a parameter (``--fast`` renders small frames) and ``simulate`` reports to
  a :class:`~engine.tutorial.recording.SectionRecorder` that times physics, rendering and
  video encoding separately.

Conventions: Y up, -Z forward, meters, seconds. ``resolution`` is ``[height, width]``.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

import engine as habitat_sim
from engine import mn

# The tutorial's three sensors render 544 x 720 (height x width) frames.
TUTORIAL_RESOLUTION = (544, 720)
# --fast: a small resolution with the same aspect ratio, both sides multiples of 16 so the
# video encoder does not resize (H.264 macro blocks are 16 x 16 pixels).
FAST_RESOLUTION = (96, 128)
# The tutorial steps the world at 60 frames per world second.
FRAME_DT = 1.0 / 60.0

# Agent pose of the tutorial's place_agent: np.quaternion(-0.83147, 0, 0.55557, 0) is
# (w, x, y, z), a rotation of about 247 degrees around +Y.
AGENT_POSITION = (-0.15, -0.7, 1.0)
AGENT_ROTATION_WXYZ = (-0.83147, 0.0, 0.55557, 0.0)


def demo_scene_path(data_path: str) -> str:
    """Return the demo apartment stage inside ``data_path`` (Habitat: apartment_1.glb)."""
    return os.path.join(data_path, "scene_datasets/demo/apartment.glb")


def place_agent(sim: habitat_sim.Simulator) -> mn.Matrix4:
    """Place agent 0 where the tutorial's onlooker stands and return its transformation."""
    agent_state = habitat_sim.AgentState()
    agent_state.position = list(AGENT_POSITION)
    # Habitat's line, kept: numpy-quaternion adds np.quaternion to numpy at import time, which
    # numpy's type stubs cannot know (the one third-party typing gap ignored here).
    agent_state.rotation = np.quaternion(*AGENT_ROTATION_WXYZ)  # type: ignore[attr-defined]
    agent = sim.initialize_agent(0, agent_state)
    return agent.scene_node.transformation_matrix()


def _camera_spec(
    uuid: str,
    sensor_type: habitat_sim.SensorType,
    resolution: Sequence[int],
    position: Sequence[float],
    orientation: Sequence[float],
) -> habitat_sim.CameraSensorSpec:
    """One pinhole camera spec; ``orientation`` is Euler angles in radians (Habitat)."""
    spec = habitat_sim.CameraSensorSpec()
    spec.uuid = uuid
    spec.sensor_type = sensor_type
    spec.resolution = list(resolution)
    spec.position = list(position)
    spec.orientation = list(orientation)
    spec.sensor_subtype = habitat_sim.SensorSubType.PINHOLE
    return spec


def make_configuration(
    data_path: str,
    resolution: Sequence[int] = TUTORIAL_RESOLUTION,
    seed: int = 0,
) -> habitat_sim.Configuration:
    """Build the tutorial's configuration: the apartment stage and three agent sensors.

    Parameters
    ----------
    data_path : str
        Folder laid out like Habitat's ``data`` (see :func:`engine.demo.datasets.demo_data_path`).
    resolution : (2,) int
        ``[height, width]`` of every sensor in pixels; the tutorial uses ``[544, 720]``.
    seed : int
        ``SimulatorConfiguration.random_seed``.
    """
    backend_cfg = habitat_sim.SimulatorConfiguration()
    backend_cfg.scene_id = demo_scene_path(data_path)
    if not os.path.exists(backend_cfg.scene_id):
        raise FileNotFoundError(f"demo scene not found: scene_id={backend_cfg.scene_id!r}")
    backend_cfg.random_seed = int(seed)
    # enable_physics defaults to True in rigidsim; set it anyway, as older tutorial versions do.
    backend_cfg.enable_physics = True

    # Note: all sensors must have the same resolution.
    # The orientation [-45, 0, 0] is in radians, as in Habitat (a -58.3 degree pitch).
    color, depth = habitat_sim.SensorType.COLOR, habitat_sim.SensorType.DEPTH
    sensor_specs = [
        _camera_spec("rgba_camera_1stperson", color, resolution, [0.0, 0.6, 0.0], [0.0, 0.0, 0.0]),
        _camera_spec("depth_camera_1stperson", depth, resolution, [0.0, 0.6, 0.0], [0.0, 0.0, 0.0]),
        _camera_spec("rgba_camera_3rdperson", color, resolution, [0.0, 1.0, 0.3], [-45, 0.0, 0.0]),
    ]

    agent_cfg = habitat_sim.agent.AgentConfiguration()
    agent_cfg.sensor_specifications = sensor_specs
    return habitat_sim.Configuration(backend_cfg, [agent_cfg])
