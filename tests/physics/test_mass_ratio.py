"""Extreme mass ratios (a heavy cube on a light one): within the range the solver holds the
light cube stays put; beyond it a warning names the masses when such a mass is set
(``engine/physics/mass_ratio.py``, docs/reliability.md "Mass ratios").

Before: no warning at any ratio, and at 1e4-1e6 : 1 the light cube was squeezed out
sideways at 1.5-6 m/s while the heavy one landed on the floor.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from engine import mn
from engine.physics.objects.mass_ratio import MAX_STABLE_MASS_RATIO
from engine.simulator import Configuration, Simulator, SimulatorConfiguration

HALF = 0.1  # m, the cubes' half extent


class _Records(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


@pytest.fixture
def warnings_logged():
    handler = _Records()
    logger = logging.getLogger("rigidsim.physics")
    logger.addHandler(handler)
    yield handler.messages
    logger.removeHandler(handler)


def _plane_sim(test_assets):
    cfg = SimulatorConfiguration()
    cfg.scene_id = str(test_assets / "scenes/plane.glb")
    return Simulator(Configuration(cfg))


def _cube_template(sim, name: str, mass: float) -> str:
    templates = sim.get_object_template_manager()
    template = templates.get_template_by_handle("cubeSolid")
    template.scale, template.mass = [HALF] * 3, mass
    return templates.get_template_by_id(templates.register_template(template, name)).handle


def _drop_heavy_on_light(sim, ratio: float, seconds: float = 3.0):
    """A 1 kg cube on the floor, a ``ratio`` kg one dropped 10 cm onto it, 3 cm off center and
    turned 0.2 rad: the light cube's largest sideways drift (m) and the heavy one's end
    height (m)."""
    manager = sim.get_rigid_object_manager()
    light = manager.add_object_by_template_handle(_cube_template(sim, "light", 1.0))
    heavy = manager.add_object_by_template_handle(_cube_template(sim, f"heavy{ratio:g}", ratio))
    light.translation = [0.0, HALF + 0.001, 0.0]
    heavy.translation = [0.03, 3 * HALF + 0.1, 0.015]
    heavy.rotation = mn.Quaternion.rotation(mn.Rad(0.2), mn.Vector3(0.0, 1.0, 0.0))
    drift = 0.0
    for _ in range(int(seconds * 60)):
        sim.step_physics(1.0 / 60.0)
        drift = max(drift, float(np.linalg.norm(np.asarray(light.translation)[[0, 2]])))
    return drift, float(heavy.translation.y)


@pytest.mark.parametrize("ratio", [10.0, 20.0])
def test_a_heavy_cube_dropped_on_a_light_one_within_the_stable_range_holds(
    test_assets, ratio, warnings_logged
):
    with _plane_sim(test_assets) as sim:
        drift, heavy_y = _drop_heavy_on_light(sim, ratio)
    assert drift < 0.01  # measured 0.28 cm at 10:1, 0.88 cm at 20:1
    assert heavy_y == pytest.approx(3 * HALF, abs=0.01)  # still on top
    assert warnings_logged == []


def test_a_mass_ratio_beyond_the_stable_range_logs_a_warning_naming_the_masses(
    test_assets, warnings_logged
):
    with _plane_sim(test_assets) as sim:
        manager = sim.get_rigid_object_manager()
        light = manager.add_object_by_template_handle(_cube_template(sim, "light", 1.0))
        heavy = manager.add_object_by_template_handle(_cube_template(sim, "heavy", 50.0))
        assert warnings_logged == []  # 50:1 is within the range
        heavy.mass = 1e4
        assert len(warnings_logged) == 1
        assert "10000 kg" in warnings_logged[0] and "1 kg" in warnings_logged[0]
        assert f"{MAX_STABLE_MASS_RATIO:g}:1" in warnings_logged[0]
        heavy.mass = 1e6  # once per object
        assert len(warnings_logged) == 1
        tiny = manager.add_object_by_template_handle(_cube_template(sim, "tiny", 1e-3))
        assert len(warnings_logged) == 2 and "0.001 kg" in warnings_logged[1]
        manager.remove_object_by_id(tiny.object_id)
        assert light.is_alive and heavy.mass == 1e6  # a warning, not a refusal (as Habitat)
