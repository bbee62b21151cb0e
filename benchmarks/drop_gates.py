"""The column's quality gates over several drops, for judging a solver change (on demand).

``bench_physics.py`` gates a column on one drop (seed 0 of ``column_positions``): the
deepest cube-cube overlap of 100 falling cubes is decided by a handful of chaotic impacts,
so a change that is as good on average can pass or miss it by luck. This script drops the
same column from several seeds and prints, per seed and as mean and worst, what the gates
read: the deepest overlap of a cube below the floor and between two cubes from
``physics_scenes.WATCH_FROM`` on (true overlaps: the lowest corner, and the separating-axis
overlap of touching cubes), and the cubes asleep at the end. ``--set`` changes
:class:`SolverSettings` fields for the run, so two settings can be compared seed by seed::

    python benchmarks/drop_gates.py                      # plane-column-100, seeds 0-7, 3 s
    python benchmarks/drop_gates.py --set velocity_iterations=8 --seeds 4
    python benchmarks/drop_gates.py --scene plane-column-500 --seconds 3 --seeds 2

Each drop is deterministic (the same seed and settings give the same figures on any
machine), so these figures need no repeats.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parent))

import physics_scenes as scenes  # noqa: E402

from engine.physics.core.settings import SolverSettings  # noqa: E402


def parse_settings(assignments: list[str]) -> dict:
    """``{"field": value}`` of ``field=value`` strings, each value converted to the type of
    the :class:`SolverSettings` field's default (``true``/``false`` for booleans)."""
    defaults = SolverSettings()
    fields = {f.name for f in dataclasses.fields(SolverSettings)}
    out = {}
    for text in assignments:
        name, sep, raw = text.partition("=")
        if not sep or name not in fields:
            raise SystemExit(
                f"--set {text!r}: expected field=value with a field of {sorted(fields)}"
            )
        kind = type(getattr(defaults, name))
        if kind is bool:
            if raw.lower() not in ("true", "false", "1", "0"):
                raise SystemExit(f"--set {text!r}: a boolean is true or false")
            out[name] = raw.lower() in ("true", "1")
        else:
            out[name] = kind(raw)
    return out


def drop(scene: str, seed: int, seconds: float, settings: dict) -> dict:
    """One drop of ``scene`` (``plane-column-N`` or ``column-N``) from ``seed``: the deepest
    floor and pair overlaps (m) from ``WATCH_FROM`` on and the cubes asleep at the end."""
    n = int(scene.rsplit("-", 1)[1])
    stage = "plane" if scene.startswith("plane-") else "box"
    positions, rotations = scenes.column_positions(n, seed=seed)
    with scenes.sleeping_disabled(stage == "box"):
        world, boxes = scenes.build_world(positions, rotations, stage)
        for name, value in settings.items():
            setattr(world.settings, name, value)
        deepest = np.zeros(2)
        for frame in range(int(round(seconds / scenes.FRAME))):
            world.step_physics(scenes.FRAME)
            if (frame + 1) * scenes.FRAME >= scenes.WATCH_FROM - 1e-9:
                deepest = np.maximum(deepest, scenes.penetration(world))
    return {"floor": deepest[0], "pair": deepest[1], "asleep": sum(not b.awake for b in boxes)}


def summary(rows: list[dict]) -> str:
    """Mean and worst of each gate over the drops."""
    floor = [r["floor"] * 1000 for r in rows]
    pair = [r["pair"] * 1000 for r in rows]
    asleep = [r["asleep"] for r in rows]
    return (
        f"floor overlap mean {statistics.mean(floor):.1f} mm, worst {max(floor):.1f} mm; "
        f"cube-cube overlap mean {statistics.mean(pair):.1f} mm, worst {max(pair):.1f} mm; "
        f"asleep at the end mean {statistics.mean(asleep):.1f}, fewest {min(asleep)}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="plane-column-100")
    parser.add_argument("--seeds", type=int, default=8, help="seeds 0 .. N-1")
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE")
    args = parser.parse_args()
    if not args.scene.startswith(("plane-column-", "column-")):
        raise SystemExit(f"--scene {args.scene!r}: a column scene (plane-column-N, column-N)")
    settings = parse_settings(args.set)
    print(f"{args.scene}, {args.seconds:g} s, settings {settings or 'default'}")
    rows = []
    for seed in tqdm(range(args.seeds), desc=f"drops of {args.scene}"):
        row = drop(args.scene, seed, args.seconds, settings)
        rows.append(row)
        tqdm.write(
            f"  seed {seed}: floor {row['floor'] * 1000:.1f} mm, cube-cube "
            f"{row['pair'] * 1000:.1f} mm, asleep {row['asleep']}"
        )
    print(summary(rows))


if __name__ == "__main__":
    main()
