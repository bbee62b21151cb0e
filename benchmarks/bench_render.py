"""Benchmark ``render.render_frame`` (color + depth + ids at 544 x 720) against pybullet.

Run on demand (not a test)::

    .venv/bin/python benchmarks/bench_render.py          # full run
    .venv/bin/python benchmarks/bench_render.py --quick  # fewer repeats, smaller scenes

Scenes: spheres of about 1k, 10k and 100k triangles (unlit vertex colors and lit), a
full-screen close-up of a textured plane with 5 lit boxes, and the demo apartment from the
tutorial's 1st- and 3rd-person camera poses (TinyRenderer gets the same triangles with flat
material colors: it does not sample our textures). When ``import pybullet`` works,
pybullet's TinyRenderer (``p.getCameraImage(..., renderer=p.ER_TINY_RENDERER)``) renders the
same triangles from the same camera in the same run; the table prints both medians and the
ratio, plus where our time goes (per-stage medians from ``FrameBuffers.timings``) and a
cross-check of the two depth images. Compare ratios, not absolute times across runs.

Another table times a static camera over the apartment with 5 lit boxes moving in view (the
tutorial's onlooker sections): a full ``render_frame`` of everything against
``render_over_layer`` (only the boxes, over a kept ``StaticLayer`` of the apartment),
checks that the two frames are bit-identical and prints the speed-up.

The last table (``--async-only`` runs it alone) times a simulator frame of the tutorial's
two cameras with 30 cubes dropping: physics then observations, against
``start_async_render_and_step_physics`` (the render worker process renders while this one
steps the physics), and prints how much of the shorter task the overlap hides.

``--baseline PATH`` compares this checkout with another rigidsim checkout instead (issue 24's
"within 3 % of the baseline" bound): every scene above plus a simulator frame (the tutorial's
two cameras over 30 cubes, ``get_sensor_observations`` after a physics step: the engine's
render scheduler) is timed by this file's code in a subprocess per checkout, run in that
checkout's folder so ``render`` and ``engine`` resolve there; the two checkouts alternate
scene by scene for ``--rounds`` rounds, and the table prints the CPU ms of each checkout's
fastest frame (wall ms for the simulator frame: the least disturbed by other processes on a
shared machine) and the ratio this / baseline.

``bench_scene(meshes, camera, world_from_camera, repeats)`` is importable, so other scenes
(e.g. the demo apartment) can be measured the same way; the scenes themselves are built by
``render_scenes.py``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from render_scenes import (
    apartment_scenes,
    look_at,
    moving_boxes,
    plane_and_boxes_scene,
    sphere_scene,
)

from render import (
    Camera,
    RenderMesh,
    RenderScene,
    StaticLayer,
    render_frame,
    render_over_layer,
)

RESOLUTION = (544, 720)
PYBULLET_CHUNK_FACES = 4000
ROOT = Path(__file__).resolve().parents[1]
#: the scenes ``--baseline`` times, by name (:func:`named_scene_cpu_ms`)
BASELINE_SCENES = (
    "sphere 1k",
    "sphere 10k",
    "sphere 100k",
    "sphere 10k, cull back faces",
    "plane + 5 boxes, full screen",
    "apartment, 1st person",
    "apartment, 3rd person",
    "static layer, 3rd person",
    "simulator frame, 2 cameras",
)


def bench_scene(
    meshes: list[RenderMesh] | RenderScene,
    camera: Camera,
    world_from_camera: np.ndarray,
    repeats: int = 10,
    cull_back_faces: bool = False,
) -> dict:
    """Time ``render_frame`` on a cached ``RenderScene`` with reused buffers.

    Returns a dict: ``ms`` (median wall time), ``cpu_ms`` (median process CPU time: steadier
    on a shared machine), ``cpu_best_ms`` (the fastest frame's CPU time: the least disturbed
    by other processes), ``stages`` (median wall ms per stage), ``fragments``,
    ``covered`` (pixels drawn), ``frame`` (the last FrameBuffers).
    """
    scene = meshes if isinstance(meshes, RenderScene) else RenderScene(meshes)
    frame = render_frame(scene, camera, world_from_camera)  # warm-up, allocates buffers
    totals, cpu, stages = [], [], {}
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        frame = render_frame(scene, camera, world_from_camera, frame, cull_back_faces)
        totals.append((time.perf_counter() - start) * 1e3)
        cpu.append((time.process_time() - start_cpu) * 1e3)
        for name, ms in frame.timings.items():
            stages.setdefault(name, []).append(ms)
    return {
        "ms": statistics.median(totals),
        "cpu_ms": statistics.median(cpu),
        "cpu_best_ms": min(cpu),
        "stages": {name: statistics.median(v) for name, v in stages.items()},
        "fragments": frame.n_fragments,
        "covered": int(np.count_nonzero(frame.depth)),
        "frame": frame,
    }


# --- pybullet TinyRenderer on the same triangles --------------------------------------------


def pybullet_renderer(meshes: list[RenderMesh], camera: Camera, world_from_camera: np.ndarray):
    """A zero-argument function rendering the meshes with TinyRenderer, or None."""
    try:
        import pybullet as p
    except ImportError:
        return None
    client = p.connect(p.DIRECT)
    for mesh in meshes:
        vertices = mesh.vertices @ mesh.world_from_mesh[:3, :3].T + mesh.world_from_mesh[:3, 3]
        color = (np.asarray(mesh.base_color) / 255.0).tolist()
        # pybullet limits the size of one visual shape: split big meshes into chunks
        for start in range(0, len(mesh.faces), PYBULLET_CHUNK_FACES):
            faces = mesh.faces[start : start + PYBULLET_CHUNK_FACES]
            used, local_faces = np.unique(faces, return_inverse=True)
            shape = p.createVisualShape(
                p.GEOM_MESH,
                vertices=vertices[used].tolist(),
                indices=local_faces.ravel().tolist(),
                rgbaColor=color,
                physicsClientId=client,
            )
            p.createMultiBody(  # a static btRigidBody, as every benchmark body is
                baseVisualShapeIndex=shape, useMaximalCoordinates=True, physicsClientId=client
            )
    height, width = camera.resolution
    view = np.linalg.inv(world_from_camera).T.ravel().tolist()  # column-major camera_from_world
    vfov = math.degrees(2 * math.atan(math.tan(math.radians(camera.hfov) / 2) * height / width))
    projection = p.computeProjectionMatrixFOV(vfov, width / height, camera.near, camera.far)

    def render() -> np.ndarray:
        _, _, _, depth_buffer, _ = p.getCameraImage(
            width, height, view, projection, renderer=p.ER_TINY_RENDERER, physicsClientId=client
        )
        buffer = np.reshape(depth_buffer, (height, width))
        n, f = camera.near, camera.far
        z = f * n / (f - (f - n) * buffer)  # OpenGL depth buffer -> z-depth
        return np.where(buffer < 1.0, z, 0.0)

    return render


def time_calls(function, repeats: int) -> tuple[float, object]:
    """Median wall time (ms) of ``function()`` and its last result."""
    result, times = function(), []
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times), result


def bench_static_layer(
    static: list[RenderMesh], camera: Camera, pose: np.ndarray, repeats: int
) -> dict:
    """Full renders of static + moving meshes against moving meshes over a static layer.

    Both paths reuse their buffers and render the same sequence of box poses; every frame
    is compared bit for bit. Returns medians (ms), the speed-up and the fastest layer
    frame's CPU ms (``layer_cpu_best_ms``).
    """
    frames = moving_boxes(repeats + 1)
    full_scene = RenderScene(static + frames[0])
    moving_scene = RenderScene(frames[0])
    n_static = len(static)
    layer = StaticLayer.from_frame(render_frame(static, camera, pose, cull_back_faces=True))
    full_ms, layer_ms, layer_cpu, full, over = [], [], [], None, None
    for meshes in frames:
        for i, mesh in enumerate(meshes):
            full_scene.set_world_from_mesh(n_static + i, mesh.world_from_mesh)
            moving_scene.set_world_from_mesh(i, mesh.world_from_mesh)
        start = time.perf_counter()
        full = render_frame(full_scene, camera, pose, full, cull_back_faces=True)
        full_ms.append((time.perf_counter() - start) * 1e3)
        start, start_cpu = time.perf_counter(), time.process_time()
        over = render_over_layer(layer, moving_scene, camera, pose, over, cull_back_faces=True)
        layer_ms.append((time.perf_counter() - start) * 1e3)
        layer_cpu.append((time.process_time() - start_cpu) * 1e3)
        for name in ("rgba", "depth", "ids"):
            if getattr(full, name).tobytes() != getattr(over, name).tobytes():
                raise AssertionError(f"static layer frame differs from the full render ({name})")
    full_median, layer_median = statistics.median(full_ms[1:]), statistics.median(layer_ms[1:])
    return {
        "full_ms": full_median,
        "layer_ms": layer_median,
        "speedup": full_median / layer_median,
        "layer_cpu_best_ms": min(layer_cpu[1:]),
        "moving_pixels": int(np.count_nonzero(over.ids >= 10)),
        "frame": over,
    }


def async_simulator(n_boxes: int):
    """The tutorial's simulator (two cameras over the apartment) with ``n_boxes`` cubes
    dropping in view, so that a frame has both physics and rendering to do."""
    from engine.demo import demo_data_path
    from engine.tutorial.scene_setup import make_configuration, place_agent

    sim = __import__("engine").Simulator(make_configuration(str(demo_data_path())))
    place_agent(sim)
    objects = sim.get_rigid_object_manager()
    eye = np.asarray(sim.agents[0].get_state().position)
    for k in range(n_boxes):
        cube = objects.add_object_by_template_handle("cubeSolid")
        cube.translation = eye + [0.3 * (k % 5) - 0.6, 1.0 + 0.25 * (k // 5), -1.5]
    return sim


def bench_async(n_frames: int, n_boxes: int = 30, dt: float = 1.0 / 60.0) -> dict:
    """Frame time of ``step_physics(dt)`` then ``get_sensor_observations()`` (sequential)
    against ``start_async_render_and_step_physics(dt)`` then
    ``get_sensor_observations_async_finish()`` (the render worker renders while the physics
    steps). Also physics alone and rendering alone, on the same scene and frames."""
    times: dict[str, list[float]] = {"physics": [], "render": [], "sequential": [], "async": []}
    for mode in times:
        sim = async_simulator(n_boxes)
        sim.get_sensor_observations()  # warm up: meshes, worker, layers
        for _ in range(n_frames):
            start = time.perf_counter()
            if mode == "physics":
                sim.step_physics(dt)
            elif mode == "render":
                sim.get_sensor_observations()
            elif mode == "sequential":
                sim.step_physics(dt)
                sim.get_sensor_observations()
            else:
                sim.start_async_render_and_step_physics(dt)
                sim.get_sensor_observations_async_finish()
            times[mode].append(1e3 * (time.perf_counter() - start))
        sim.close()
    medians = {mode: statistics.median(values) for mode, values in times.items()}
    hidden = medians["sequential"] - medians["async"]
    medians["overlap"] = hidden / max(1e-9, min(medians["physics"], medians["render"]))
    return medians


def simulator_frame_ms(repeats: int, n_boxes: int = 30, dt: float = 1.0 / 60.0) -> float:
    """Fastest wall ms of ``get_sensor_observations()`` (both tutorial cameras) after an
    untimed ``step_physics(dt)``, with ``n_boxes`` cubes dropping in view (wall time: the
    scheduler may render a camera in its worker process, whose CPU time is not ours)."""
    sim = async_simulator(n_boxes)
    sim.get_sensor_observations()  # warm up: meshes, worker, layers
    times = []
    for _ in range(repeats):
        sim.step_physics(dt)
        start = time.perf_counter()
        sim.get_sensor_observations()
        times.append(1e3 * (time.perf_counter() - start))
    sim.close()
    return min(times)


def named_scene_cpu_ms(name: str, repeats: int) -> float:
    """CPU ms of the fastest of ``repeats`` frames of one of :data:`BASELINE_SCENES` (the
    render tables' scenes at :data:`RESOLUTION`, hfov 90, the same poses; the static layer:
    ``render_over_layer`` of the 5 boxes; the simulator frame: wall ms)."""
    if name == "simulator frame, 2 cameras":
        return simulator_frame_ms(repeats)
    camera = Camera(RESOLUTION, hfov=90.0)
    if name.startswith("sphere"):
        n = int(name.split()[1].rstrip("k,")) * 1000
        pose = look_at((0, 0.5, 3.0), (0, 0, 0))
        return bench_scene(sphere_scene(n), camera, pose, repeats, "cull" in name)["cpu_best_ms"]
    if name.startswith("plane"):
        pose = look_at((0, 1.0, 0.8), (0, 0, -1.5))
        return bench_scene(plane_and_boxes_scene(), camera, pose, repeats)["cpu_best_ms"]
    scenes = {label: (meshes, pose) for label, meshes, pose, _ in apartment_scenes()}
    if name.startswith("static layer"):
        meshes, pose = scenes["apartment, 3rd person"]
        return bench_static_layer(meshes, camera, pose, repeats)["layer_cpu_best_ms"]
    meshes, pose = scenes[name]
    return bench_scene(meshes, camera, pose, repeats, cull_back_faces=True)["cpu_best_ms"]


def checkout_cpu_ms(checkout: Path, name: str, repeats: int) -> float:
    """:func:`named_scene_cpu_ms` run by this file's code on the rigidsim checkout
    ``checkout`` (a subprocess in its folder, so its ``render`` and ``engine`` are used)."""
    code = (
        "import json, sys; sys.path.insert(0, sys.argv[1]); import bench_render as b; "
        "print(json.dumps(b.named_scene_cpu_ms(sys.argv[2], int(sys.argv[3]))))"
    )
    run = subprocess.run(
        [sys.executable, "-c", code, str(ROOT / "benchmarks"), name, str(repeats)],
        env=dict(os.environ, PYTHONPATH=str(checkout)),
        cwd=checkout,
        capture_output=True,
        text=True,
    )
    if run.returncode != 0:
        raise RuntimeError(f"{name!r} failed in {checkout}: {run.stderr.strip()[-500:]}")
    return float(json.loads(run.stdout.strip().splitlines()[-1]))


def compare_with_baseline(
    baseline: Path, rounds: int, repeats: int, names: tuple[str, ...] = BASELINE_SCENES
) -> None:
    """Print the fastest frame's CPU ms of this checkout and ``baseline`` over ``rounds``, which
    alternate scene by scene (who goes first alternates too), and their ratio."""
    print(f"this checkout {ROOT} vs baseline {baseline}: CPU ms per frame at {RESOLUTION[1]}x")
    print(f"{RESOLUTION[0]}, the fastest frame of {rounds} rounds of {repeats} frames each")
    print(f"{'scene':30s} {'this ms':>8s} {'base ms':>8s} {'ratio':>6s}  all rounds (this/base)")
    worst = 0.0
    for name in names:
        times: dict[Path, list[float]] = {ROOT: [], baseline: []}
        for round_ in range(rounds):
            order = (ROOT, baseline) if round_ % 2 == 0 else (baseline, ROOT)
            for checkout in order:
                times[checkout].append(checkout_cpu_ms(checkout, name, repeats))
        ours, base = min(times[ROOT]), min(times[baseline])
        worst = max(worst, ours / base)
        rounds_text = " ".join(
            f"{a:.1f}/{b:.1f}" for a, b in zip(times[ROOT], times[baseline], strict=True)
        )
        print(f"{name:30s} {ours:8.1f} {base:8.1f} {ours / base:5.3f}x  {rounds_text}", flush=True)
    print(f"slowest ratio {worst:.3f}x: {'within' if worst <= 1.03 else 'OVER'} the 3 % bound")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--async-only", action="store_true", help="only the async table")
    parser.add_argument("--baseline", type=Path, help="a rigidsim checkout to compare with")
    parser.add_argument("--rounds", type=int, default=5, help="alternating --baseline rounds")
    parser.add_argument("--frames", type=int, help="frames per --baseline round (default 9)")
    parser.add_argument("--only", help="--baseline: comma-separated scene names to run")
    args = parser.parse_args()
    if args.async_only:
        print_async_table(10 if args.quick else 40)
        return
    if args.baseline:
        names = tuple(args.only.split(",")) if args.only else BASELINE_SCENES
        unknown = sorted(set(names) - set(BASELINE_SCENES))
        if unknown:
            parser.error(f"--only: no scene {unknown}; scenes: {', '.join(BASELINE_SCENES)}")
        frames = args.frames or (3 if args.quick else 9)
        compare_with_baseline(args.baseline.resolve(), args.rounds, frames, names)
        return
    repeats = 3 if args.quick else 15
    camera = Camera(RESOLUTION, hfov=90.0)
    spheres = [1_000, 10_000] if args.quick else [1_000, 10_000, 100_000]
    scenes = [
        (f"sphere {n // 1000}k", sphere_scene(n), look_at((0, 0.5, 3.0), (0, 0, 0)), False)
        for n in spheres
    ]
    scenes.append(("sphere 10k, cull back faces", scenes[1][1], scenes[1][2], True))
    boxes_pose = look_at((0, 1.0, 0.8), (0, 0, -1.5))
    scenes.append(("plane + 5 boxes, full screen", plane_and_boxes_scene(), boxes_pose, False))
    scenes.extend(apartment_scenes())
    print(f"render_frame at {RESOLUTION[1]}x{RESOLUTION[0]} (color + depth + ids), medians")
    print(
        f"{'scene':30s} {'tris':>7s} {'covered':>8s} {'frags':>8s} {'ours ms':>8s} "
        f"{'cpu ms':>7s} {'tiny ms':>8s} {'ratio':>6s} {'depth diff':>10s}"
    )
    for name, meshes, pose, cull in scenes:
        result = bench_scene(meshes, camera, pose, repeats, cull_back_faces=cull)
        n_triangles = sum(len(m.faces) for m in meshes)
        tiny = pybullet_renderer(meshes, camera, pose)
        tiny_ms, ratio, diff = float("nan"), float("nan"), float("nan")
        if tiny is not None:
            tiny_ms, tiny_depth = time_calls(tiny, max(1, repeats // 2))
            ratio = tiny_ms / result["ms"]
            ours = result["frame"].depth
            both = (ours > 0) & (tiny_depth > 0)
            if both.any():
                diff = float(np.median(np.abs(ours[both] - tiny_depth[both]) / ours[both]))
        print(
            f"{name:30s} {n_triangles:7d} {result['covered']:8d} {result['fragments']:8d} "
            f"{result['ms']:8.1f} {result['cpu_ms']:7.1f} {tiny_ms:8.1f} {ratio:5.1f}x "
            f"{diff:10.1e}"
        )
        stages = ", ".join(f"{k} {v:.1f}" for k, v in result["stages"].items())
        print(f"{'':30s} stages (ms): {stages}")
    print("ratio = TinyRenderer time / ours (> 1: we are faster); depth diff = median relative")
    print()
    print("static camera, 5 moving lit boxes over the apartment (bit-identical frames checked)")
    print(f"{'scene':30s} {'full ms':>8s} {'layer ms':>9s} {'speed-up':>9s} {'box px':>7s}")
    for name, meshes, pose, _ in scenes[-2:]:
        result = bench_static_layer(meshes, camera, pose, repeats)
        print(
            f"{name:30s} {result['full_ms']:8.1f} {result['layer_ms']:9.1f} "
            f"{result['speedup']:8.1f}x {result['moving_pixels']:7d}"
        )
    print()
    print_async_table(10 if args.quick else 40)


def print_async_table(n_frames: int) -> None:
    """Print :func:`bench_async`'s medians and the share of the shorter task hidden."""
    result = bench_async(n_frames)
    print("asynchronous rendering: tutorial cameras + 30 dropping cubes, ms per frame (medians)")
    print(f"{'physics':>8s} {'render':>8s} {'sequential':>11s} {'async':>8s} {'overlap':>8s}")
    print(
        f"{result['physics']:8.1f} {result['render']:8.1f} {result['sequential']:11.1f} "
        f"{result['async']:8.1f} {100 * result['overlap']:7.0f}%"
    )
    print("overlap = (sequential - async) / min(physics, render): 100 % hides the shorter one")


if __name__ == "__main__":
    main()
