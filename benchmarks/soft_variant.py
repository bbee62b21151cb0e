"""Run a benchmark command with solver settings patched into every benchmark world.

The soft step (``SolverSettings.soft_step``, Box2D v3's schedule) is off by default; this
wrapper turns it (and its constants) on for one measurement run without touching the
library: ``RIGIDSIM_SETTINGS="soft_step=1,soft_substeps=2"`` is read here, and only
here, and applied to the ``settings`` of each world :func:`physics_scenes.build_world`
makes. Usage::

    RIGIDSIM_SETTINGS="soft_step=1" python benchmarks/soft_variant.py bench_physics.py --only ...
    RIGIDSIM_SETTINGS="soft_step=1" python benchmarks/soft_variant.py hash plane-column-100 2.0

``gates SCENE...`` prints each scene's operations per step and quality gates;
``hash SCENE SECONDS`` prints the world's state hash after stepping the scene (a
trajectory fingerprint: the same before and after a change that must be bit-identical).
"""

from __future__ import annotations

import os
import runpy
import sys
from dataclasses import fields
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import physics_scenes  # noqa: E402

from engine.physics.core.settings import SolverSettings  # noqa: E402


def parsed_settings(text: str) -> dict:
    """``{"soft_step": True, ...}`` of ``"soft_step=1,soft_substeps=2"`` (typed by the
    :class:`SolverSettings` field it names)."""
    types = {f.name: type(getattr(SolverSettings(), f.name)) for f in fields(SolverSettings)}
    out = {}
    for item in filter(None, text.split(",")):
        name, value = item.split("=")
        kind = types[name.strip()]
        out[name.strip()] = bool(int(value)) if kind is bool else kind(value)
    return out


def patch(values: dict) -> None:
    """Every world the benchmark scenes build gets ``values`` in its settings."""
    build = physics_scenes.build_world

    def patched(*args, **kwargs):
        world, boxes = build(*args, **kwargs)
        for name, value in values.items():
            setattr(world.settings, name, value)
        return world, boxes

    physics_scenes.build_world = patched


def trajectory_hash(scene: str, seconds: float) -> str:
    """The state hash after ``seconds`` of the scene ``scene`` (default sleeping)."""
    (positions, rotations), stage = physics_scenes.named_scene(scene)
    world, _ = physics_scenes.build_world(positions, rotations, stage)
    for _ in range(int(round(seconds / physics_scenes.FRAME))):
        world.step_physics(physics_scenes.FRAME)
    return world.state_hash()


def gates(scenes: list[str], seconds: float = 3.0) -> None:
    """One line per scene: NumPy operations per step (``count_operations``), the deepest
    floor and cube-cube overlaps from 1 s on, the cubes asleep at the end and when all
    were (the quality gates of ``bench_physics.py``, rigidsim only)."""
    for scene in scenes:
        (positions, rotations), stage = physics_scenes.named_scene(scene)
        sleep = not scene.startswith("column-")
        run = physics_scenes.run_rigidsim(positions, rotations, seconds, sleep=sleep, stage=stage)
        ops, _ = physics_scenes.count_operations(positions, rotations, sleep=sleep, stage=stage)
        settled = "never" if run["settled"] is None else f"{run['settled'][0]:.2f} s"
        floor, pair = 1000 * run["deepest"]
        print(
            f"{scene}: {ops:,.0f} ops/step, floor {floor:.1f} mm, cube-cube {pair:.1f} mm, "
            f"asleep {run['asleep']}/{len(positions)} at {seconds:g} s, all asleep: {settled}, "
            f"CPU {1000 * run['cpu'] / run['steps']:.2f} ms/step",
            flush=True,
        )


def main() -> None:
    values = parsed_settings(os.environ.get("RIGIDSIM_SETTINGS", ""))
    patch(values)
    print(f"settings patched into the benchmark worlds: {values}", flush=True)
    command, args = sys.argv[1], sys.argv[2:]
    if command == "hash":
        print(trajectory_hash(args[0], float(args[1])))
        return
    if command == "gates":
        gates(args)
        return
    script = Path(command) if Path(command).exists() else HERE / command
    sys.argv = [str(script), *args]
    runpy.run_path(str(script), run_name="__main__")


if __name__ == "__main__":
    main()
