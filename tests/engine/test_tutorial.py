"""End-to-end check of ``python -m engine.tutorial --fast``: physics outcomes and videos.

The job runs once per module (small frames, the tutorial's simulated durations) into a
temporary folder; the tests read its ``summary.json`` and videos. Scene facts used below
come from the demo apartment, which matches Habitat's ``apartment_1.glb``: floor at
y = -1.45 m, coffee table top at y = -1.05 m around (2.45, 0.1).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import imageio
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

FLOOR_Y = -1.45
TABLE_TOP_Y = -1.05
FRAME_DT = 1.0 / 60.0
FAST_RESOLUTION = (96, 128)
VIDEOS = {
    "basics": "sim_basics",
    "dynamic_control": "dynamic_control",
    "kinematic_interactions": "kinematic_interactions",
    "kinematic_update": "kinematic_update",
    "velocity_control": "velocity_control",
    "local_velocity_control": "local_velocity_control",
    "embodied_agent": "robot_control",
    "embodied_agent_navmesh_sliding": "robot_control_sliding",
    "embodied_agent_navmesh_no_sliding": "robot_control_no_sliding",
}
# Resting contact: docs/physics.md allows a 5 mm gap or sinking; the scene's surfaces are only
# known to about 5 mm, hence 1 cm.
REST_TOL = 0.01


@pytest.fixture(scope="module")
def job(tmp_path_factory: pytest.TempPathFactory) -> dict:
    out = tmp_path_factory.mktemp("tutorial_output")
    cmd = [sys.executable, "-m", "engine.tutorial", "--fast", "--quiet", "--seed", "0"]
    completed = subprocess.run(  # two worker processes (engine.tutorial.parallel)
        [*cmd, "--jobs", "2", "--output-dir", str(out)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert completed.returncode == 0, completed.stderr[-4000:]
    summary = json.loads((out / "summary.json").read_text())
    summary["by_name"] = {s["name"]: s for s in summary["sections"]}
    summary["stdout"] = completed.stdout
    summary["out"] = out
    return summary


#: the sections the simulation-only job runs: the first five (about a quarter of the job's
#: physics; the robot's three sections, which take most of it, are left out)
NO_VIDEO_SECTIONS = (
    "basics",
    "object_user_configurations",
    "dynamic_control",
    "kinematic_interactions",
    "kinematic_update",
)


@pytest.fixture(scope="module")
def job_without_video(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """The job's first five sections with ``--no-make-video`` (simulation only), same seed."""
    out = tmp_path_factory.mktemp("tutorial_no_video")
    cmd = [sys.executable, "-m", "engine.tutorial", "--fast", "--quiet", "--no-make-video"]
    cmd += ["--sections", ",".join(NO_VIDEO_SECTIONS), "--seed", "0"]
    completed = subprocess.run(
        [*cmd, "--output-dir", str(out)], capture_output=True, text=True, timeout=600
    )
    assert completed.returncode == 0, completed.stderr[-4000:]
    return {"summary": json.loads((out / "summary.json").read_text()), "out": out}


def outcomes(job: dict, name: str) -> dict:
    return job["by_name"][name]["outcomes"]


def quat_xyzw(values) -> Rotation:
    return Rotation.from_quat(np.asarray(values, dtype=np.float64))


def assert_same_rotation(actual_xyzw, expected: Rotation, atol: float) -> None:
    """Quaternions q and -q are the same rotation: compare the relative angle."""
    angle = (quat_xyzw(actual_xyzw) * expected.inv()).magnitude()
    assert angle < atol, f"rotation differs by {angle} rad"


# ------------------------------------------------------------------------------------------
# The job itself
# ------------------------------------------------------------------------------------------
def test_job_runs_every_section_in_order(job: dict) -> None:
    names = [s["name"] for s in job["sections"]]
    assert names == [
        "basics",
        "object_user_configurations",
        "dynamic_control",
        "kinematic_interactions",
        "kinematic_update",
        "velocity_control",
        "local_velocity_control",
        "embodied_agent",
        "embodied_agent_navmesh_sliding",
        "embodied_agent_navmesh_no_sliding",
    ]
    assert job["settings"]["resolution"] == list(FAST_RESOLUTION)
    # the summary table lists every section and the total
    for name in names:
        assert name in job["stdout"]
    assert "total" in job["stdout"]


def test_groups_ran_longest_first_each_section_once(job: dict) -> None:
    from engine.tutorial.cli import SECTION_NAMES
    from engine.tutorial.parallel import (
        SECTION_SECONDS,
        estimated_seconds,
        plan_groups,
        render_threads_per_worker,
    )

    groups = job["settings"]["groups"]  # in the order they were handed to the workers
    estimates = [group["estimated_seconds"] for group in groups]
    assert estimates == sorted(estimates, reverse=True) and len(groups) == 2
    assert sorted(name for g in groups for name in g["sections"]) == sorted(SECTION_NAMES)
    if not os.environ.get("RIGIDSIM_RENDER_THREADS"):  # 2 workers share the cores
        assert {group["render_threads"] for group in groups} == {render_threads_per_worker(2)}
    assert all(g["cpu_seconds"] > 0 and g["wall_seconds"] > 0 for g in groups)
    # a group's estimate: its sections recorded plus the replay of every section before
    replay = sum(SECTION_SECONDS[name][1] for name in SECTION_NAMES[:8])
    assert estimated_seconds([8]) == pytest.approx(replay + SECTION_SECONDS[SECTION_NAMES[8]][0])
    # selecting sections keeps only the groups that have some, still longest first
    assert plan_groups([0, 9]) == [[9], [0]]


@pytest.mark.parametrize("section", sorted(VIDEOS))
def test_video_has_one_frame_per_simulated_frame(job: dict, section: str) -> None:
    info = job["by_name"][section]
    path = Path(job["out"]) / f"{VIDEOS[section]}.mp4"
    assert info["video"] == str(path)
    assert path.is_file()
    with imageio.get_reader(path, "ffmpeg") as reader:
        n_frames = reader.count_frames()
        height_width = reader.get_data(0).shape[:2]
    assert n_frames == info["frames"]
    assert height_width == FAST_RESOLUTION
    # frames are step_physics(1/60) calls while world time < start + duration; world time
    # advances in whole fixed steps and lags the requested time by less than one step, so
    # the count is ceil(duration * 60) plus at most one frame per simulate() phase
    assert info["world_time"] * 60.0 == pytest.approx(info["frames"], abs=1.0)


def test_world_time_is_the_sum_of_the_sections(job: dict) -> None:
    expected = {"basics": 1.5, "dynamic_control": 3.0, "kinematic_interactions": 1.5}
    expected.update(kinematic_update=1.0, velocity_control=2.0, local_velocity_control=1.5)
    expected.update(embodied_agent=10.0)
    expected["embodied_agent_navmesh_sliding"] = expected["embodied_agent_navmesh_no_sliding"] = 6.0
    for name, seconds in expected.items():
        world_time = job["by_name"][name]["world_time"]
        # each simulate() loop stops at the first fixed step at or past its target: it may
        # overshoot by up to one frame (1/60 s) per phase (6 phases in embodied_agent)
        assert seconds <= world_time + 1e-9 < seconds + 6 * FRAME_DT, name


def test_no_make_video_simulates_the_same_world_bit_for_bit(job: dict, job_without_video: dict):
    # rendering must not touch the simulation, and a seeded run is deterministic
    sections = job_without_video["summary"]["sections"]
    assert [s["name"] for s in sections] == list(NO_VIDEO_SECTIONS)
    recorded = [job["by_name"][name] for name in NO_VIDEO_SECTIONS]
    assert [s["outcomes"] for s in sections] == [s["outcomes"] for s in recorded]
    assert [s["frames"] for s in sections] == [s["frames"] for s in recorded]
    assert all(s["video"] is None for s in sections)
    assert not list(Path(job_without_video["out"]).glob("*.mp4"))


def test_one_process_writes_the_same_videos_as_two(job: dict, tmp_path: Path) -> None:
    # --jobs 1 on two sections: one simulator runs the tutorial up to kinematic_update,
    # rendering only the two (the sections between them run without rendering); the job
    # above recorded every section of their group in one of its two workers
    cmd = [sys.executable, "-m", "engine.tutorial", "--fast", "--quiet", "--jobs", "1"]
    cmd += ["--sections", "basics,kinematic_update", "--output-dir", str(tmp_path)]
    completed = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert completed.returncode == 0, completed.stderr[-4000:]
    for name in ("sim_basics", "kinematic_update"):
        one = (tmp_path / f"{name}.mp4").read_bytes()
        assert one == (Path(job["out"]) / f"{name}.mp4").read_bytes(), name
    assert sorted(p.name for p in tmp_path.glob("*.mp4")) == [
        "kinematic_update.mp4",
        "sim_basics.mp4",
    ]


# ------------------------------------------------------------------------------------------
# Sections
# ------------------------------------------------------------------------------------------
def test_basics_sphere_comes_to_rest_on_the_coffee_table(job: dict) -> None:
    result = outcomes(job, "basics")
    sphere = result["sphere"]
    x, y, z = sphere["translation"]
    radius = sphere["half_extents"][1]
    # its lowest point touches the table top (y = -1.05)
    assert y - radius == pytest.approx(TABLE_TOP_Y, abs=REST_TOL)
    # dropped from (2.5, 0, 0.2): it lands on the table, no farther than the table's half size
    assert math.hypot(x - 2.5, z - 0.2) < 0.3
    # no vertical motion left after 1.5 s (it may still roll on the table top)
    assert abs(result["sphere_linear_velocity"][1]) < 0.01


def test_user_attributes_read_back_in_habitat_format(job: dict) -> None:
    strings = outcomes(job, "object_user_configurations")["user_attributes"]
    assert strings["obj_val_0"].startswith("This is a sphere object named sphere_:")
    assert strings["obj_val_1"] == "17"
    assert strings["obj_val_2"] == "False"
    assert strings["obj_val_3"] == "19.7"
    assert strings["obj_val_4"] == "[2.5 0 0.2]"
    assert strings["obj_val_5"] == "0.707107 [-0.707107 0 0]"


def test_anti_gravity_boxes_hover_until_the_sphere_arrives(job: dict) -> None:
    result = outcomes(job, "dynamic_control")
    tracks = np.asarray(result["box_tracks"])  # (frames, 5, 3)
    start = np.asarray(result["boxes_start"])
    # the sphere is thrown with v = 5 * (box - sphere): it needs about 0.2 s to arrive, so
    # for the first 0.1 s (6 frames) F = -m g holds every box in place (drift < 1 mm,
    # docs/physics.md's anti-gravity bound)
    np.testing.assert_allclose(tracks[:6], np.broadcast_to(start, (6, 5, 3)), atol=1e-3)
    # nothing ends up under the floor
    assert np.all(tracks[:, :, 1] > FLOOR_Y)


def test_boxes_the_sphere_misses_hover_and_spin_for_the_whole_run(job: dict) -> None:
    result = outcomes(job, "dynamic_control")
    tracks = np.asarray(result["box_tracks"])
    start = np.asarray(result["boxes_start"])
    drift = np.max(np.linalg.norm(tracks - start, axis=2), axis=0)  # (5,) max over frames
    hovering = np.flatnonzero(drift < 1e-3)  # docs/physics.md: < 1 mm in 3 s
    # the sphere hits the top box and scatters the column; the two side boxes stay clear
    assert len(hovering) >= 2, f"max drift per box: {drift}"
    spins = np.asarray(result["boxes_angular_velocity"])[hovering]
    # the torque (0, 0.01, 0) N m spins them about +y only
    assert np.all(spins[:, 1] > 0.1)
    np.testing.assert_allclose(spins[:, [0, 2]], 0.0, atol=1e-6)


def cylinder_y_range(can: dict) -> tuple[float, float]:
    """Lowest and highest world y of the can, a cylinder, at its pose.

    The cylinder's axis is the local axis whose AABB half size differs from the other two
    (the YCB can is modelled Z-up, so it lies on its side). With that axis a = R e_k (unit,
    world frame), radius r and half height h about the center c, the extreme points are at
    c_y -+ (h |a_y| + r sqrt(1 - a_y^2)).
    """
    half = np.asarray(can["half_extents"])
    k = int(np.argmax(np.abs(half - np.median(half))))
    h, r = half[k], float(np.median(half))
    a_y = quat_xyzw(can["rotation"]).apply(np.eye(3)[k])[1]
    reach = h * abs(a_y) + r * math.sqrt(max(1.0 - a_y**2, 0.0))
    return can["translation"][1] - reach, can["translation"][1] + reach


def test_kinematic_can_holds_still_and_catches_the_can_dropped_on_it(job: dict) -> None:
    result = outcomes(job, "kinematic_interactions")
    kinematic = result["kinematic_can"]
    np.testing.assert_allclose(kinematic["translation"], [2.4, -0.64, 0.0])
    np.testing.assert_allclose(kinematic["rotation"], [0, 0, 0, 1], atol=1e-12)
    kinematic_top_y = cylinder_y_range(kinematic)[1]
    side_a, side_b, on_top = result["dynamic_cans"]
    # the can dropped from (2.4, -0.3, 0) rests on top of the kinematic can
    assert cylinder_y_range(on_top)[0] == pytest.approx(kinematic_top_y, abs=REST_TOL)
    # the two cans beside it come to rest on the coffee table or, rolling off, on the floor
    for can in (side_a, side_b):
        bottom_y = cylinder_y_range(can)[0]
        assert min(abs(bottom_y - TABLE_TOP_Y), abs(bottom_y - FLOOR_Y)) < REST_TOL, bottom_y


def test_kinematic_update_follows_the_manual_state_updates(job: dict) -> None:
    result = outcomes(job, "kinematic_update")
    n = result["steps"]
    start = np.asarray(result["clamp_start"]["translation"])
    # translation += (0, 0, 0.01) before each of the n steps (float64 sums: 1e-9)
    np.testing.assert_allclose(result["clamp"]["translation"], start + [0, 0, 0.01 * n], atol=1e-9)
    # rotation = R(0.05 rad about -x) * rotation, n times
    start_rotation = quat_xyzw(result["clamp_start"]["rotation"])
    expected = Rotation.from_rotvec([-0.05 * n, 0, 0]) * start_rotation
    assert_same_rotation(result["clamp"]["rotation"], expected, atol=1e-9)


def replay_velocity_control(start: dict, steps: list[tuple[int, np.ndarray, np.ndarray, bool]]):
    """Explicit Euler of VelocityControl.integrate_transform (docs/habitat_api.md), once per
    step_physics(1/60) call. ``steps``: (n, linear, angular, is_local) phases."""
    t = np.asarray(start["translation"], dtype=np.float64)
    q = quat_xyzw(start["rotation"])
    for n, linear, angular, is_local in steps:
        for _ in range(n):
            v = q.apply(linear) if is_local else linear
            w = q.apply(angular) if is_local else angular
            t = t + v * FRAME_DT
            q = Rotation.from_rotvec(w * FRAME_DT) * q
    return t, q


def test_velocity_control_moves_the_clamp_as_commanded(job: dict) -> None:
    result = outcomes(job, "velocity_control")
    n_forward, n_back = result["steps"]
    omega = np.array([4.0, 0.0, 0.0])
    phases = [(n_forward, np.array([0, 0, -1.0]), omega, False)]
    phases.append((n_back, np.array([0, 0, 1.0]), omega, False))
    t, q = replay_velocity_control(result["clamp_start"], phases)
    # same formulas, different operation order: agreement to float64 round-off over 120 steps
    np.testing.assert_allclose(result["clamp"]["translation"], t, atol=1e-9)
    assert_same_rotation(result["clamp"]["rotation"], q, atol=1e-9)


def test_local_velocity_control_moves_the_clamp_in_its_own_frame(job: dict) -> None:
    result = outcomes(job, "local_velocity_control")
    phases = [(result["steps"], np.array([0, 0, 2.3]), np.array([-4.3, 0, 0]), True)]
    t, q = replay_velocity_control(result["clamp_start"], phases)
    np.testing.assert_allclose(result["clamp"]["translation"], t, atol=1e-9)
    assert_same_rotation(result["clamp"]["rotation"], q, atol=1e-9)


def test_embodied_robot_settles_upright_on_the_floor(job: dict) -> None:
    result = outcomes(job, "embodied_agent")
    for state in (result["settled"], result["robot"]):
        assert state["y_extent"][0] == pytest.approx(FLOOR_Y, abs=REST_TOL)
        up = quat_xyzw(state["rotation"]).apply([0.0, 1.0, 0.0])
        assert up[1] > math.cos(math.radians(5.0))  # upright within 5 degrees
    # it drove away from where it landed
    moved = np.subtract(result["robot"]["translation"], result["settled"]["translation"])
    assert np.hypot(moved[0], moved[2]) > 0.5


def test_embodied_robot_carries_the_agent_and_leaves_it_when_removed(job: dict) -> None:
    result = outcomes(job, "embodied_agent")
    # the agent's scene node is the robot's root node: they share the translation
    np.testing.assert_allclose(result["agent_position"], result["robot"]["translation"], atol=1e-9)
    assert result["robot_is_alive_after_removal"] is False
    np.testing.assert_allclose(result["agent_position_after_removal"], result["agent_position"])


@pytest.mark.parametrize("sliding", ["sliding", "no_sliding"])
def test_navmesh_robot_stays_on_the_navmesh(job: dict, sliding: str) -> None:
    result = outcomes(job, f"embodied_agent_navmesh_{sliding}")
    assert result["navmesh_loaded"]
    assert all(result["end_on_navmesh"])
    start, target, end = (np.asarray(result[k]) for k in ("step_start", "step_target", "step_end"))
    collided = np.asarray(result["collided"])
    # a step the navmesh left alone goes where the controller asked (flat floor: same x, z)
    # and is not reported as a collision
    reached = np.linalg.norm((end - target)[:, [0, 2]], axis=1) < 1e-6
    assert not np.any(collided[reached])
    # the demo scene keeps the floor within 1 m of the start clear but for the table: the
    # first 20 steps (1/3 m) are free
    assert np.all(reached[:20])
    # the filter never ends farther from the target than the start is (the start is always
    # reachable); navmesh points are float32-rounded, 1e-5 m covers that a few m from 0
    to_target_after = np.linalg.norm((target - end)[:, [0, 2]], axis=1)
    to_target_before = np.linalg.norm((target - start)[:, [0, 2]], axis=1)
    assert np.all(to_target_after <= to_target_before + 1e-5)
    if sliding == "no_sliding":
        # stopping on the segment: at most the commanded |v| dt = 1/60 m
        step_length = np.linalg.norm((end - start)[:, [0, 2]], axis=1)
        assert np.all(step_length <= FRAME_DT + 1e-5), step_length.max() - FRAME_DT


def test_navmesh_without_sliding_stops_along_the_commanded_direction(job: dict) -> None:
    result = outcomes(job, "embodied_agent_navmesh_no_sliding")
    start, target, end = (np.asarray(result[k]) for k in ("step_start", "step_target", "step_end"))
    hit = np.asarray(result["collided"])
    assert np.any(hit), "the 6 s drive should reach a wall"
    moved, wanted = (end - start)[:, [0, 2]], (target - start)[:, [0, 2]]
    moved_length = np.linalg.norm(moved, axis=1)
    # a blocked step either stays put or keeps the commanded direction (within 1 degree)
    going = hit & (moved_length > 1e-6)
    cosine = np.sum(moved[going] * wanted[going], axis=1)
    cosine /= moved_length[going] * np.linalg.norm(wanted[going], axis=1)
    assert np.all(cosine > math.cos(math.radians(1.0)))


def test_navmesh_with_sliding_slides_along_walls(job: dict) -> None:
    result = outcomes(job, "embodied_agent_navmesh_sliding")
    start, target, end = (np.asarray(result[k]) for k in ("step_start", "step_target", "step_end"))
    hit = np.asarray(result["collided"])
    assert np.any(hit), "the 6 s drive should reach a wall"
    moved, wanted = (end - start)[:, [0, 2]], (target - start)[:, [0, 2]]
    cross = moved[:, 0] * wanted[:, 1] - moved[:, 1] * wanted[:, 0]
    # sliding turns some blocked steps away from the commanded direction
    assert np.any(np.abs(cross[hit]) > 1e-6)
