"""Issue 10's bad-input reports, one by one: each is refused with a clear exception.

The objects' overflowing ``translate`` / ``apply_impulse``, a zero node scale, ``cast_ray``
of None, bad template fields, oversized sensor resolutions, navmesh and top-down budgets,
an empty video and an empty ``.navmesh`` file.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from bad_inputs import (
    assert_refused,
    objects,
)
from world_hash import world_hash

from engine.sensors import CameraSensor, CameraSensorSpec
from navmesh import NavMeshSettings
from render import video as vut


# -- issue 10's reports, one by one ----------------------------------------------------------
def test_issue_cases_objects(sim):
    dynamic, kinematic = objects(sim)[0], objects(sim)[1]
    start = dynamic.translation
    # refused the first time: 1e308 m is beyond the 32-bit float range Habitat keeps poses in
    assert_refused(sim, lambda: dynamic.translate([1e308, 0.0, 0.0]), ValueError, match="vector")
    assert dynamic.translation == start
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
        ("restitution_coefficient", -5.0),  # above 1 is stored (Habitat stores it)
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
