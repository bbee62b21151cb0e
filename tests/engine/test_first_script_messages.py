"""The three stumbles of a first script get messages that name the way out.

Habitat's return values stay Habitat's (a list from ``get_template_handles``, ``None`` and a
warning for an unknown handle, a ``KeyError`` for a missing observation); what changes is the
text: the matching full handles, the call that loads a config (``load_configs``), the sensor
uuids there are.
"""

from __future__ import annotations

import pickle
import warnings

import pytest

import engine as habitat_sim
from engine.attributes_managers import ObjectAttributesManager


def make_sim(sensors=()):
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    agent_cfg.sensor_specifications = list(sensors)
    sim_cfg = habitat_sim.SimulatorConfiguration()
    sim_cfg.scene_id = "NONE"
    return habitat_sim.Simulator(habitat_sim.Configuration(sim_cfg, [agent_cfg]))


def color_camera(uuid: str) -> habitat_sim.CameraSensorSpec:
    spec = habitat_sim.CameraSensorSpec()
    spec.uuid, spec.sensor_type, spec.resolution = uuid, habitat_sim.SensorType.COLOR, [8, 8]
    return spec


def test_a_search_before_load_configs_returns_an_empty_list_and_says_to_load(test_assets):
    templates = ObjectAttributesManager()
    with pytest.warns(UserWarning, match=r"load_configs\(") as caught:
        assert templates.get_template_handles("donut") == []  # Habitat's list, empty
    assert "'donut'" in str(caught[0].message)
    assert ".object_config.json" in str(caught[0].message)
    templates.load_configs(test_assets / "objects")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # found: no warning
        assert templates.get_template_handles("donut")[0].endswith("donut.object_config.json")
        assert templates.get_template_handles("donut", contains=False)  # never warns
        assert templates.get_template_handles("no such", contains=False)


def test_a_short_handle_warns_with_the_full_handles_and_returns_none(test_assets):
    templates = ObjectAttributesManager()
    templates.load_configs(test_assets / "objects")
    full = str(test_assets / "objects" / "sphere.object_config.json")
    with pytest.warns(UserWarning, match="these contain it") as caught:
        assert templates.get_template_by_handle("sphere") is None  # Habitat's None
    assert repr(full) in str(caught[0].message)
    with pytest.warns(UserWarning, match="these contain it"):
        assert templates.get_template_id_by_handle("sphere") == -1


def test_adding_an_object_by_a_short_handle_names_the_full_one(test_assets):
    with make_sim() as sim:
        sim.get_object_template_manager().load_configs(str(test_assets / "objects"))
        objects = sim.get_rigid_object_manager()
        full = str(test_assets / "objects" / "sphere.object_config.json")
        with pytest.warns(UserWarning, match="these contain it") as caught:
            assert objects.add_object_by_template_handle("sphere") is None
        assert repr(full) in str(caught[0].message)
        with pytest.warns(UserWarning, match=r"load_configs\("):
            assert objects.add_object_by_template_handle("cheezit") is None
        assert objects.get_num_objects() == 0


def test_a_missing_observation_names_the_sensor_uuids():
    with make_sim([color_camera("color_sensor")]) as sim:
        observations = sim.step("move_forward")
        assert isinstance(observations, dict)  # Habitat's type
        with pytest.raises(KeyError, match="'color_sensor'.*'collided'") as caught:
            observations["rgb"]
        assert "'rgb'" in str(caught.value)
        assert observations.get("rgb") is None and "rgb" not in observations
        again = pickle.loads(pickle.dumps(observations))
        assert sorted(again) == ["collided", "color_sensor"]
        assert sorted(sim.get_sensor_observations()) == ["color_sensor"]
        with pytest.raises(KeyError, match="'color_sensor'"):
            sim.get_sensor_observations()["depth"]
