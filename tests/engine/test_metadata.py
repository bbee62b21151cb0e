"""Scene datasets through ``MetadataMediator`` (Habitat's test dataset ``dataset_1``)."""

from __future__ import annotations

import pytest

from engine.metadata import MetadataMediator
from engine.simulator import Configuration, Simulator, SimulatorConfiguration


@pytest.fixture(scope="module")
def dataset_1(test_assets):
    return test_assets / "dataset_tests/dataset_1/test_dataset_1.scene_dataset_config.json"


def test_default_dataset_holds_the_primitives():
    mediator = MetadataMediator()
    assert mediator.active_dataset == "default"
    assert mediator.object_template_manager.get_num_templates() == 12
    assert mediator.stage_template_manager.get_num_templates() == 0
    with pytest.warns(UserWarning):
        assert not mediator.set_active_dataset("/no/such.scene_dataset_config.json")
    assert mediator.active_dataset == "default"


def test_dataset_objects_stages_defaults_and_configs(dataset_1):
    mediator = MetadataMediator()
    assert mediator.set_active_dataset(str(dataset_1))
    assert mediator.dataset_exists(str(dataset_1))
    objects = mediator.object_template_manager
    # 12 primitives + 4 object files under objects/* + 2 "configs" entries
    assert objects.get_num_templates() == 18
    modified = objects.get_template_by_handle("modified_test_object1_1_slick_heavy")
    assert modified.mass == 3.5 and modified.friction_coefficient == pytest.approx(0.2)
    assert modified.margin == pytest.approx(0.03)  # from the original file
    new = objects.get_template_by_handle("new_test_object3")
    assert new.mass == pytest.approx(1.1)
    assert new.render_asset_handle.endswith("objects/object_1/dataset_test_object3_1.glb")
    # default_attributes fill what a file leaves out: inertia [3, 2, 1]; the file's mass wins
    from_file = objects.get_template_by_handle(objects.get_file_template_handles("object1_0")[0])
    assert from_file.inertia == [3.0, 2.0, 1.0] and from_file.mass == pytest.approx(0.038)
    stages = mediator.stage_template_manager
    assert stages.get_num_templates() == 5  # 2 stage files + 3 "configs" entries
    assert stages.get_template_by_handle("new_test_stage").scale == [2.0, 2.0, 2.0]
    # default_attributes origin [1, 2, 3] fills the new template; stage_0's file says [0, 0, 0]
    assert stages.get_template_by_handle("new_test_stage").origin == [1.0, 2.0, 3.0]
    assert stages.get_template_by_handle("modified_test_stage_0").origin == [0.0, 0.0, 0.0]
    assert stages.get_template_by_handle("modified_test_stage_0").margin == pytest.approx(0.041)
    assert len(mediator.get_scene_handles()) == 2
    assert "articulated_objects" in mediator.dataset_report()
    # switching back keeps both datasets
    assert mediator.set_active_dataset("default")
    assert mediator.object_template_manager.get_num_templates() == 12
    assert sorted(mediator.get_dataset_handles()) == sorted(["default", str(dataset_1)])


def test_simulator_uses_the_active_dataset(dataset_1):
    config = SimulatorConfiguration(scene_id="modified_test_stage_0")
    config.scene_dataset_config_file = str(dataset_1)
    with Simulator(Configuration(config)) as sim:
        assert sim.metadata_mediator.active_dataset == str(dataset_1)
        assert sim.get_stage_is_collidable()  # the dataset's stage was loaded
        obj = sim.get_rigid_object_manager().add_object_by_template_handle("new_test_object3")
        assert obj.mass == pytest.approx(1.1)
    missing = SimulatorConfiguration()
    missing.scene_dataset_config_file = "/no/such.scene_dataset_config.json"
    with pytest.warns(UserWarning), pytest.raises(FileNotFoundError):
        Simulator(Configuration(missing))
