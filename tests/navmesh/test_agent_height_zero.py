"""``agent_height`` 0 is accepted, as Habitat accepts it (its ``make_cfg`` copies
``sensor_height`` into the navmesh settings, and ``test_gfx.py`` sets that to 0): no
clearance is required, so a floor under a low slab stays walkable."""

from __future__ import annotations

import numpy as np
import pytest

from navmesh import NavMeshSettings


def test_zero_is_valid_and_negative_is_not():
    settings = NavMeshSettings()
    settings.agent_height = 0.0
    settings.validate()
    settings.agent_height = -0.1
    with pytest.raises(ValueError, match="agent_height"):
        settings.validate()


@pytest.mark.parametrize(("agent_height", "snapped_y"), [(0.0, 0.0), (1.5, 0.4)])
def test_a_floor_under_a_low_slab_needs_no_clearance_at_height_zero(
    geometry, agent_height, snapped_y
):
    floor = geometry.box((0, -0.1, 0), (6, 0, 4))
    slab = geometry.box((3, 0.3, 0), (6, 0.4, 4))  # 0.3 m of clearance over x in [3, 6]
    pf = geometry.build(floor, slab, agent_height=agent_height)
    assert pf.is_navigable(np.array([1.5, 0.0, 2.0]))
    # under the slab: the floor itself (height 0), else only the slab's top (0.4 m) is there
    snapped = pf.snap_point(np.array([4.5, 0.0, 2.0]))
    assert snapped[1] == pytest.approx(snapped_y, abs=0.05)
