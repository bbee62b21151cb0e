"""Scene instances (``*.scene_instance.json``) through a dataset written by the test.

The numbers are hand computed from Habitat's rules (engine.scene.instance): a COM corrected
instance puts the asset origin at ``translation``, so the body (its center of mass ``c``)
sits at ``translation + R c``; scale multiplies, mass follows the scaled volume.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from engine import mn
from engine.physics import MotionType
from engine.scene.instance import find_scene_instance, read_scene_instance
from engine.simulator import Configuration, Simulator, SimulatorConfiguration

FLOOR_OBJ = """v -5 0 -5
v 5 0 -5
v 5 0 5
v -5 0 5
f 1 3 2
f 1 4 3
"""
# rotation by 90 degrees about +Y as [w, x, y, z]: maps +X to -Z
QUARTER_TURN_Y = [math.cos(math.pi / 4), 0.0, math.sin(math.pi / 4), 0.0]


def write_json(path: Path, content: object) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(content), encoding="utf-8")
    return path


def write_dataset(root: Path, objects: list[dict], scene_extra: dict | None = None) -> Path:
    """A dataset with one floor stage, one cube object (COM [0.5, 0, 0], mass 2) and one scene."""
    (root / "stages").mkdir(parents=True)
    (root / "stages/floor.obj").write_text(FLOOR_OBJ, encoding="utf-8")
    write_json(
        root / "configs/stages/floor.stage_config.json",
        {"render_asset": "../../stages/floor.obj", "up": [0, 1, 0], "front": [0, 0, -1]},
    )
    write_json(
        root / "configs/objects/cube.object_config.json",
        {"render_asset": "cubeSolid", "mass": 2.0, "COM": [0.5, 0.0, 0.0]},
    )
    scene = {
        "translation_origin": "asset_local",
        "stage_instance": {"template_name": "stages/floor"},
        "object_instances": objects,
        **(scene_extra or {}),
    }
    write_json(root / "configs/scenes/room_00.scene_instance.json", scene)
    return write_json(
        root / "toy.scene_dataset_config.json",
        {
            "stages": {"paths": {".json": ["configs/stages"]}},
            "objects": {"paths": {".json": ["configs/objects"]}},
            "scene_instances": {"paths": {".json": ["configs/scenes"]}},
        },
    )


def make_sim(dataset: Path, scene_id: str) -> Simulator:
    config = SimulatorConfiguration(scene_id=scene_id)
    config.scene_dataset_config_file = str(dataset)
    return Simulator(Configuration(config))


def test_objects_are_placed_at_their_asset_origin_or_center_of_mass(tmp_path):
    objects = [
        # scene default asset_local: body at t + R c = [1, 2, 3] + [0, 0, -0.5]
        {"template_name": "objects/cube", "translation": [1, 2, 3], "rotation": QUARTER_TURN_Y},
        # "com": the translation is the center of mass itself
        {"template_name": "cube", "translation": [1, 2, 3], "translation_origin": "COM"},
        # asset_local, identity rotation: [0, 1, 0] + [0.5, 0, 0]
        {"template_name": "cube", "translation": [0, 1, 0], "translation_origin": "asset_local"},
    ]
    dataset = write_dataset(tmp_path, objects)
    with make_sim(dataset, "room_00") as sim:
        placed = sorted(
            sim.get_rigid_object_manager().get_objects_by_handle_substring().values(),
            key=lambda o: o.object_id,
        )
        assert len(placed) == 3
        np.testing.assert_allclose(placed[0].translation, [1.0, 2.0, 2.5], atol=1e-9)
        np.testing.assert_allclose(
            placed[0].rotation.transform_vector(mn.Vector3(1, 0, 0)), [0, 0, -1], atol=1e-9
        )
        np.testing.assert_allclose(placed[1].translation, [1.0, 2.0, 3.0], atol=1e-9)
        np.testing.assert_allclose(placed[2].translation, [0.5, 1.0, 0.0], atol=1e-9)
        # the stage is the floor: a ray down from above hits y = 0
        assert sim.curr_scene_name == "room_00"
        assert sim.get_stage_initialization_template().handle.endswith("floor.stage_config.json")


def test_scale_mass_motion_type_and_reset_pose(tmp_path):
    objects = [
        {
            "template_name": "cube",
            "translation": [0, 3, 0],
            "translation_origin": "com",
            "uniform_scale": 2.0,
            "non_uniform_scale": [1, 2, 1],
            "mass_scale": 0.5,
            "motion_type": "KINEMATIC",
        },
        {"template_name": "cube", "translation": [2, 3, 0], "apply_scale_to_mass": False,
         "uniform_scale": 3.0, "motion_type": "static"},
    ]  # fmt: skip
    dataset = write_dataset(tmp_path, objects)
    with make_sim(dataset, "room_00") as sim:
        manager = sim.get_rigid_object_manager()
        first, second = sorted(
            manager.get_objects_by_handle_substring().values(), key=lambda o: o.object_id
        )
        # scale [2, 4, 2]: mass 2 * (2 * 4 * 2) * 0.5 = 16
        assert first.mass == pytest.approx(16.0)
        assert first.motion_type == MotionType.KINEMATIC
        assert second.mass == pytest.approx(2.0)  # apply_scale_to_mass false
        assert second.motion_type == MotionType.STATIC
        # the COM the config gives ([0.5, 0, 0], the visual node's offset, not scaled) from
        # the asset origin [2, 3, 0]
        np.testing.assert_allclose(second.translation, [2.5, 3.0, 0.0], atol=1e-9)
        first.translation = mn.Vector3(5, 5, 5)
        sim.reset()
        np.testing.assert_allclose(first.translation, [0.0, 3.0, 0.0], atol=1e-9)


def test_scene_id_finds_the_instance_by_substring_or_by_file(tmp_path):
    dataset = write_dataset(tmp_path, [])
    scene_file = tmp_path / "configs/scenes/room_00.scene_instance.json"
    handles = [str(scene_file.resolve())]
    assert find_scene_instance(handles, "room_00") == handles[0]
    assert find_scene_instance(handles, str(scene_file)) == handles[0]
    assert find_scene_instance([], str(scene_file)) == handles[0]  # a file outside the dataset
    assert find_scene_instance(handles, "stages/floor") is None  # a stage, not a scene
    assert find_scene_instance(handles, "NONE") is None
    with make_sim(dataset, str(scene_file)) as sim:
        assert sim.get_rigid_object_manager().get_num_objects() == 0
        assert sim.get_stage_is_collidable()


def test_bad_scene_instances(tmp_path):
    missing_stage = write_json(tmp_path / "a.scene_instance.json", {"object_instances": []})
    with pytest.raises(ValueError, match="stage_instance"):
        read_scene_instance(missing_stage)
    odd = write_json(
        tmp_path / "b.scene_instance.json",
        {
            "stage_instance": {"template_name": "NONE"},
            "object_instances": [
                7,
                {"template_name": "x", "motion_type": "flying", "translation": [1, 2]},
            ],
            "translation_origin": "sideways",
        },
    )
    with pytest.warns(UserWarning) as caught:
        scene = read_scene_instance(odd)
    messages = " ".join(str(w.message) for w in caught)
    assert "object_instances[0]" in messages and "'flying'" in messages
    assert "[1, 2]" in messages and "'sideways'" in messages
    assert scene.translation_origin == "unknown"
    (instance,) = scene.object_instances
    assert instance.motion_type == "undefined" and list(instance.translation) == [0, 0, 0]
    dataset = write_dataset(tmp_path / "d", [{"template_name": "no_such_object"}])
    with pytest.raises(KeyError, match="no_such_object"):
        make_sim(dataset, "room_00")
