"""Shared setup of the reliability tests (pytest runs in importlib mode).

Makes ``world_hash`` and ``bad_inputs`` importable, and gives every bad-input test module
(``test_bad_inputs_*.py``) its own world under test, ``sim``: the demo apartment with one
16 x 16 color camera, the example object templates and three objects (a dynamic cube, a
kinematic cube, a dynamic sphere) after 0.1 s of physics.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bad_inputs import BAD_INPUTS_CHECKED  # noqa: E402 - importable once the path is set

import engine as habitat_sim  # noqa: E402
from engine.physics import MotionType  # noqa: E402
from engine.sensors import CameraSensorSpec  # noqa: E402


@pytest.fixture(scope="module")
def sim(demo_data: Path):
    cfg = habitat_sim.SimulatorConfiguration()
    cfg.scene_id = str(demo_data / "scene_datasets/demo/apartment.glb")
    spec = CameraSensorSpec()
    spec.uuid, spec.resolution = "color", [16, 16]
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    agent_cfg.sensor_specifications = [spec]
    simulator = habitat_sim.Simulator(habitat_sim.Configuration(cfg, [agent_cfg]))
    templates = simulator.get_object_template_manager()
    templates.load_configs(str(demo_data / "objects/example_objects"))
    manager = simulator.get_rigid_object_manager()
    for k, (handle, motion) in enumerate(
        [
            ("cubeSolid", MotionType.DYNAMIC),
            ("cubeSolid", MotionType.KINEMATIC),
            ("uvSphereSolid", MotionType.DYNAMIC),
        ]
    ):
        full = templates.get_template_handles(handle)[0]
        obj = manager.add_object_by_template_handle(full)
        obj.translation = [1.0 + k, 0.5, 0.0]
        obj.motion_type = motion
    simulator.step_physics(0.1)
    yield simulator
    simulator.close()
    print(f"\nbad inputs checked: {BAD_INPUTS_CHECKED['count']}")
