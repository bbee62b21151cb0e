"""Hypothesis-driven bad input over the public API: a clear exception, the world unchanged.

Every example calls one public function with a value it must refuse and asserts two things:
the exception type (``ValueError`` / ``TypeError``, or ``load_nav_mesh`` returning False with
a warning, as Habitat), and an unchanged :func:`world_hash.world_hash` (bodies, objects,
template libraries, navmesh, agents). Families: object setters (non-finite, wrongly shaped,
out of range, and values that only overflow when used: a second ``translate`` by 1e308),
templates, sensor specs, navmesh settings and size budgets, path-finder queries, ray casts,
videos and ``.navmesh`` files. ``BAD_INPUTS_CHECKED`` counts the examples run (printed at the
end of the module with ``pytest -s``).
"""

from __future__ import annotations

import io
import json
import math
import shutil
import tempfile
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from numpy.lib import format as npy_format
from world_hash import bodies_are_finite, world_hash

import engine as habitat_sim
from engine.physics import MotionType
from engine.sensors import CameraSensor, CameraSensorSpec
from navmesh import NavMeshSettings, PathFinder, ShortestPath
from render import video as vut
from render.settings import MAX_PIXELS

EXAMPLES = settings(
    max_examples=25,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
REFUSED = (ValueError, TypeError)
BAD_INPUTS_CHECKED = {"count": 0}


# -- the world under test ----------------------------------------------------------------------
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


def objects(sim) -> list:
    manager = sim.get_rigid_object_manager()
    return [manager.get_object_by_id(i) for i in sorted(manager._objects)]


def assert_refused(sim, call, errors=REFUSED, match: str | None = None) -> None:
    """``call()`` raises one of ``errors`` (message matching ``match``), world unchanged."""
    before = world_hash(sim)
    with pytest.raises(errors, match=match):
        call()
    assert world_hash(sim) == before
    assert bodies_are_finite(sim.get_physics_world())
    BAD_INPUTS_CHECKED["count"] += 1


# -- strategies ----------------------------------------------------------------------------------
finite = st.floats(allow_nan=False, allow_infinity=False, width=64)
non_finite = st.sampled_from([math.nan, math.inf, -math.inf])
junk = st.one_of(
    st.none(),
    st.text(max_size=4),
    st.binary(max_size=4),
    st.dictionaries(st.text(max_size=2), finite, max_size=2),
    st.just(object()),
)


def bad_vector(n: int):
    """Anything a setter of an n-vector must refuse."""
    with_non_finite = st.lists(st.one_of(finite, non_finite), min_size=n, max_size=n).filter(
        lambda v: not all(math.isfinite(x) for x in v)
    )
    return st.one_of(
        junk,
        st.lists(finite, max_size=n - 1),
        st.lists(finite, min_size=n + 1, max_size=n + 3),
        with_non_finite,
        st.lists(st.text(max_size=2), min_size=n, max_size=n),
    )


def bad_number(low: float | None = None, high: float | None = None, low_open: bool = False):
    """Non-numbers, non-finite numbers and numbers outside ``[low, high]``."""
    parts = [junk, non_finite, st.booleans()]
    if low is not None:
        below = finite.filter(lambda x: x <= low if low_open else x < low)
        parts.append(below)
    if high is not None:
        parts.append(finite.filter(lambda x: x > high))
    return st.one_of(*parts)


VECTOR_TARGETS = {
    "translation": (3, lambda o, v: setattr(o, "translation", v)),
    "rotation": (4, lambda o, v: setattr(o, "rotation", v)),
    "linear_velocity": (3, lambda o, v: setattr(o, "linear_velocity", v)),
    "angular_velocity": (3, lambda o, v: setattr(o, "angular_velocity", v)),
    "translate": (3, lambda o, v: o.translate(v)),
    "translate_local": (3, lambda o, v: o.translate_local(v)),
    "apply_force": (3, lambda o, v: o.apply_force(v, [0.0, 0.0, 0.0])),
    "apply_force at": (3, lambda o, v: o.apply_force([1.0, 0.0, 0.0], v)),
    "apply_torque": (3, lambda o, v: o.apply_torque(v)),
    "apply_impulse": (3, lambda o, v: o.apply_impulse(v, [0.0, 0.0, 0.0])),
    "apply_impulse at": (3, lambda o, v: o.apply_impulse([1.0, 0.0, 0.0], v)),
    "apply_impulse_torque": (3, lambda o, v: o.apply_impulse_torque(v)),
    "intertia_diagonal": (3, lambda o, v: setattr(o, "intertia_diagonal", v)),
    "rotate axis": (3, lambda o, v: o.rotate(habitat_sim.mn.Rad(0.1), v)),
    "vc linear": (3, lambda o, v: setattr(o.velocity_control, "linear_velocity", v)),
    "vc angular": (3, lambda o, v: setattr(o.velocity_control, "angular_velocity", v)),
    "node scaling": (3, lambda o, v: setattr(o.root_scene_node, "scaling", v)),
    "node translation": (3, lambda o, v: setattr(o.root_scene_node, "translation", v)),
}

SCALAR_TARGETS = {
    "mass": (dict(low=0.0, low_open=True), lambda o, v: setattr(o, "mass", v)),
    "friction_coefficient": (dict(low=0.0), lambda o, v: setattr(o, "friction_coefficient", v)),
    "restitution_coefficient": (
        dict(low=0.0, high=1.0),
        lambda o, v: setattr(o, "restitution_coefficient", v),
    ),
    "linear_damping": (dict(low=0.0, high=1.0), lambda o, v: setattr(o, "linear_damping", v)),
    "angular_damping": (dict(low=0.0, high=1.0), lambda o, v: setattr(o, "angular_damping", v)),
    "rotate angle": ({}, lambda o, v: o.rotate_x(v)),
    "motion_type": (dict(low=0.0, high=2.5), lambda o, v: setattr(o, "motion_type", v)),
    "step_physics dt": ({}, lambda o, v: o._world.step_physics(v)),
}


# -- objects ---------------------------------------------------------------------------------------
@EXAMPLES
@given(data=st.data())
def test_object_vector_setters_refuse_bad_vectors(sim, data):
    name = data.draw(st.sampled_from(sorted(VECTOR_TARGETS)), label="target")
    size, call = VECTOR_TARGETS[name]
    obj = data.draw(st.sampled_from(objects(sim)), label="object")
    value = data.draw(bad_vector(size), label="value")
    assert_refused(sim, lambda: call(obj, value))


@EXAMPLES
@given(data=st.data())
def test_object_scalar_setters_refuse_bad_numbers(sim, data):
    name = data.draw(st.sampled_from(sorted(SCALAR_TARGETS)), label="target")
    bounds, call = SCALAR_TARGETS[name]
    obj = data.draw(st.sampled_from(objects(sim)), label="object")
    value = data.draw(bad_number(**bounds), label="value")
    if name == "motion_type" and isinstance(value, float) and value in (0.0, 1.0, 2.0):
        value = 0.5  # a float equal to a member is still not a MotionType
    assert_refused(sim, lambda: call(obj, value))


@EXAMPLES
@given(
    a=st.floats(1e-6, 1e3),
    b=st.floats(1e-6, 1e3),
    excess=st.floats(1e-4, 1e3),
    order=st.permutations([0, 1, 2]),
)
def test_inertia_breaking_the_triangle_inequality_is_refused(sim, a, b, excess, order):
    inertia = np.array([a, b, (a + b) * (1.0 + excess)])[list(order)]
    obj = objects(sim)[0]
    assert_refused(
        sim, lambda: setattr(obj, "intertia_diagonal", inertia), match="triangle inequality"
    )


OVERFLOW_TARGETS = (
    "translate",
    "apply_impulse",
    "apply_force",
    "apply_torque",
    "apply_impulse_torque",
    "transformation",
)


@EXAMPLES
@given(
    name=st.sampled_from(OVERFLOW_TARGETS),
    big=st.floats(0.9e308, 1.7e308),
    sign=st.sampled_from([-1.0, 1.0]),
    axis=st.integers(0, 2),
)
def test_values_that_overflow_only_when_used_are_refused(sim, name, big, sign, axis):
    """The first call is fine (finite result), the second would overflow: refused."""
    obj = objects(sim)[0]  # dynamic
    original = (obj.translation, obj.rotation, obj.linear_velocity, obj.angular_velocity)
    vector = np.zeros(3)
    vector[axis] = sign * big
    try:
        if name == "transformation":
            matrix = np.eye(4)
            matrix[:3, :3] *= big  # columns of norm 1e308: fine; their squares overflow
            matrix[axis, 3] = 1.0
            obj.transformation = matrix
            assert bodies_are_finite(sim.get_physics_world())
            matrix[:3, :3] = np.diag([1.0, 1.0, -1.0]) * 1e300  # a (huge) reflection
            assert_refused(sim, lambda: setattr(obj, "transformation", matrix), ValueError)
            return
        call = {
            "translate": lambda: obj.translate(vector),
            "apply_impulse": lambda: obj.apply_impulse(vector * obj.mass, [0, 0, 0]),
            "apply_force": lambda: obj.apply_force(vector, [0, 0, 0]),
            "apply_torque": lambda: obj.apply_torque(vector),
            "apply_impulse_torque": lambda: obj.apply_impulse_torque(vector),
        }[name]
        try:
            call()  # may already be refused (a force's h F / m), else it is finite
        except ValueError:
            pass
        assert bodies_are_finite(sim.get_physics_world())
        assert_refused(sim, call, ValueError, match="non-finite")
    finally:
        sim.get_physics_world().bodies.body_force[obj.object_id] = 0.0
        sim.get_physics_world().bodies.body_torque[obj.object_id] = 0.0
        obj.translation, obj.rotation = original[0], original[1]
        obj.linear_velocity, obj.angular_velocity = original[2], original[3]


@settings(
    max_examples=6,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(speed=st.floats(1e154, 1.7e308), angular=st.booleans())
def test_huge_speeds_are_clamped_to_the_limit_not_to_zero(sim, speed, angular):
    from engine.physics import settings as constants

    obj = objects(sim)[2]
    original = obj.translation
    obj.translation = [3.0, 30.0, 0.0]  # in the air: nothing to hit in one step
    try:
        if angular:
            obj.angular_velocity = [0.0, speed, 0.0]
        else:
            obj.linear_velocity = [speed, 0.0, 0.0]
        sim.step_physics(0.0)  # one fixed step; in the air nothing is hit
        value = obj.angular_velocity if angular else obj.linear_velocity
        limit = constants.MAX_ANGULAR_SPEED if angular else constants.MAX_LINEAR_SPEED
        assert bodies_are_finite(sim.get_physics_world())
        assert np.linalg.norm(np.asarray(value)) == pytest.approx(limit, rel=1e-6)
    finally:
        obj.translation, obj.linear_velocity, obj.angular_velocity = original, [0, 0, 0], [0, 0, 0]


def test_huge_rotation_components_are_normalized_without_overflow(sim):
    obj = objects(sim)[0]
    original = obj.rotation
    obj.rotation = [1e300, 1e300, 0.0, 0.0]
    np.testing.assert_allclose(
        np.asarray(obj.rotation.xyzw), [math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0], atol=1e-12
    )
    obj.rotation = original
    assert bodies_are_finite(sim.get_physics_world())


def test_a_kinematic_node_with_zero_scale_is_refused(sim):
    kinematic = objects(sim)[1]
    assert_refused(
        sim,
        lambda: setattr(kinematic.root_scene_node, "scaling", [0.0, 0.0, 0.0]),
        ValueError,
        match="scaling",
    )


# -- templates ----------------------------------------------------------------------------------
TEMPLATE_FIELDS = {
    "scale": st.lists(st.one_of(finite, non_finite), min_size=3, max_size=3).filter(
        lambda v: not all(math.isfinite(x) and x > 0 for x in v)
    ),
    "collision_asset_size": st.lists(finite, min_size=3, max_size=3).filter(lambda v: min(v) <= 0),
    "restitution_coefficient": bad_number(0.0, 1.0),
    "linear_damping": bad_number(0.0, 1.0),
    "angular_damping": bad_number(0.0, 1.0),
    "mass": bad_number(0.0, low_open=True),
    "friction_coefficient": bad_number(0.0),
    "inertia": st.tuples(st.floats(1e-3, 10), st.floats(1e-3, 10), st.floats(1e-3, 10)).map(
        lambda t: [t[0], t[1], (t[0] + t[1]) * 1.01 + t[2]]
    ),
    "units_to_meters": bad_number(0.0, low_open=True),
}


@EXAMPLES
@given(data=st.data())
def test_template_fields_get_the_object_limits(sim, data):
    templates = sim.get_object_template_manager()
    handle = data.draw(st.sampled_from(templates.get_template_handles()), label="template")
    name = data.draw(st.sampled_from(sorted(TEMPLATE_FIELDS)), label="field")
    value = data.draw(TEMPLATE_FIELDS[name], label="value")
    template = templates.get_template_by_handle(handle)
    assert_refused(sim, lambda: setattr(template, name, value))


@EXAMPLES
@given(
    up=st.lists(st.floats(-1, 1), min_size=3, max_size=3),
    front=st.lists(st.floats(-1, 1), min_size=3, max_size=3),
)
def test_skewed_or_degenerate_frames_are_refused_at_registration(sim, up, front):
    up, front = np.array(up), np.array(front)
    lengths = np.linalg.norm(up), np.linalg.norm(front)
    if min(lengths) > 1e-9 and abs(up @ front) / (lengths[0] * lengths[1]) < 1e-3:
        front = front + up  # make an orthogonal pair skewed
    templates = sim.get_object_template_manager()
    template = templates.get_template_by_handle(templates.get_template_handles("cheezit")[0])
    template.orient_up, template.orient_front = up, front
    assert_refused(sim, lambda: templates.register_template(template, "skewed"), ValueError)


BAD_CONFIGS = [
    {"scale": [-1.0, 1.0, 1.0]},
    {"scale": [0.0, 1.0, 1.0]},
    {"scale": 5.0},
    {"scale": [1.0, math.nan, 1.0]},
    {"collision_asset_size": [1.0, -1.0, 1.0]},
    {"restitution_coefficient": 5.0},
    {"restitution_coefficient": -0.1},
    {"inertia": [1.0, 1.0, 10.0]},
    {"inertia": [-1.0, 1.0, 1.0]},
    {"mass": -2.0},
    {"mass": 0},
    {"up": [0.0, 0.0, 0.0]},
    {"up": [1.0, 1.0, 10.0]},
    {"up": [0, 1, 0], "front": [0, 1, 0]},
    {"linear_damping": 2.0},
    {"angular_damping": -1.0},
    {"friction_coefficient": None},
    {"COM": "x"},
    {"user_defined": [1, 2]},
    {"semantic_id": 1.5},
    {"units_to_meters": 0.0},
]


@pytest.mark.parametrize("bad", BAD_CONFIGS, ids=lambda bad: "-".join(bad))
def test_bad_config_files_register_nothing(sim, bad, tmp_path):
    path = tmp_path / "bad.object_config.json"
    path.write_text(json.dumps({"render_asset": "cubeSolid", **bad}))
    templates = sim.get_object_template_manager()
    assert_refused(sim, lambda: templates.load_configs(str(path)), ValueError)


def test_null_in_user_defined_is_skipped_with_a_warning_as_habitat(sim, tmp_path):
    path = tmp_path / "nulls.object_config.json"
    path.write_text(
        json.dumps(
            {
                "render_asset": "cubeSolid",
                "user_defined": {
                    "gone": None,
                    "partly": [1, None, 2],
                    "rotation": [1, None, 0, 0],
                    "kept": 3,
                    "nested": {"also_gone": None, "fine": "yes"},
                },
            }
        )
    )
    templates = sim.get_object_template_manager()
    with pytest.warns(UserWarning, match="null"):
        (template_id,) = templates.load_configs(str(path))
    user = templates.get_template_by_id(template_id).get_user_config()
    assert user.get_keys() == ["kept"] and user.get("kept") == 3
    assert user.get_subconfig("nested").get_keys() == ["fine"]
    templates.remove_template_by_id(template_id)


# -- sensors -------------------------------------------------------------------------------------
SPEC_FIELDS = {
    "resolution": st.one_of(
        junk,
        st.lists(st.integers(-5, 0), min_size=2, max_size=2),
        st.tuples(st.sampled_from([math.nan, math.inf, 1.5, -3.0]), st.integers(1, 64)),
        st.tuples(st.integers(MAX_PIXELS // 64 + 1, 10**7), st.integers(65, 10**7)),
        st.lists(st.integers(1, 8), min_size=3, max_size=3),
    ),
    "hfov": st.one_of(bad_number(), st.floats(180, 1e9), st.floats(-1e9, 0)),
    "near": st.one_of(bad_number(), st.floats(-1e9, 0)),
    "far": st.one_of(bad_number(), st.floats(-1e9, 0.005)),
    "position": bad_vector(3),
    "orientation": bad_vector(3),
    "ortho_scale": st.one_of(bad_number(), st.floats(-1e9, 0)),
}


@EXAMPLES
@given(data=st.data())
def test_sensor_specs_are_refused_at_sensor_creation(sim, data):
    name = data.draw(st.sampled_from(sorted(SPEC_FIELDS)), label="field")
    value = data.draw(SPEC_FIELDS[name], label="value")
    spec = CameraSensorSpec()
    spec.uuid = "bad"
    setattr(spec, name, value)
    node = sim.agents[0].scene_node
    children = len(node.children)
    assert_refused(sim, lambda: CameraSensor(spec, node))
    assert len(node.children) == children


# -- navmesh settings, budgets, queries --------------------------------------------------------
NAV_FIELDS = {
    "cell_size": st.one_of(bad_number(0.0, low_open=True), st.floats(1e-6, 1e-3)),
    "cell_height": st.one_of(bad_number(0.0, low_open=True), st.floats(1e-7, 1e-5)),
    "agent_height": bad_number(0.0, low_open=True),
    "agent_radius": bad_number(0.0),
    "agent_max_climb": bad_number(0.0),
    "agent_max_slope": bad_number(0.0, 90.0),
    "region_min_size": bad_number(0.0),
    "filter_ledge_spans": st.one_of(junk, st.integers(), finite),
}


@EXAMPLES
@given(data=st.data())
def test_navmesh_settings_and_budgets_are_refused_before_building(sim, data):
    name = data.draw(st.sampled_from(sorted(NAV_FIELDS)), label="field")
    value = data.draw(NAV_FIELDS[name], label="value")
    nav_settings = NavMeshSettings()
    setattr(nav_settings, name, value)
    match = (
        "MAX_GRID_CELLS|MAX_RASTER_SAMPLES"
        if (name in ("cell_size", "cell_height") and isinstance(value, float) and 0 < value < 1e-2)
        else None
    )
    assert_refused(sim, lambda: sim.recompute_navmesh(sim.pathfinder, nav_settings), match=match)
    assert sim.pathfinder.is_loaded


QUERIES = {
    "snap_point": lambda pf, p: pf.snap_point(p),
    "is_navigable": lambda pf, p: pf.is_navigable(p),
    "get_island": lambda pf, p: pf.get_island(p),
    "try_step start": lambda pf, p: pf.try_step(p, [1.0, 0.0, 0.0]),
    "try_step end": lambda pf, p: pf.try_step([1.0, 0.0, 0.0], p),
    "try_step_no_sliding": lambda pf, p: pf.try_step_no_sliding(p, [1.0, 0.0, 0.0]),
    "find_path": lambda pf, p: pf.find_path(
        ShortestPath(requested_start=p, requested_end=[1, 0, 0])
    ),
    "distance_to_closest_obstacle": lambda pf, p: pf.distance_to_closest_obstacle(p),
    "random point near": lambda pf, p: pf.get_random_navigable_point_near(p, 1.0),
}


@EXAMPLES
@given(data=st.data())
def test_pathfinder_queries_refuse_bad_points(sim, data):
    name = data.draw(st.sampled_from(sorted(QUERIES)), label="query")
    value = data.draw(bad_vector(3), label="point")
    assert_refused(sim, lambda: QUERIES[name](sim.pathfinder, value))


@EXAMPLES
@given(
    point=st.lists(
        st.one_of(st.floats(-1.7e308, -1e12), st.floats(1e12, 1.7e308)), min_size=3, max_size=3
    )
)
def test_far_points_snap_to_nothing_without_overflow(sim, point):
    """Habitat's result for a point far from every polygon: NaN snap, the step stays put."""
    pf = sim.pathfinder
    before = world_hash(sim)
    assert np.all(np.isnan(pf.snap_point(point)))
    assert pf.get_island(point) == -1 and not pf.is_navigable(point)
    start = pf.get_random_navigable_point()
    np.testing.assert_array_equal(pf.try_step(point, start), np.asarray(point))
    assert np.all(np.isfinite(pf.try_step(start, point)))
    assert world_hash(sim) == before


@EXAMPLES
@given(
    mpp=st.one_of(bad_number(0.0, low_open=True), st.floats(1e-9, 1e-3)),
    height=st.one_of(finite, non_finite),
)
def test_topdown_views_over_the_budget_are_refused(sim, mpp, height):
    assert_refused(sim, lambda: sim.pathfinder.get_topdown_view(mpp, height))


# -- ray casts -----------------------------------------------------------------------------------
@EXAMPLES
@given(
    ray=st.one_of(junk, st.integers(), st.lists(finite, max_size=6)),
    distance=st.one_of(bad_number(0.0), st.just(100.0)),
)
def test_cast_ray_refuses_non_rays_and_bad_distances(sim, ray, distance):
    if distance == 100.0:
        assert_refused(sim, lambda: sim.cast_ray(ray, distance), TypeError, match="ray")
    else:
        good = habitat_sim.geo.Ray([0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
        assert_refused(sim, lambda: sim.cast_ray(good, distance))


@EXAMPLES
@given(
    origin=st.lists(st.floats(-1e300, 1e300), min_size=3, max_size=3),
    direction=st.lists(st.floats(-1e300, 1e300), min_size=3, max_size=3),
)
def test_cast_ray_with_huge_rays_returns_finite_hits(sim, origin, direction):
    before = world_hash(sim)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no overflow anywhere
        results = sim.cast_ray(habitat_sim.geo.Ray(origin, direction), 10.0)
    for hit in results.hits:
        assert np.all(np.isfinite(np.asarray(hit.point))) and math.isfinite(hit.ray_distance)
    assert world_hash(sim) == before


# -- videos --------------------------------------------------------------------------------------
@EXAMPLES
@given(
    dims=st.one_of(
        st.just("empty"),
        junk.filter(lambda v: v is not None),
        st.tuples(st.integers(-3, 0), st.integers(1, 8)),
        st.tuples(st.integers(MAX_PIXELS // 8 + 1, 10**9), st.integers(9, 10**9)),
    )
)
def test_make_video_refuses_empty_lists_and_bad_dims(sim, dims):
    frame = {"color": np.zeros((8, 8, 4), np.uint8)}
    with tempfile.TemporaryDirectory() as folder:
        target = str(Path(folder) / "clip")
        frames = [] if dims == "empty" else [frame]
        size = None if dims == "empty" else dims

        def call() -> None:
            vut.make_video(frames, "color", "color", target, open_vid=False, video_dims=size)

        assert_refused(sim, call, ValueError)
        assert not any(Path(folder).iterdir())  # nothing written


# -- .navmesh files ---------------------------------------------------------------------------
@pytest.fixture(scope="module")
def navmesh_bytes(sim) -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "good.navmesh"
        assert sim.pathfinder.save_nav_mesh(path)
        return path.read_bytes()


def _mutated_archive(good: bytes, key: str, how: str, rng: np.random.Generator) -> bytes:
    """The good archive with one array replaced by an inconsistent one."""
    arrays = dict(np.load(io.BytesIO(good)))
    array = arrays[key]
    if how == "shape":
        arrays[key] = np.zeros(
            (*array.shape[:-1], array.shape[-1] + 1) if array.ndim else (2,), dtype=array.dtype
        )
    elif how == "dtype":
        arrays[key] = np.full(array.shape, "x") if array.dtype.kind != "U" else np.array(7.0)
    elif how == "values":
        if array.dtype.kind in "iu":
            arrays[key] = rng.integers(-100, 100, array.shape).astype(array.dtype)
        elif array.dtype.kind == "f":
            arrays[key] = np.full(array.shape, rng.choice([math.nan, math.inf, -1.0, 0.0]))
        elif array.dtype.kind == "b":
            arrays[key] = ~array
        else:
            arrays[key] = np.array("{not json" if key == "settings_json" else "other")
    elif how == "missing":
        del arrays[key]
    stream = io.BytesIO()
    np.savez_compressed(stream, **arrays)
    if how == "huge":  # a header claiming 8 GB of floats in a few bytes: must not be read
        with zipfile.ZipFile(stream, "a") as archive:
            header = io.BytesIO()
            npy_format.write_array_header_1_0(
                header, {"descr": "<f8", "fortran_order": False, "shape": (1000, 1000, 1000)}
            )
            archive.writestr(f"{key}_huge.npy", header.getvalue() + bytes(64))
        stream = _renamed(stream.getvalue(), f"{key}_huge.npy", f"{key}.npy")
    return stream.getvalue()


def _renamed(content: bytes, old: str, new: str) -> io.BytesIO:
    """A copy of a zip archive where member ``old`` replaces member ``new``."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(content)) as source, zipfile.ZipFile(out, "w") as target:
        for info in source.infolist():
            if info.filename == new:
                continue
            data = source.read(info.filename)
            target.writestr(new if info.filename == old else info.filename, data)
    return out


@settings(
    max_examples=40,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(data=st.data())
def test_bad_navmesh_files_are_refused_and_the_old_one_keeps_working(sim, navmesh_bytes, data):
    kind = data.draw(st.sampled_from(["bytes", "truncated", "array"]), label="kind")
    if kind == "bytes":
        content = data.draw(st.binary(max_size=64), label="bytes")
    elif kind == "truncated":
        content = navmesh_bytes[: data.draw(st.integers(0, len(navmesh_bytes) - 1), label="n")]
    else:
        key = data.draw(
            st.sampled_from(
                [
                    "floor",
                    "ceiling",
                    "navigable",
                    "links",
                    "island",
                    "bounds",
                    "origin_xz",
                    "cell_size",
                    "settings_json",
                    "format_version",
                ]
            ),
            label="key",
        )
        how = data.draw(
            st.sampled_from(["shape", "dtype", "values", "missing", "huge"]), label="how"
        )
        rng = np.random.default_rng(data.draw(st.integers(0, 1000), label="seed"))
        content = _mutated_archive(navmesh_bytes, key, how, rng)
        if content == navmesh_bytes:
            return
    pf = sim.pathfinder
    probe = pf.get_random_navigable_point()
    snapped = pf.snap_point(probe)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bad.navmesh"
        path.write_bytes(content)
        before = world_hash(sim)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            loaded = pf.load_nav_mesh(path)
        if loaded:  # a mutation that kept the file consistent (floors all moved to -1 m)
            assert pf.load_nav_mesh(_write(folder, navmesh_bytes))
            return
        assert any("load_nav_mesh" in str(w.message) for w in caught)
        assert world_hash(sim) == before
        np.testing.assert_array_equal(pf.snap_point(probe), snapped)
        BAD_INPUTS_CHECKED["count"] += 1


def _write(folder: str, content: bytes) -> Path:
    path = Path(folder) / "restore.navmesh"
    path.write_bytes(content)
    return path


def test_a_bad_navmesh_beside_the_stage_leaves_the_simulator_without_one(demo_data, tmp_path):
    scene = demo_data / "scene_datasets/demo"
    for name in ("apartment.glb", "apartment.stage_config.json"):
        shutil.copy(scene / name, tmp_path / name)
    (tmp_path / "apartment.navmesh").write_bytes(b"")
    cfg = habitat_sim.SimulatorConfiguration()
    cfg.scene_id = str(tmp_path / "apartment.glb")
    with pytest.warns(UserWarning, match="not a valid navmesh"):
        simulator = habitat_sim.Simulator(habitat_sim.Configuration(cfg))
    assert not simulator.pathfinder.is_loaded
    simulator.close()


@pytest.mark.parametrize(
    "name, value",
    [
        ("agent_radius", 1e6),
        ("agent_radius", 1e300),
        ("region_min_size", 1e150),
        ("agent_max_climb", 1e6),
        ("cell_size", 1e3),
        ("agent_height", 1e300),
    ],
)
def test_extreme_but_valid_navmesh_settings_finish(name, value):
    """Work is bounded by the grid, not by the values: these used to hang or overflow."""
    floor = np.array([[0, 0, 0], [10, 0, 0], [10, 0, 10], [0, 0, 10]], np.float64)
    faces = np.array([[0, 2, 1], [0, 3, 2]], np.int64)
    nav_settings = NavMeshSettings()
    setattr(nav_settings, name, value)
    pathfinder = PathFinder()
    assert pathfinder.build(floor, faces, nav_settings)
    area = pathfinder.navigable_area
    if name in ("agent_radius", "region_min_size", "cell_size"):
        assert area == 0.0  # eroded away, or every island under region_min_size^2 cells
    else:
        assert 0.0 < area <= 100.0 + 1e-9


# -- issue 10's reports, one by one ----------------------------------------------------------
def test_issue_cases_objects(sim):
    dynamic, kinematic = objects(sim)[0], objects(sim)[1]
    start = dynamic.translation
    dynamic.translate([1e308, 0.0, 0.0])
    assert_refused(sim, lambda: dynamic.translate([1e308, 0.0, 0.0]), ValueError, match="vector")
    dynamic.translation = start
    dynamic.apply_impulse([1e308, 0.0, 0.0], [0.0, 0.0, 0.0])
    assert_refused(
        sim,
        lambda: dynamic.apply_impulse([1e308, 0.0, 0.0], [0.0, 0.0, 0.0]),
        ValueError,
        match="impulse",
    )
    dynamic.linear_velocity = [0.0, 0.0, 0.0]
    assert_refused(
        sim,
        lambda: setattr(kinematic.root_scene_node, "scaling", [0, 0, 0]),
        ValueError,
        match="scaling",
    )
    assert_refused(sim, lambda: sim.cast_ray(None), TypeError, match="ray")


def test_issue_cases_templates_sensors_budgets_files(sim, tmp_path):
    templates = sim.get_object_template_manager()
    cube = templates.get_template_by_handle(templates.get_template_handles("cubeSolid")[0])
    for name, value in (
        ("scale", [-1.0, 1.0, 1.0]),
        ("restitution_coefficient", 5.0),
        ("inertia", [1.0, 1.0, 10.0]),
    ):
        assert_refused(sim, lambda n=name, v=value: setattr(cube, n, v), ValueError, match=name)
    spec = CameraSensorSpec()
    for resolution in ([math.nan, 64], [100000, 100000]):
        spec.resolution = resolution
        assert_refused(
            sim,
            lambda: CameraSensor(spec, sim.agents[0].scene_node),
            ValueError,
            match="resolution",
        )
    tiny = NavMeshSettings()
    tiny.cell_size = 1e-4
    assert_refused(
        sim, lambda: sim.recompute_navmesh(sim.pathfinder, tiny), ValueError, match="MAX_GRID_CELLS"
    )
    assert_refused(
        sim,
        lambda: sim.pathfinder.get_topdown_view(1e-5, 0.0),
        ValueError,
        match="MAX_TOPDOWN_PIXELS",
    )
    assert_refused(
        sim,
        lambda: vut.make_video([], "color", "color", str(tmp_path / "v"), open_vid=False),
        ValueError,
        match="empty",
    )
    empty = tmp_path / "empty.navmesh"
    empty.write_bytes(b"")
    before = world_hash(sim)
    with pytest.warns(UserWarning, match="load_nav_mesh"):
        assert sim.pathfinder.load_nav_mesh(empty) is False
    assert world_hash(sim) == before and sim.pathfinder.is_loaded
    far = [1e300, 0.0, 1e300]
    assert np.all(np.isnan(sim.pathfinder.snap_point(far)))
    np.testing.assert_array_equal(sim.pathfinder.try_step(far, [0.0, 0.0, 0.0]), far)


def test_kinematic_velocity_control_that_would_overflow_is_refused_at_the_step(sim):
    kinematic = objects(sim)[1]
    original = kinematic.translation
    kinematic.translation = [1.7e308, 0.5, 0.0]
    control = kinematic.velocity_control
    control.controlling_lin_vel, control.linear_velocity = True, [1e308, 0.0, 0.0]
    try:
        assert_refused(sim, lambda: sim.step_physics(1.0), ValueError, match="linear_velocity")
    finally:
        control.controlling_lin_vel, control.linear_velocity = False, [0.0, 0.0, 0.0]
        kinematic.translation = original
