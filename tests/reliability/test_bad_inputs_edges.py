"""The last unclear errors: each input a student or a program produces by mistake is refused
naming what is wrong, with the world unchanged (:func:`bad_inputs.assert_refused`).

Constraint pivots and frames, the physics time step, a huge string and a huge number in a
template JSON, a ``.glb`` whose JSON chunk is not UTF-8, ``copy.deepcopy(sim)``, and complex,
numeric-string or bool coordinates.
"""

from __future__ import annotations

import copy
import json
import pickle
import struct
import time

import numpy as np
import pytest
import trimesh
from bad_inputs import assert_refused

import engine as habitat_sim
from engine import mn
from engine.attributes import PhysicsManagerAttributes
from engine.physics import RigidConstraintSettings
from engine.scene.assets import load_meshes


def _first_object(sim):
    manager = sim.get_rigid_object_manager()
    return manager.get_object_by_id(sorted(manager._objects)[0])


# -- constraints -------------------------------------------------------------------------------
@pytest.mark.parametrize("far", [1e39, 1e300, -1e300])
@pytest.mark.parametrize("field", ["pivot_a", "pivot_b"])
def test_a_constraint_pivot_beyond_the_coordinate_range_is_refused_naming_it(sim, far, field):
    """Before: a pivot at 1e300 was accepted and flung the object at the speed cap."""
    settings = RigidConstraintSettings()
    settings.object_id_a = _first_object(sim).object_id
    assert_refused(sim, lambda: setattr(settings, field, [far, 0.0, 0.0]), ValueError, field)
    assert np.all(np.asarray(getattr(settings, field)) == 0.0)  # the field kept its value


DEGENERATE_FRAMES = {
    "zero": np.zeros((3, 3)),
    "scaled": 2.0 * np.eye(3),
    "sheared": np.array([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
    "mirror": np.diag([1.0, 1.0, -1.0]),
    "rank-one": np.outer([1.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
}


@pytest.mark.parametrize("frame", sorted(DEGENERATE_FRAMES))
@pytest.mark.parametrize("field", ["frame_a", "frame_b"])
def test_a_degenerate_constraint_frame_is_refused_naming_it(sim, frame, field):
    settings = RigidConstraintSettings()
    matrix = DEGENERATE_FRAMES[frame]
    assert_refused(sim, lambda: setattr(settings, field, matrix), ValueError, field)


def test_a_rotation_frame_and_a_pivot_within_range_are_accepted():
    settings = RigidConstraintSettings()
    angle = 0.3
    turn = [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
    settings.frame_a = turn
    settings.pivot_b = [3e38, -1.0, 0.0]
    np.testing.assert_allclose(np.asarray(settings.frame_a), turn)


# -- the time step -----------------------------------------------------------------------------
@pytest.mark.parametrize("timestep", [1e-9, 1e-6, 0.5, 10.0])
def test_a_physics_time_step_outside_the_range_that_works_is_refused_up_front(timestep):
    """Before: 1e-9 was accepted, and then every 1/60 s step raised (too many steps)."""
    physics = PhysicsManagerAttributes()
    with pytest.raises(ValueError, match=r"timestep must be in \[1e-05, 0.1\]"):
        physics.timestep = timestep
    assert physics.timestep == 0.008


@pytest.mark.parametrize("timestep", [1e-9, 1.0])
def test_a_physics_config_with_a_time_step_out_of_range_is_refused_naming_it(tmp_path, timestep):
    path = tmp_path / "bad.physics_config.json"
    path.write_text(json.dumps({"timestep": timestep}))
    with pytest.raises(ValueError, match="timestep.*bad.physics_config.json|timestep"):
        PhysicsManagerAttributes.from_json_file(str(path))


# -- template JSON -----------------------------------------------------------------------------
def test_a_template_json_with_a_200_mb_string_is_refused_quickly_naming_field_and_limit(
    sim, tmp_path
):
    """Before: ``OSError: File name too long`` after 19 s and a 1.75 GB peak."""
    path = tmp_path / "huge.object_config.json"
    with path.open("w") as stream:  # written in pieces: the test holds no 200 MB string
        stream.write('{"mass": 2.0, "render_asset": "')
        chunk = "a" * 2**20
        for _ in range(200):
            stream.write(chunk)
        stream.write('"}')
    templates = sim.get_object_template_manager()
    start = time.perf_counter()
    assert_refused(
        sim, lambda: templates.load_configs(str(path)), ValueError, r"'render_asset'.*32 MB"
    )
    assert time.perf_counter() - start < 1.0
    path.unlink()


def test_a_long_string_within_the_file_limit_is_refused_naming_the_field(sim, tmp_path):
    path = tmp_path / "long.object_config.json"
    path.write_text(json.dumps({"render_asset": "b" * 100_000}))
    templates = sim.get_object_template_manager()
    assert_refused(sim, lambda: templates.load_configs(str(path)), ValueError, "render_asset.*4096")
    assert path.stat().st_size < 32 * 2**20  # within the file size limit


@pytest.mark.parametrize("digits", [400, 4000])
def test_a_mass_of_hundreds_of_digits_is_refused_naming_mass(sim, tmp_path, digits):
    """Before: ``OverflowError: int too large to convert to float``, naming nothing."""
    path = tmp_path / "heavy.object_config.json"
    path.write_text('{"render_asset": "cubeSolid", "mass": 1' + "0" * (digits - 1) + "}")
    templates = sim.get_object_template_manager()
    assert_refused(sim, lambda: templates.load_configs(str(path)), ValueError, "mass")


# -- a .glb whose JSON is not UTF-8 ------------------------------------------------------------
def _glb_with_bad_text(path):
    data = trimesh.creation.box().export(file_type="glb")
    length = struct.unpack("<I", data[12:16])[0]
    chunk = bytearray(data[20 : 20 + length])
    at = chunk.find(b'"asset"') + 1
    chunk[at : at + 2] = b"\xff\xfe"  # not UTF-8 (glTF requires UTF-8)
    path.write_bytes(data[:20] + bytes(chunk) + data[20 + length :])
    return path


def test_a_glb_with_a_bad_text_encoding_is_refused_naming_the_file(sim, tmp_path):
    """Before: trimesh guessed another encoding (or, without the optional guesser
    installed, ``ModuleNotFoundError: charset_normalizer``)."""
    path = _glb_with_bad_text(tmp_path / "latin.glb")
    with pytest.raises(ValueError, match=r"latin\.glb.*not UTF-8"):
        load_meshes(path)
    templates = sim.get_object_template_manager()
    template_id = templates.register_template(templates.create_new_template(str(path)))
    manager = sim.get_rigid_object_manager()
    handle = templates.get_template_by_id(template_id).handle
    add = manager.add_object_by_template_handle
    assert_refused(sim, lambda: add(handle), ValueError, r"latin\.glb.*not UTF-8")
    templates.remove_template_by_id(template_id)


def test_a_glb_with_a_bad_text_encoding_as_a_stage_is_refused_naming_the_file(tmp_path):
    path = _glb_with_bad_text(tmp_path / "latin_stage.glb")
    cfg = habitat_sim.SimulatorConfiguration()
    cfg.scene_id = str(path)
    with pytest.raises(ValueError, match=r"latin_stage\.glb.*not UTF-8"):
        habitat_sim.Simulator(
            habitat_sim.Configuration(cfg, [habitat_sim.agent.AgentConfiguration()])
        )


# -- copying a simulator -----------------------------------------------------------------------
@pytest.mark.parametrize("copier", [copy.copy, copy.deepcopy, pickle.dumps])
def test_copying_a_simulator_is_a_clear_type_error(sim, copier):
    """Before: ``copy.deepcopy(sim)`` failed inside ``LightInfo`` with an AttributeError."""
    assert_refused(sim, lambda: copier(sim), TypeError, "Simulator cannot be copied")


# -- coordinates -------------------------------------------------------------------------------
BAD_COORDINATES = {
    "complex": [1.0 + 2.0j, 0.0, 0.0],
    "complex-array": np.array([1.0, 0.5j, 0.0]),
    "numeric-string": ["1", 0.0, 0.0],
    "string-array": np.array(["1", "2", "3"]),
    "bool": [True, 0.0, 0.0],
    "bool-array": np.array([True, False, True]),
}
VECTOR_SETTERS = {
    "translation": lambda obj, v: setattr(obj, "translation", v),
    "linear_velocity": lambda obj, v: setattr(obj, "linear_velocity", v),
    "angular_velocity": lambda obj, v: setattr(obj, "angular_velocity", v),
    "force": lambda obj, v: obj.apply_force(v, [0.0, 0.0, 0.0]),
    "impulse": lambda obj, v: obj.apply_impulse([0.0, 1.0, 0.0], v),
    "translate": lambda obj, v: obj.translate(v),
}


@pytest.mark.parametrize("bad", sorted(BAD_COORDINATES))
@pytest.mark.parametrize("setter", sorted(VECTOR_SETTERS))
def test_complex_string_or_bool_coordinates_are_refused_naming_the_argument(sim, bad, setter):
    """Before: a complex part was dropped with only NumPy's warning, strings and bools read
    as numbers."""
    obj = _first_object(sim)
    value = BAD_COORDINATES[bad]
    assert_refused(sim, lambda: VECTOR_SETTERS[setter](obj, value), ValueError, "real numbers")


@pytest.mark.parametrize("bad", sorted(BAD_COORDINATES))
def test_bad_coordinates_in_vectors_rays_gravity_and_agent_states_are_refused(sim, bad):
    value = BAD_COORDINATES[bad]
    assert_refused(sim, lambda: sim.set_gravity(value), ValueError, "gravity")
    assert_refused(sim, lambda: habitat_sim.geo.Ray(value, [0.0, -1.0, 0.0]), ValueError, "origin")
    assert_refused(sim, lambda: mn.Vector3(*value), TypeError, "real numbers")
    assert_refused(sim, lambda: mn.Quaternion(value, 1.0), TypeError, "real numbers")
    state = habitat_sim.agent.AgentState()
    assert_refused(sim, lambda: setattr(state, "position", value), TypeError, "position")


def test_real_coordinates_of_every_numeric_type_are_still_accepted(sim):
    obj = _first_object(sim)
    before = np.asarray(obj.translation)
    for value in ([1, 2, 3], (1.0, 2.0, 3.0), np.array([1, 2, 3], np.int32),
                  np.array([1, 2, 3], np.float32), mn.Vector3(1, 2, 3),
                  [np.float64(1), np.int64(2), 3]):  # fmt: skip
        obj.translation = value
        np.testing.assert_allclose(np.asarray(obj.translation), [1, 2, 3])
    obj.translation = before
