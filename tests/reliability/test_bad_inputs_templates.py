"""Bad template fields and config files: a clear exception, nothing registered.

Object template setters get the object setters' limits, skewed or degenerate ``up`` /
``front`` frames are refused at registration, and a bad ``*.object_config.json`` registers
nothing (a JSON null in ``user_defined`` is skipped with a warning, as Habitat does).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from bad_inputs import (
    EXAMPLES,
    assert_refused,
    bad_number,
    finite,
    non_finite,
)
from hypothesis import given
from hypothesis import strategies as st

# -- templates ----------------------------------------------------------------------------------
TEMPLATE_FIELDS = {
    "scale": st.lists(st.one_of(finite, non_finite), min_size=3, max_size=3).filter(
        lambda v: not all(math.isfinite(x) and x > 0 for x in v)
    ),
    "collision_asset_size": st.lists(finite, min_size=3, max_size=3).filter(lambda v: min(v) <= 0),
    # above 1 is stored with a warning, as Habitat stores it: only negative or non-finite
    "restitution_coefficient": bad_number(0.0),
    "linear_damping": bad_number(0.0),
    "angular_damping": bad_number(0.0),
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
    {"restitution_coefficient": math.inf},
    {"restitution_coefficient": -0.1},
    {"inertia": [1.0, 1.0, 10.0]},
    {"inertia": [-1.0, 1.0, 1.0]},
    {"mass": -2.0},
    {"mass": 0},
    {"up": [0.0, 0.0, 0.0]},
    {"up": [1.0, 1.0, 10.0]},
    {"up": [0, 1, 0], "front": [0, 1, 0]},
    {"linear_damping": -2.0},
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


@pytest.mark.parametrize("com", [1e39, 1e200, 1e300, -1e300])
@pytest.mark.parametrize("asset", ["cubeSolid", "mug"])
def test_a_com_beyond_float32_is_refused_naming_it_when_the_object_is_added(sim, com, asset):
    """The reliability probe: a registered template with ``com`` = 1e200 made
    ``add_object_by_template_handle`` raise qhull's internal error (QH6014, "not enough
    points") from deep in the hull code; now a ValueError naming the COM, world unchanged."""
    templates = sim.get_object_template_manager()
    template = templates.get_template_by_handle(templates.get_template_handles(asset)[0])
    template.com = [com, 0.0, 0.0]
    template_id = templates.register_template(template, f"far_com_{asset}_{com:g}")
    manager = sim.get_rigid_object_manager()
    handle = templates.get_template_by_id(template_id).handle
    try:
        assert_refused(
            sim, lambda: manager.add_object_by_template_handle(handle), ValueError, match="COM"
        )
    finally:
        templates.remove_template_by_id(template_id)
