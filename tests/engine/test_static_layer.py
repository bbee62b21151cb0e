"""The renderer's static layer, render threads and render worker process change no pixel:
every observation equals a full single-threaded in-process render, across the tutorial's
sections (all but the two navmesh drives, which render as the robot section does)
and across scene changes; a worker that dies is replaced by in-process renders."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

import engine as habitat_sim
import engine.simulator.simulator
from engine.demo import demo_data_path
from engine.physics.objects.rigid_object_manager import MotionType
from engine.sensors.render_scheduler import RenderScheduler
from engine.sensors.scene_render import SceneRenderer
from engine.tutorial.cli import run_tutorial
from engine.tutorial.runner import SECTION_NAMES
from engine.tutorial.scene_setup import make_configuration, place_agent
from render.settings import RenderSettings


class CheckedRenderer(SceneRenderer):
    """Renders observations a second time with a full single-threaded in-process renderer
    and asserts the two are bit-identical: every frame that used a static layer, and every
    ``FULL_CHECK_EVERY``-th frame of full renders; counts the modes and the places. Groups
    after the first render in a worker process when ``PROCESSES`` is 1 (at any size)."""

    modes: Counter = Counter()
    places: Counter = Counter()
    FULL_CHECK_EVERY = 4
    PROCESSES = 1

    def __init__(self, root, static_drawables=None, lights_for=None, **kwargs) -> None:
        super().__init__(
            root, static_drawables, lights_for, static_layer=True, threads=2,
            processes=self.PROCESSES,
        )  # fmt: skip
        self.scheduler.process_min_pixels = 0
        self.reference = SceneRenderer(
            root, static_drawables, lights_for, static_layer=False, threads=1, processes=0
        )
        self.n_full = 0

    def observe(self, sensors):
        fast = super().observe(sensors)
        CheckedRenderer.modes.update(self.last_modes.values())
        CheckedRenderer.places.update(self.last_places.values())
        if set(self.last_modes.values()) == {"full"}:
            self.n_full += 1
            if self.n_full % self.FULL_CHECK_EVERY:
                return fast
        CheckedRenderer.modes["checked"] += 1
        full = self.reference.observe(sensors)
        assert fast.keys() == full.keys()
        for uuid in full:
            assert fast[uuid].dtype == full[uuid].dtype
            assert fast[uuid].tobytes() == full[uuid].tobytes(), uuid
        return fast


@pytest.fixture
def checked(monkeypatch):
    CheckedRenderer.modes, CheckedRenderer.places = Counter(), Counter()
    monkeypatch.setattr(engine.simulator.simulator, "SceneRenderer", CheckedRenderer)
    monkeypatch.setattr(CheckedRenderer, "PROCESSES", 1)
    return CheckedRenderer


#: the tutorial's sections but the two navmesh drives: their robot cameras move, as in
#: ``embodied_agent``, so they render the same way (full renders, a third of them checked)
#: and would add a third of the run's time
CHECKED_SECTIONS = SECTION_NAMES[: SECTION_NAMES.index("embodied_agent") + 1]


def test_the_tutorial_sections_render_the_same_with_the_static_layer_and_the_worker(
    checked, tmp_path
):
    results = run_tutorial(
        str(tmp_path),
        make_video=False,
        fast=True,
        progress=False,
        keep_observations=True,
        sections=CHECKED_SECTIONS,
    )
    assert [r.name for r in results] == CHECKED_SECTIONS
    assert sum(r.frames for r in results) > 1200  # 1239 frames
    # the onlooker's six sections reuse their layers; the robot's cameras mostly move
    assert checked.modes["layer"] > 1500
    assert checked.modes["full"] > 850
    assert checked.modes["new layer"] >= 6
    assert checked.modes["checked"] > 850
    assert checked.places["worker"] > 1200  # the 3rd-person camera
    assert checked.places["here"] > 1200


def test_a_dead_worker_is_replaced_by_renders_in_this_process(checked):
    sim = small_sim()
    renderer = sim.get_renderer()
    sim.get_sensor_observations()
    assert renderer.last_places[("rgba_camera_3rdperson",)] == "worker"
    renderer.scheduler._worker._process.kill()  # noqa: SLF001 - simulate a crash
    with pytest.warns(RuntimeWarning, match="render worker"):
        sim.get_sensor_observations()  # checked against the reference renderer
    assert set(renderer.last_places.values()) == {"here"}
    for _ in range(3):
        sim.step_physics(1.0 / 60.0)
        sim.get_sensor_observations()
    assert set(renderer.last_modes.values()) == {"layer"}
    sim.close()


def small_sim() -> habitat_sim.Simulator:
    sim = habitat_sim.Simulator(make_configuration(str(demo_data_path()), (48, 64)))
    place_agent(sim)
    return sim


@pytest.mark.parametrize("processes", [0, 1])
def test_adding_removing_moving_and_relighting_objects_match_full_renders(
    checked, monkeypatch, processes
):
    monkeypatch.setattr(CheckedRenderer, "PROCESSES", processes)
    sim = small_sim()
    renderer = sim.get_renderer()
    templates = sim.get_object_template_manager()
    templates.load_configs(str(demo_data_path() / "objects/example_objects"))
    handle = templates.get_template_handles("cheezit")[0]
    manager = sim.get_rigid_object_manager()

    def frames(n: int = 3) -> list[str]:
        modes = []
        for _ in range(n):
            sim.step_physics(1.0 / 60.0)
            sim.get_sensor_observations()
            modes.append(sorted(set(renderer.last_modes.values())))
        return modes

    assert frames()[-1] == ["layer"]  # the empty apartment, camera at rest
    box = manager.add_object_by_template_handle(handle)
    box.translation = [2.39, -0.37, 0.0]  # in view of both cameras, falling
    assert frames()[-1] == ["layer"]  # a moving object keeps the layer
    changed = [["full"], ["new layer"], ["layer"]]  # a static change: full, then a new layer
    box.motion_type = MotionType.STATIC  # now part of the static layer
    assert frames() == changed
    box.motion_type = MotionType.KINEMATIC
    box.translation = [2.2, -0.5, 0.1]
    assert frames() == changed
    second = manager.add_object_by_template_handle(handle)
    second.translation = [2.3, -0.8, 0.3]
    assert frames()[-1] == ["layer"]  # a new moving object
    second.motion_type = MotionType.STATIC
    assert frames() == changed
    second.root_scene_node.translation = [2.3, -0.7, 0.3]  # a STATIC node moved by hand
    assert frames(1)[0] == ["full"]
    frames()
    # a new light setup for the default key (which the STATIC object uses): a static change
    sim.set_light_setup([habitat_sim.gfx.LightInfo(vector=[0.0, -1.0, 0.0, 0.0])])
    assert frames(1)[0] == ["full"]
    frames(1)
    sim.get_agent(0).agent_config.sensor_specifications[0].hfov = 70.0  # a sensor spec
    assert "full" in frames(1)[0]
    manager.remove_object_by_id(second.object_id)
    assert frames(1)[0] == ["full"]
    frames()
    manager.remove_all_objects()  # the last (kinematic) object: the layer stays valid
    assert frames() == [["layer"]] * 3
    sim.close()


def test_the_switches_select_single_threaded_full_renders(checked):
    sim = small_sim()
    renderer = sim.get_renderer()
    renderer.static_layer, renderer.threads = False, 1
    for _ in range(3):
        sim.get_sensor_observations()
        assert set(renderer.last_modes.values()) == {"full"}
    renderer.static_layer, renderer.threads = True, 2
    for _ in range(3):
        observation = sim.get_sensor_observations()
    assert set(renderer.last_modes.values()) == {"layer"}
    assert np.any(observation["rgba_camera_1stperson"][..., :3])
    sim.close()


def test_full_renders_shared_between_this_process_and_the_worker_match(checked, monkeypatch):
    splits = iter([8, 16, 40, 0, 24, 8, 32, 16])

    def next_split(self, remote, collected, busy_here, waited=0.0):  # any split: same frame
        for job in remote:
            job.state.split = next(splits, 8)

    monkeypatch.setattr(RenderScheduler, "_balance", next_split)
    monkeypatch.setattr(CheckedRenderer, "FULL_CHECK_EVERY", 1)
    sim = small_sim()
    renderer = sim.get_renderer()
    renderer.settings = RenderSettings(shade_band_pixels=64 * 8)  # bands of 8 rows
    agent = sim.get_agent(0)
    for k in range(8):
        state = agent.get_state()
        state.position = state.position + np.array([0.02, 0.0, -0.03 * k])  # cameras move
        agent.set_state(state)
        sim.get_sensor_observations()  # checked against the reference renderer
        assert renderer.last_modes[("rgba_camera_3rdperson",)] == "full"
    assert checked.places["shared"] >= 6
    sim.close()
