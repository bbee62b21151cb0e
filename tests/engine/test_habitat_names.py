"""Every Habitat name habitat-lab touches imports from its Habitat path through the alias;
the placeholders among them raise NotImplementedError naming what rigidsim lacks."""

from __future__ import annotations

import importlib
import typing
from collections.abc import Iterator

import pytest

import engine
from engine import mn
from engine.habitat_compat import alias

#: (Habitat module, name) for every name habitat-lab 0.3 touches that rigidsim lacked
HABITAT_NAMES = [
    ("corrade.containers", "StridedArrayView1D"),
    ("habitat_sim.gfx", "DebugLineRender"),
    ("habitat_sim._ext.habitat_sim_bindings", "Configuration"),
    ("magnum.trade", "ImporterManager"),
    ("magnum.trade", "MeshData"),
    ("magnum.trade", "MeshAttribute"),
    ("magnum.trade", "SceneField"),
    ("magnum", "MutableImageView2D"),
    ("habitat_sim.physics", "ManagedArticulatedObject"),
    ("habitat_sim.physics", "ManagedBulletArticulatedObject"),
    ("habitat_sim.physics", "ArticulatedObjectManager"),
    ("habitat_sim.physics", "JointMotorSettings"),
    ("habitat_sim.physics", "JointType"),
    ("habitat_sim.sim", "SimulatorBackend"),
    ("habitat_sim", "ReplayRenderer"),
    ("habitat_sim", "ReplayRendererConfiguration"),
    ("habitat_sim.sensors.sensor_wrapper", "Sensor"),
    ("habitat_sim.simulator", "Sensor"),
    ("magnum", "Vector3d"),
    ("magnum", "MeshPrimitive"),
    ("magnum", "PixelFormat"),
    ("magnum", "PixelStorage"),
    ("magnum.meshtools", "InterleaveFlags"),
    ("magnum.meshtools", "generate_indices"),
    ("magnum.meshtools", "filter_only_attributes"),
    ("magnum.meshtools", "interleave"),
    ("magnum.scenetools", "absolute_field_transformations3d"),
]
#: placeholder classes: (Habitat module, name, a word of what the message says is missing)
PLACEHOLDER_CLASSES = [
    ("corrade.containers", "StridedArrayView1D", "array views"),
    ("magnum.trade", "MeshData", "importers"),
    ("magnum", "MutableImageView2D", "image views"),
    ("magnum", "PixelStorage", "image memory"),
    ("habitat_sim.physics", "ManagedArticulatedObject", "articulated objects"),
    ("habitat_sim.physics", "ManagedBulletArticulatedObject", "articulated objects"),
    ("habitat_sim.physics", "ArticulatedObjectManager", "articulated objects"),
    ("habitat_sim.physics", "JointMotorSettings", "joint motors"),
    ("habitat_sim.sim", "SimulatorBackend", "backend"),
    ("habitat_sim", "ReplayRenderer", "replay renderer"),
    ("habitat_sim", "ReplayRendererConfiguration", "replay renderer"),
]
PLACEHOLDER_FUNCTIONS = [
    ("magnum.meshtools", "generate_indices"),
    ("magnum.meshtools", "filter_only_attributes"),
    ("magnum.meshtools", "interleave"),
    ("magnum.meshtools", "transform3d"),
    ("magnum.scenetools", "absolute_field_transformations3d"),
]


@pytest.fixture(autouse=True)
def aliased() -> Iterator[None]:
    alias.install()
    try:
        yield
    finally:
        alias.uninstall()


def habitat_name(module: str, name: str) -> object:
    """``from <module> import <name>``, as Habitat code writes it."""
    namespace: dict[str, object] = {}
    exec(f"from {module} import {name}", namespace)
    return namespace[name]


@pytest.mark.parametrize(("module", "name"), HABITAT_NAMES)
def test_name_imports_from_its_habitat_path(module: str, name: str) -> None:
    value = habitat_name(module, name)
    # the same object as rigidsim's own module holds under the mapped name
    assert getattr(importlib.import_module(alias.rigidsim_name(module) or ""), name) is value


@pytest.mark.parametrize(("module", "name", "missing"), PLACEHOLDER_CLASSES)
def test_placeholder_class_annotates_but_does_not_construct(
    module: str, name: str, missing: str
) -> None:
    cls = habitat_name(module, name)
    assert isinstance(cls, type)

    # annotations evaluated when the function is defined, as in habitat-lab's modules
    source = "def annotated(value: C, values: typing.List[C]) -> C:\n    return value\n"
    namespace: dict[str, object] = {"C": cls, "typing": typing}
    exec(compile(source, "<habitat-lab style>", "exec", dont_inherit=True), namespace)
    assert namespace["annotated"].__annotations__["value"] is cls  # type: ignore[attr-defined]
    assert not isinstance(object(), cls)
    assert not hasattr(cls, "__origin__")  # private and dunder names: plain AttributeError
    with pytest.raises(NotImplementedError, match=rf"{name}\(\) is a placeholder.*{missing}"):
        cls()
    with pytest.raises(NotImplementedError, match=rf"{name}\.some_method is a placeholder"):
        cls.some_method  # noqa: B018 - reading a method off the class raises too


@pytest.mark.parametrize(("module", "name"), PLACEHOLDER_FUNCTIONS)
def test_placeholder_function_raises_when_called(module: str, name: str) -> None:
    function = habitat_name(module, name)
    assert callable(function) and function.__name__ == name  # type: ignore[attr-defined]
    with pytest.raises(NotImplementedError, match=rf"{module}\.{name} is a placeholder"):
        function(None)  # type: ignore[operator]


def test_importer_manager_constructs_at_import_time_and_raises_when_used() -> None:
    manager = habitat_name("magnum.trade", "ImporterManager")()  # type: ignore[operator]
    with pytest.raises(NotImplementedError, match="load_and_instantiate.*engine.scene.assets"):
        manager.load_and_instantiate("AnySceneImporter")


def test_simulator_backend_reset_raises_naming_the_backend() -> None:
    backend = habitat_name("habitat_sim.sim", "SimulatorBackend")
    with pytest.raises(NotImplementedError, match="SimulatorBackend.reset is a placeholder"):
        backend.reset(None)  # type: ignore[attr-defined]  # rearrange_sim's call


def test_enums_carry_habitats_and_magnums_members() -> None:
    joint_type = habitat_name("habitat_sim.physics", "JointType")
    assert [member.name for member in joint_type] == [  # type: ignore[attr-defined]
        "Revolute",
        "Prismatic",
        "Spherical",
        "Planar",
        "Fixed",
        "Invalid",
    ]
    assert str(joint_type.Prismatic) == "JointType.Prismatic"  # type: ignore[attr-defined]
    magnum = importlib.import_module("magnum")
    assert {"TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"} <= set(magnum.MeshPrimitive.__members__)
    assert {"RGBA8_UNORM", "R32F"} <= set(magnum.PixelFormat.__members__)
    assert magnum.trade.MeshAttribute.POSITION != magnum.trade.MeshAttribute.NORMAL
    assert magnum.trade.SceneField.MESH.name == "MESH"
    assert not magnum.meshtools.InterleaveFlags.NONE


def test_vector3d_compares_with_the_double_epsilon() -> None:
    vector = mn.Vector3d(1.0, 2.0, 3.0)
    assert vector == mn.Vector3d(1.0, 2.0, 3.0 + 1e-15)
    assert vector != mn.Vector3d(1.0, 2.0, 3.0 + 1e-9)  # Vector3 (float epsilon) calls it equal
    assert mn.Vector3(1.0, 2.0, 3.0) == mn.Vector3(1.0, 2.0, 3.0 + 1e-9)
    assert isinstance(vector + [1, 1, 1], mn.Vector3d)
    assert vector + [1, 1, 1] == mn.Vector3d(2.0, 3.0, 4.0)


def test_simulator_names_habitat_lab_reads() -> None:
    config = engine.Configuration(engine.SimulatorConfiguration(scene_id="NONE"))
    with engine.Simulator(config) as sim, engine.Simulator(config) as twin:
        assert sim.renderer is sim.get_renderer()
        sim.step_world(0.1)  # Habitat's backend step: the same step as step_physics
        twin.step_physics(0.1)
        assert sim.get_world_time() == twin.get_world_time() == pytest.approx(0.096)
        with pytest.raises(NotImplementedError, match="get_articulated_object_manager"):
            sim.get_articulated_object_manager()
        with pytest.raises(NotImplementedError, match="gfx_replay_manager.save_keyframe"):
            sim.gfx_replay_manager.save_keyframe()
