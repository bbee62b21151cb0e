"""engine.viewer without a browser: overlays against the physics they show, replays, live log.

Each overlay is checked by the law it draws (a resting box's contact impulses add up to its
weight times the step; a box turned 45 degrees has a sqrt(2) wider AABB; two touching sleeping
boxes share an island colour; a 1 m/s velocity command's target is 1 m away), and the viewer's
promise to cost nothing when nobody watches is checked by counting overlay queries.
"""

from __future__ import annotations

import json
import urllib.request
from pathlib import Path

import msgpack
import numpy as np
import pytest

import engine as habitat_sim
from engine import mn
from engine.physics import MotionType
from engine.viewer import OverlaySwitches, Replay, Viewer
from engine.viewer.overlays import (
    aabb_boxes,
    broad_phase_pairs,
    contact_normals,
    navmesh_mesh,
    path_segments,
)
from engine.viewer.server import LiveServer
from engine.viewer.settings import (
    CONTACT_LENGTH_PER_IMPULSE,
    CONTACT_MAX_LENGTH,
    CONTACT_MIN_LENGTH,
    VELOCITY_HORIZON,
)

FRAME_DT = 1.0 / 60.0
CUBE_HALF = 0.1  # m, the primitive cube templates have scale 0.1 (a 0.2 m cube)


def make_floor_sim(test_assets: Path) -> habitat_sim.Simulator:
    """A Y-up floor stage (Habitat's ``stage_floor1``) and one agent without sensors."""
    sim_cfg = habitat_sim.SimulatorConfiguration()
    sim_cfg.scene_id = str(test_assets / "scenes" / "stage_floor1.glb")
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    agent_cfg.sensor_specifications = []
    return habitat_sim.Simulator(habitat_sim.Configuration(sim_cfg, [agent_cfg]))


def add_cube(sim: habitat_sim.Simulator, position: list[float]):
    cube = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
    cube.translation = position
    return cube


def step(sim: habitat_sim.Simulator, seconds: float) -> None:
    for _ in range(round(seconds / FRAME_DT)):
        sim.step_physics(FRAME_DT)


@pytest.fixture
def floor_sim(test_assets: Path):
    with make_floor_sim(test_assets) as sim:
        yield sim


# -- what the viewer reads ----------------------------------------------------------------------
def test_parts_are_the_stage_and_each_object_named_by_its_handle(floor_sim):
    cube = add_cube(floor_sim, [0.0, 0.5, 0.0])
    viewer = Viewer(floor_sim)
    owners = {part.object_id for part in viewer.parts}
    assert owners == {0, cube.object_id}
    names = {mesh.name for mesh in viewer.drawing.meshes.values()}
    assert names == {"stage", cube.handle}
    # the cube's mesh is drawn where the cube is: its model matrix is its transformation
    key = next(p.key for p in viewer.parts if p.object_id == cube.object_id)
    np.testing.assert_allclose(
        viewer.drawing.meshes[key].model_matrix, np.asarray(cube.transformation), atol=1e-6
    )


# -- contacts -----------------------------------------------------------------------------------
def test_resting_cube_contact_impulses_add_up_to_its_weight_times_the_step(floor_sim):
    cube = add_cube(floor_sim, [0.0, 0.5, 0.0])
    step(floor_sim, 1.0)  # landed and settled (< 1 mm/s), still awake
    contacts = floor_sim.get_physics_contact_points()
    h = floor_sim.get_physics_time_step()
    segments, points = contact_normals(contacts, h)
    assert len(segments) == len(contacts) == 4
    lengths = np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1)
    assert np.all(lengths < CONTACT_MAX_LENGTH)  # none clipped, so the sum below is exact
    # length = min + k * impulse, so sum(length - min) / k is the total normal impulse, which
    # for a body at rest is its weight times the step; 1 % covers the solver's residual
    # (linear damping and the last iterations leave the sum 0.3 % under m g)
    total_impulse = np.sum(lengths - CONTACT_MIN_LENGTH) / CONTACT_LENGTH_PER_IMPULSE
    np.testing.assert_allclose(total_impulse, cube.mass * 9.8 * h, rtol=0.01)
    # drawn as the push the cube (B) receives, -contact_normal_on_b_in_ws: up, out of the
    # floor into the cube (the floor mesh's normals tilt by up to 8 degrees here)
    directions = (segments[:, 1] - segments[:, 0]) / lengths[:, None]
    normals_on_b = np.array([np.asarray(c.contact_normal_on_b_in_ws) for c in contacts])
    np.testing.assert_allclose(directions, -normals_on_b, atol=1e-5)  # float32 drawing
    assert np.all(directions[:, 1] > 0.98)
    # from the cube's bottom face: the 4 corners of its footprint, on average at its bottom
    # (within the 5 mm resting tolerance of the contact laws; the cube rests tilted 4 degrees)
    bottom = cube.translation[1] - CUBE_HALF
    np.testing.assert_allclose(points[:, 1].mean(), bottom, atol=5e-3)
    # the points are the corners of its bottom face: sqrt(3) half sizes from its centre
    distances = np.linalg.norm(points - np.asarray(cube.translation), axis=1)
    np.testing.assert_allclose(distances, np.sqrt(3) * CUBE_HALF, atol=5e-3)


def test_no_contacts_draw_nothing():
    segments, points = contact_normals([], 0.008)
    assert segments.shape == (0, 2, 3) and points.shape == (0, 3)


# -- AABBs and broad phase ----------------------------------------------------------------------
def test_aabb_of_a_cube_turned_45_degrees_is_sqrt2_wider(floor_sim):
    cube = add_cube(floor_sim, [1.0, 0.5, 0.0])
    cube.rotation = mn.Quaternion.rotation(mn.Deg(45.0), [0.0, 1.0, 0.0])
    lows, highs = aabb_boxes([cube])
    half = (highs - lows)[0] / 2.0
    # x and z half extents become the half diagonal of the 0.2 m square, y is unchanged
    np.testing.assert_allclose(half, [CUBE_HALF * np.sqrt(2), CUBE_HALF, CUBE_HALF * np.sqrt(2)])
    np.testing.assert_allclose((highs + lows)[0] / 2.0, [1.0, 0.5, 0.0], atol=1e-12)


def test_broad_phase_pairs_are_the_overlapping_boxes_only():
    lows = np.array([[0.0, 0, 0], [0.5, 0, 0], [3.0, 0, 0]])
    highs = lows + 1.0
    assert broad_phase_pairs(lows, highs).tolist() == [[0, 1]]  # box 2 is 2 m away
    assert broad_phase_pairs(lows[:1], highs[:1]).shape == (0, 2)


def test_aabb_overlay_draws_12_edges_per_object_and_one_pair_line(floor_sim):
    add_cube(floor_sim, [0.0, 0.5, 0.0])
    add_cube(floor_sim, [0.15, 0.5, 0.0])  # boxes overlap by 5 cm along x
    frame = Viewer(floor_sim, aabbs=True).frame
    assert frame is not None
    assert frame.segments["aabbs"].shape == (24, 2, 3)
    assert frame.segments["pairs"].shape == (1, 2, 3)


# -- sleeping islands ---------------------------------------------------------------------------
def test_sleeping_islands_share_a_colour_when_touching(floor_sim):
    bottom = add_cube(floor_sim, [0.0, 0.11, 0.0])
    top = add_cube(floor_sim, [0.0, 0.32, 0.0])  # stacked on the first
    alone = add_cube(floor_sim, [1.0, 0.11, 0.0])
    viewer = Viewer(floor_sim)
    assert viewer.frame is not None and viewer.frame.tints == {}  # all awake at first
    step(floor_sim, 3.0)
    assert not (bottom.awake or top.awake or alone.awake)
    tints = viewer.update().tints
    assert tints[bottom.object_id] == tints[top.object_id] != tints[alone.object_id]
    # a woken cube gets its own colours back (the floor does not tie it to the others)
    alone.awake = True
    assert alone.object_id not in viewer.update().tints


# -- velocity control ---------------------------------------------------------------------------
def test_velocity_target_is_where_the_command_leads_after_the_horizon(floor_sim):
    cube = add_cube(floor_sim, [0.0, 1.0, 0.0])
    cube.motion_type = MotionType.KINEMATIC
    control = cube.velocity_control
    control.controlling_lin_vel = True
    control.linear_velocity = [1.0, 0.0, 0.0]
    frame = Viewer(floor_sim).frame
    assert frame is not None
    segment = frame.segments["velocity"]
    np.testing.assert_allclose(segment[0, 0], [0.0, 1.0, 0.0], atol=1e-6)
    np.testing.assert_allclose(segment[0, 1], [VELOCITY_HORIZON, 1.0, 0.0], atol=1e-6)


# -- navmesh and path ---------------------------------------------------------------------------
def test_navmesh_overlay_covers_the_navigable_area_and_the_path_reaches_the_goal(demo_data):
    from engine.viewer.demo import make_tutorial_scene

    with make_tutorial_scene(str(demo_data)) as sim:  # the apartment's navmesh: 2 islands
        pathfinder = sim.pathfinder
        assert pathfinder.is_loaded and pathfinder.num_islands == 2
        vertices, faces, colors = navmesh_mesh(pathfinder)
        assert len(vertices) == len(colors) and faces.max() < len(vertices)
        assert len(np.unique(colors)) == 2  # one colour per island
        # the triangles cover the navigable cells exactly: their area seen from above (merged
        # rectangles may tilt by the centimetres their cells' heights differ) is the navmesh's
        a, b, c = (vertices[faces[:, k]].astype(np.float64) for k in range(3))
        area = np.abs(np.cross(b - a, c - a)[:, 1]).sum() / 2.0
        np.testing.assert_allclose(area, pathfinder.navigable_area, rtol=1e-6)
        pathfinder.seed(1)
        start = pathfinder.get_random_navigable_point(island_index=0)
        goal = pathfinder.get_random_navigable_point(island_index=0)
        segments = path_segments(pathfinder, start, goal)
        assert len(segments) >= 1
        # the polyline is connected and runs from the start to the goal (lifted 5 cm)
        np.testing.assert_allclose(segments[1:, 0], segments[:-1, 1])
        lift = np.array([0.0, 0.05, 0.0])
        np.testing.assert_allclose(segments[0, 0], pathfinder.snap_point(start) + lift, atol=1e-5)
        np.testing.assert_allclose(segments[-1, 1], pathfinder.snap_point(goal) + lift, atol=1e-5)
        viewer = Viewer(sim, navmesh=True, path=True, path_goal=goal)
        assert viewer.drawing.navmesh is not None
        assert viewer.frame is not None and len(viewer.frame.segments["path"]) >= 1


# -- a step that nobody watches -----------------------------------------------------------------
def test_unwatched_steps_run_no_overlay_query_and_match_watched_ones(test_assets, monkeypatch):
    calls = []
    original = habitat_sim.Simulator.get_physics_contact_points

    def counting(self):
        calls.append(self)
        return original(self)

    monkeypatch.setattr(habitat_sim.Simulator, "get_physics_contact_points", counting)
    with make_floor_sim(test_assets) as watched, make_floor_sim(test_assets) as unwatched:
        cube_w, cube_u = add_cube(watched, [0, 0.5, 0]), add_cube(unwatched, [0, 0.5, 0])
        step(unwatched, 0.5)
        assert calls == []  # no viewer: no overlay query at all
        assert "step_physics" not in vars(unwatched)
        viewer = Viewer(watched, follow=True)
        calls.clear()
        step(watched, 0.5)
        assert len(calls) == 30 and all(sim is watched for sim in calls)  # one per step call
        # watching does not change the physics: bit for bit the same poses
        assert np.array_equal(np.asarray(cube_w.transformation), np.asarray(cube_u.transformation))
        viewer.close()
        assert "step_physics" not in vars(watched)  # the class's method is back
        calls.clear()
        step(watched, 0.1)
        assert calls == []


# -- replays ------------------------------------------------------------------------------------
def test_replay_animates_the_falling_cube_and_writes_a_page_without_network(floor_sim, tmp_path):
    cube = add_cube(floor_sim, [0.0, 0.5, 0.0])
    viewer = Viewer(floor_sim)
    viewer.start_recording()
    for _ in range(30):
        floor_sim.step_physics(FRAME_DT)
        viewer.update()
    replay = viewer.replay()
    assert len(replay.frames) == 31 and replay.times()[0] == 0.0
    drawing = replay.drawing()
    key = next(p.key for p in replay.parts if p.object_id == cube.object_id)
    series = drawing.meshes[key].model_matrix
    assert isinstance(series, dict) and len(series) == 31
    heights = [float(np.asarray(m)[1, 3]) for m in series.values()]
    assert heights[0] == pytest.approx(0.5) and heights[-1] < 0.2  # it fell
    contacts = drawing.lines["contacts"].vertices
    assert isinstance(contacts, dict) and len(contacts) == 31
    path = replay.save(tmp_path / "replay.html")
    page = path.read_text(encoding="utf-8")
    assert "<script src" not in page  # every script inline: nothing to fetch
    assert "window.rigidsimShowFrame" in page and len(page) > 500_000  # k3d is inlined
    assert 'iframe srcdoc="' in replay._repr_html_()


def test_demo_replay_records_the_tutorial_cans_landing(demo_data, tmp_path):
    from engine.viewer.demo import record_tutorial_replay

    replay = record_tutorial_replay(seconds=1.0, data_path=str(demo_data))
    assert set(replay.names.values()) == {f"chefcan_:000{i}" for i in range(4)}
    counts = [frame.n_contacts for frame in replay.frames]
    assert counts[0] == 0 and max(counts) >= 4  # no contact in the air, then they land


def test_cli_writes_the_demo_replay(tmp_path, demo_data, monkeypatch):
    from engine.viewer import __main__ as cli
    from engine.viewer import demo

    monkeypatch.setattr(
        demo, "make_tutorial_scene", lambda data_path=None, f=demo.make_tutorial_scene: f(
            str(demo_data)
        ),
    )  # fmt: skip
    out = tmp_path / "replays" / "tutorial_replay.html"
    assert cli.main(["--demo-replay", str(out), "--seconds", "0.2"]) == 0
    assert out.is_file() and out.read_text(encoding="utf-8").startswith("<!doctype html>")


# -- live server --------------------------------------------------------------------------------
def test_live_server_binds_localhost_and_sends_only_what_changed(floor_sim):
    cube = add_cube(floor_sim, [0.0, 0.5, 0.0])
    with Viewer(floor_sim) as viewer:
        url = viewer.serve()
        assert url.startswith("http://127.0.0.1:")

        def changes(since: int) -> dict:
            with urllib.request.urlopen(f"{url}changes?since={since}", timeout=10) as answer:
                return msgpack.unpackb(answer.read())

        first = changes(0)
        names = {o["name"] for o in first["objects"].values()}
        assert {"stage", cube.handle, "contacts"} <= names
        with urllib.request.urlopen(f"{url}scene.json", timeout=10) as answer:
            scene = json.loads(answer.read())
        assert scene["version"] == first["version"]
        step(floor_sim, 0.1)
        viewer.update()
        second = changes(first["version"])
        assert second["version"] == first["version"] + 1
        name_of = {key: o["name"] for key, o in first["objects"].items()}
        changed = {name_of[key]: set(o) - {"id", "type"} for key, o in second["objects"].items()}
        assert changed[cube.handle] == {"model_matrix"}  # the cube moved, nothing else of it
        assert "stage" not in changed  # the stage's mesh went to the page once
        assert changes(second["version"])["objects"] == {}
    with pytest.raises(OSError):  # closed with the viewer: the port is free again
        urllib.request.urlopen(url, timeout=2)


# -- bad input ----------------------------------------------------------------------------------
def test_bad_input_raises_naming_the_value(floor_sim, tmp_path):
    with pytest.raises(TypeError, match="Simulator"):
        Viewer(object())
    with pytest.raises(TypeError, match="bogus"):
        Viewer(floor_sim, bogus=True)
    with pytest.raises(TypeError, match="contacts.*'yes'"):
        Viewer(floor_sim, contacts="yes")
    with pytest.raises(ValueError, match="path_goal"):
        OverlaySwitches(path_goal=[0.0, float("nan"), 0.0])
    with pytest.raises(ValueError, match="camera"):
        Viewer(floor_sim, camera=[0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="height.*'tall'"):
        Viewer(floor_sim, height="tall")
    viewer = Viewer(floor_sim)
    with pytest.raises(RuntimeError, match="start_recording"):
        viewer.replay()
    with pytest.raises(TypeError, match="bogus"):
        viewer.set_overlays(bogus=False)
    with pytest.raises(ValueError, match="port"):
        LiveServer(viewer.plot, port=-1)
    with pytest.raises(ValueError, match="host"):
        LiveServer(viewer.plot, host="")
    viewer.start_recording()
    with pytest.raises(ValueError, match="replay.txt"):
        viewer.replay().save(tmp_path / "replay.txt")
    with pytest.raises(ValueError, match="at least one frame"):
        Replay(viewer.parts, {}).to_html()


# -- objects added later, on the plot already on screen -----------------------------------------
def test_an_object_added_later_appears_in_the_same_plot_and_on_the_live_page(floor_sim):
    first = add_cube(floor_sim, [0.0, 0.5, 0.0])
    with Viewer(floor_sim) as viewer:
        plot, url = viewer.plot, viewer.serve()
        with urllib.request.urlopen(f"{url}changes?since=0", timeout=10) as answer:
            before = msgpack.unpackb(answer.read())
        second = add_cube(floor_sim, [0.5, 0.5, 0.0])
        viewer.update()  # notices the new object and reads the scene again
        assert viewer.plot is plot  # the widget a notebook shows stays the one drawn into
        assert {first.handle, second.handle} <= {o.name for o in plot.objects}
        with urllib.request.urlopen(f"{url}changes?since={before['version']}", timeout=10) as a:
            after = msgpack.unpackb(a.read())
        assert {o["name"] for o in after["objects"].values()} >= {second.handle, "stage"}
        assert set(after["removed"]) == {int(key) for key in before["objects"]}
        first_id, first_handle = first.object_id, first.handle
        floor_sim.get_rigid_object_manager().remove_object_by_id(first_id)
        viewer.update()  # notices the removal
        names = {o.name for o in viewer.plot.objects}
        assert second.handle in names and first_handle not in names
        assert first_id not in viewer.names


# -- an optional extra, outside the engine's import graph ---------------------------------------
ENGINE_DIR = Path(__file__).resolve().parents[2] / "engine"


def imported_modules(path: Path) -> set[str]:
    """Absolute module names a file imports (at any depth, inside functions too)."""
    import ast

    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module)
    return names


def test_the_engine_never_imports_the_viewer_and_the_viewer_has_no_cycle():
    import networkx as nx

    core = [p for p in ENGINE_DIR.rglob("*.py") if "viewer" not in p.relative_to(ENGINE_DIR).parts]
    assert len(core) > 50
    for path in core:
        bad = {m for m in imported_modules(path) if m.split(".")[0] in ("k3d", "msgpack")}
        bad |= {m for m in imported_modules(path) if m.startswith("engine.viewer")}
        assert not bad, f"{path.relative_to(ENGINE_DIR)} imports {bad}"
    graph = nx.DiGraph()
    for path in (ENGINE_DIR / "viewer").glob("*.py"):
        module = f"engine.viewer.{path.stem}".removesuffix(".__init__")
        for target in imported_modules(path):
            if target.startswith("engine.viewer."):
                graph.add_edge(module, target)
    assert graph.number_of_edges() >= 10
    assert nx.is_directed_acyclic_graph(graph), list(nx.simple_cycles(graph))


def test_import_engine_works_without_k3d_and_the_viewer_names_its_extra():
    import subprocess
    import sys

    script = (
        "import sys; sys.modules['k3d'] = None\n"  # None in sys.modules: import k3d fails
        "import engine, engine.simulator, engine.tutorial.cli\n"
        "assert 'engine.viewer' not in sys.modules\n"
        "try:\n    import engine.viewer\nexcept ImportError as error:\n"
        "    assert \"extra 'viewer'\" in str(error), error\nelse:\n    raise SystemExit(1)\n"
    )
    root = str(ENGINE_DIR.parent)
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=root, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr


def test_demo_replay_rejects_bad_arguments():
    from engine.viewer.demo import record_tutorial_replay

    with pytest.raises(ValueError, match="seconds.*-1"):
        record_tutorial_replay(seconds=-1.0)
    with pytest.raises(ValueError, match="every.*0"):
        record_tutorial_replay(seconds=1.0, every=0)


def test_default_camera_looks_at_the_objects_from_one_meter_in_front_of_the_agent(floor_sim):
    from engine.viewer.viewer import default_camera

    assert default_camera(floor_sim) is None  # nothing to look at: k3d fits the scene
    add_cube(floor_sim, [3.0, 0.5, 0.0])
    add_cube(floor_sim, [3.0, 0.5, 2.0])
    agent = floor_sim.agents[0]
    state = agent.get_state()
    state.position = [0.0, 0.0, 1.0]
    agent.set_state(state)
    camera = np.array(default_camera(floor_sim))
    eye, target, up = camera[:3], camera[3:6], camera[6:]
    np.testing.assert_allclose(target, [3.0, 0.5, 1.0])  # centre of the objects
    head = np.array([0.0, agent.agent_config.height, 1.0])
    np.testing.assert_allclose(eye, head + [1.0, 0.0, 0.0], atol=1e-12)  # 1 m towards them
    np.testing.assert_allclose(up, [0.0, 1.0, 0.0])
