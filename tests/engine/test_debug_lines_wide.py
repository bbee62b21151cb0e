"""Debug lines in fisheye and equirectangular frames and in asynchronous renders
(engine.sensors.line_overlay): drawn into the cube faces before the resampling, so a line lands on
the pixels whose rays point at it.

Hand geometry: the sensor is at the agent's height ``h = 1.5 m`` looking down -Z, in an empty
world. A long red line at eye height, ``y = h``, 1 m ahead, lies in the horizontal plane
through the camera: every pixel it colors has a ray of elevation ~0 (within the 3-pixel
line's half width, 1.5 face pixels of 90/S degrees, plus one face pixel of bilinear
filtering and half an output pixel), and the
pixel looking straight ahead is red. Straight lines through the image center stay straight
in the double-sphere fisheye (the model is radial), so that line is a horizontal band
through the center row there.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import engine as habitat_sim
from engine import mn
from render import camera_models

RED = [255, 0, 0, 255]


def make_sim(*specs, enable_physics=False):
    sim_cfg = habitat_sim.SimulatorConfiguration()
    sim_cfg.scene_id = "NONE"
    sim_cfg.enable_physics = enable_physics
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    agent_cfg.sensor_specifications = list(specs)
    return habitat_sim.Simulator(habitat_sim.Configuration(sim_cfg, [agent_cfg]))


def fisheye_spec():
    spec = habitat_sim.FisheyeSensorDoubleSphereSpec()
    spec.uuid, spec.resolution, spec.focal_length = "fisheye", [64, 64], [20.0, 20.0]
    return spec


def pano_spec():
    spec = habitat_sim.EquirectangularSensorSpec()
    spec.uuid, spec.resolution = "pano", [32, 64]
    return spec


def pinhole_spec():
    spec = habitat_sim.CameraSensorSpec()
    spec.uuid, spec.resolution = "rgb", [48, 64]
    return spec


def draw_eye_level_line(sim):
    """A red line 1 m ahead at eye height (y = 1.5), 10 m long, 3 px wide."""
    lines = sim.get_debug_line_render()
    lines.set_line_width(3)
    lines.draw_transformed_line(
        mn.Vector3(-5.0, 1.5, -1.0), mn.Vector3(5.0, 1.5, -1.0), mn.Color4(1, 0, 0, 1)
    )


def test_a_line_at_eye_level_lies_on_the_panorama_horizon():
    with make_sim(pano_spec()) as sim:
        plain = sim.get_sensor_observations()["pano"]
        draw_eye_level_line(sim)
        drawn = sim.get_sensor_observations()["pano"]
    changed = np.any(drawn != plain, axis=-1)
    rays = camera_models.equirectangular_rays((32, 64))
    elevation = np.degrees(np.arcsin(rays[..., 1]))
    face_pixel, row = 90.0 / 32, 180.0 / 32
    bound = (1.5 + 1.0) * face_pixel + 0.5 * row
    assert changed.sum() > 0
    assert np.all(np.abs(elevation[changed]) <= bound + 1e-9)
    # in front and no wider than the line: |x| <= 5 at z = -1 is within 78.7 degrees, plus
    # the brush's half width, the filter and half a column
    azimuth = np.degrees(np.arctan2(rays[..., 0], -rays[..., 2]))
    end = math.degrees(math.atan(5.0)) + 2.5 * face_pixel + 0.5 * 360 / 64
    assert np.all(np.abs(azimuth[changed]) <= end)
    # the row just below the horizon is covered all along the line (|azimuth| < 70 deg)
    assert changed[16, 32 - 12 : 32 + 12].all()
    np.testing.assert_array_equal(drawn[16, 32], RED)  # straight ahead, at the horizon
    assert changed[15, 32] and drawn[15, 32, 0] > 128  # above it: partly red (filtered)
    assert not changed[:, 0].any()  # behind the camera


def test_a_line_through_the_fisheye_center_stays_a_straight_band():
    with make_sim(fisheye_spec()) as sim:
        plain = sim.get_sensor_observations()["fisheye"]
        draw_eye_level_line(sim)
        drawn = sim.get_sensor_observations()["fisheye"]
    changed = np.any(drawn != plain, axis=-1)
    rows = sorted(set(np.nonzero(changed)[0].tolist()))
    assert rows and set(rows) <= {30, 31, 32, 33}  # a band around the center row
    np.testing.assert_array_equal(drawn[32, 32], RED)
    # wider than a 90-degree pinhole view of the same line: the fisheye sees more of it
    assert changed[32].sum() > 32


@pytest.mark.parametrize("path", ["worker", "thread", "plain"])
def test_async_renders_draw_the_lines_taken_at_start(path):
    with make_sim(pinhole_spec(), fisheye_spec(), enable_physics=True) as sim:
        sim.get_renderer().processes = 1 if path == "worker" else 0
        sim._async_render.use_worker = path == "worker"
        sim._async_render.threaded = path == "thread"
        draw_eye_level_line(sim)
        expected = sim.get_sensor_observations()
        draw_eye_level_line(sim)
        sim.start_async_render_and_step_physics(1.0 / 60.0)
        sim.get_debug_line_render().draw_transformed_line(  # for the next draw, not this one
            mn.Vector3(0, 0, -1), mn.Vector3(0, 3, -1), mn.Color4(0, 1, 0, 1)
        )
        observed = sim.get_sensor_observations_async_finish()
        for uuid in ("rgb", "fisheye"):
            np.testing.assert_array_equal(observed[uuid], expected[uuid])
        np.testing.assert_array_equal(observed["rgb"][24, 32], RED)
