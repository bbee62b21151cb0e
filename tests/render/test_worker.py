"""A render worker process gives the bits of an in-process render: every mode (full, new
layer, layer), pinhole and orthographic views at once, scenes mixing every material kind
and light setup, the render settings of each job; its errors and its death reach the caller."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from render import frame, shade
from render.camera import Camera
from render.frame import RenderScene, render_frame
from render.settings import RenderSettings
from render.worker import LayeredView, RenderProcess, SplitScene, WorkerJob, WorkerLost

RNG_SEED = 21


def _mixed_scene(rng: np.random.Generator):
    """``test_shade``'s scene of every material kind (tests import in importlib mode)."""
    spec = importlib.util.spec_from_file_location(
        "_shade_cases", Path(__file__).parent / "test_shade.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module._mixed_scene(rng)  # noqa: SLF001


def split_meshes():
    """The mixed scene: floor and wall static, the rest moving; two moving meshes share a
    light setup object, one names the default setup explicitly."""
    meshes = _mixed_scene(np.random.default_rng(RNG_SEED))
    shared = shade.Lights([[0.0, 1.0, 0.3, 0.0], [2.0, 1.0, -2.0, 1.0]], [0.6, 0.3], ("world",) * 2)
    meshes[2].lights = meshes[4].lights = shared
    meshes[5].lights = shade.DEFAULT_LIGHTS
    meshes[6].lights = shade.Lights([[0.0, 0.0, 1.0, 0.0]], [0.5], ("camera",))
    return meshes[:2], meshes[2:]


def views():
    """Two views rendered in one submit: a pinhole and an orthographic camera."""
    pose = np.eye(4)
    pose[:3, 3] = [0.0, 0.3, 0.5]
    pinhole = Camera((90, 120), hfov=80.0)
    ortho = Camera((60, 80), subtype="orthographic", ortho_scale=0.4)
    return [(1, pinhole, pose), (2, ortho, pose)]


def frame_bytes(frame) -> tuple[bytes, bytes, bytes]:
    return frame.rgba.tobytes(), frame.depth.tobytes(), frame.ids.tobytes()


@pytest.fixture(scope="module")
def worker():
    process = RenderProcess()
    yield process
    process.close()


def test_worker_frames_equal_in_process_frames_in_every_mode(worker):
    static, moving = split_meshes()
    local_scene = SplitScene()
    local_scene.set_meshes(static, moving)
    local_views = {key: LayeredView() for key, _, _ in views()}
    worker.set_meshes(static, moving)
    rng = np.random.default_rng(3)
    moving_poses = np.array([m.world_from_mesh for m in moving])
    static_poses = np.array([m.world_from_mesh for m in static])
    for mode in ("full", "new layer", "layer", "layer", "full", "new layer", "layer"):
        moving_poses[:, :3, 3] += rng.normal(0.0, 0.05, (len(moving), 3))  # objects move
        local_scene.set_poses(static_poses, moving_poses)
        worker.submit(static_poses, moving_poses, [WorkerJob(k, mode, c, p) for k, c, p in views()])
        remote = worker.collect()
        for key, camera, pose in views():
            local = local_views[key].render(mode, local_scene, camera, pose)
            assert frame_bytes(remote[key]) == frame_bytes(local), (mode, key)
            everything = RenderScene(local_scene.static.meshes + local_scene.moving.meshes)
            everything.world_from_mesh[:] = np.concatenate([static_poses, moving_poses])
            full = render_frame(everything, camera, pose, cull_back_faces=True)
            assert frame_bytes(remote[key]) == frame_bytes(full), (mode, key)
    assert len(np.unique(remote[1].ids)) >= 6  # every kind of mesh is on screen


def test_the_worker_follows_each_jobs_settings_and_mesh_changes(worker):
    static, moving = split_meshes()
    worker.set_meshes(static, moving)
    static_poses = np.array([m.world_from_mesh for m in static])
    moving_poses = np.array([m.world_from_mesh for m in moving])
    key, camera, pose = views()[0]

    def both(settings: RenderSettings, rows=None) -> tuple:
        job = WorkerJob(key, "full", camera, pose, rows, settings=settings)
        worker.submit(static_poses, moving_poses, [job])
        remote = frame_bytes(worker.collect()[key])
        scene = SplitScene()
        scene.set_meshes(static, moving)
        scene.set_poses(static_poses, moving_poses)
        view = LayeredView()
        return remote, frame_bytes(view.render("full", scene, camera, pose, settings=settings))

    default_remote, default_local = both(RenderSettings())
    assert default_remote == default_local
    plain = RenderSettings.plain(shade_band_pixels=1200, triangle_batch=7, fragment_chunk=50)
    plain_remote, plain_local = both(plain, rows=(10, 90))  # rows of 10-row bands: valid
    assert plain_remote == plain_local
    with pytest.raises(ValueError, match="multiple of 136 rows"):  # the default bands
        both(RenderSettings(), rows=(10, 90))
    moving = moving[:2]  # objects removed: only the moving part is sent again
    moving_poses = moving_poses[:2]
    worker.set_meshes(None, moving)
    fewer_remote, fewer_local = both(plain)
    assert fewer_remote == fewer_local
    assert fewer_remote[2] != plain_remote[2]


def test_errors_come_back_to_the_caller_and_a_dead_worker_is_reported():
    static, moving = split_meshes()
    process = RenderProcess()
    try:
        process.set_meshes(static, moving)
        static_poses = np.array([m.world_from_mesh for m in static])
        moving_poses = np.array([m.world_from_mesh for m in moving])
        key, camera, pose = views()[0]
        process.submit(static_poses, moving_poses, [WorkerJob(key, "layer", camera, pose)])
        with pytest.raises(ValueError, match="needs a static layer"):
            process.collect()
        process.submit(static_poses, moving_poses, [WorkerJob(key, "full", camera, pose)])
        assert process.collect()[key].depth.max() > 0  # still serving
        process._process.kill()  # noqa: SLF001 - simulate a crash
        process._process.wait()  # noqa: SLF001
        with pytest.raises(WorkerLost):
            process.submit(static_poses, moving_poses, [WorkerJob(key, "full", camera, pose)])
            process.collect()
        assert not process.alive
    finally:
        process.close()
    process.close()  # twice is fine


def test_rows_of_full_renders_here_and_in_the_worker_compose_the_whole_frame(worker):
    settings = RenderSettings(shade_band_pixels=1200)  # bands of 10 rows (the worker's too)
    static, moving = split_meshes()
    scene = SplitScene()
    scene.set_meshes(static, moving)
    static_poses = np.array([m.world_from_mesh for m in static])
    moving_poses = np.array([m.world_from_mesh for m in moving])
    scene.set_poses(static_poses, moving_poses)
    worker.set_meshes(static, moving)
    key, camera, pose = views()[0]
    whole = frame_bytes(render_frame(scene.full(), camera, pose, cull_back_faces=True))
    step = frame.band_rows(camera, settings)
    assert step == 10
    for split in (step, 5 * step, camera.height):
        job = WorkerJob(key, "full", camera, pose, (split, 90), settings=settings)
        worker.submit(static_poses, moving_poses, [job])
        there = worker.collect()[key]
        view = LayeredView()
        here = view.render("full", scene, camera, pose, rows=(0, split), settings=settings)
        names = ("rgba", "depth", "ids")
        parts = [
            np.concatenate([getattr(here, n)[:split], getattr(there, n)[split:]]) for n in names
        ]
        assert tuple(part.tobytes() for part in parts) == whole, split
        if split < camera.height:  # each part rasterizes only its rows: the work is divided
            full_fragments = render_frame(scene.full(), camera, pose, cull_back_faces=True)
            assert here.n_fragments + there.n_fragments == full_fragments.n_fragments
            assert 0 < here.n_fragments < full_fragments.n_fragments
    with pytest.raises(ValueError, match="multiple of"):
        render_frame(scene.full(), camera, pose, rows=(1, 90), settings=settings)
    with pytest.raises(ValueError, match="rows are for full renders"):
        LayeredView().render("new layer", scene, camera, pose, rows=(0, step))


def test_jobs_are_checked_before_anything_is_sent(worker):
    key, camera, pose = views()[0]
    with pytest.raises(TypeError, match="WorkerJob.settings must be RenderSettings"):
        WorkerJob(key, "full", camera, pose, settings={"fast_shading": False})
    static, moving = split_meshes()
    worker.set_meshes(static, moving)
    static_poses = np.array([m.world_from_mesh for m in static])
    moving_poses = np.array([m.world_from_mesh for m in moving])
    with pytest.raises(TypeError, match="takes WorkerJob items"):
        worker.submit(static_poses, moving_poses, [(key, "full", camera, pose)])
    worker.submit(static_poses, moving_poses, [WorkerJob(key, "full", camera, pose)])
    assert worker.collect()[key].depth.max() > 0  # nothing was pending: still in step
