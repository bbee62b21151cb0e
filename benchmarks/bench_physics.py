"""Benchmark rigidsim's physics against pybullet on the same scenes (on demand).

Scenes (0.2 m cubes of 1 kg on a floor, fixed step 0.008 s in both engines, driven by 1/60 s
frames through the same accumulator):

* ``column-N``: N cubes dropped from a loose column 5 m high (12 layers, random
  orientations), **sleeping switched off in both engines**, so every body moves (or is
  simulated as if it could) for the whole run: the cost of a scene that keeps moving
  (issue 13; N = 10, 100, 500);
* ``pile-N``: N cubes dropped in a loose grid, sleeping on (N = 10, 100): time to settle;
* ``stack-10``: a vertical stack of 10 cubes, 10 s (quality: lateral drift of the top cube,
  energy drift);
* ``pyramid-6``: a pyramid with a base of 6 cubes (quality: largest displacement).

Reported per scene: ms of wall time per fixed step and per simulated second, pybullet's
figures and the ratio, bodies asleep at the end, the largest contact penetration over the
run and at the end, the energy change (J), the fastest body at the end (jitter), and where
rigidsim's time went (``world.profile``, the stage timers). ``--sweep`` adds the scaling
table (10 to 1000 cubes in the moving column): ms per step, per body, each stage's share,
and writes ``docs/physics_scaling.png``. The last block prints issue 13's targets and
whether each was met. Ratios measured in one run are the numbers to compare; absolute
times vary a lot on a shared machine.

Usage::

    python benchmarks/bench_physics.py               # targets: columns, stack, piles
    python benchmarks/bench_physics.py --sweep       # + scaling sweep and plot
    python benchmarks/bench_physics.py --quick       # 2 s columns, no 500, short quality runs
    python benchmarks/bench_physics.py --reference   # also time the reference path
                                                     # (use_vectorized=False) on each scene
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "physics"))

from helpers import add, make_world, register_primitive  # noqa: E402

from engine import mn  # noqa: E402
from engine.physics import settings as physics_settings  # noqa: E402
from engine.physics.quaternions import quat_to_matrix  # noqa: E402

FRAME = 1.0 / 60.0
STEP = 0.008
HALF = 0.1
GRAVITY = 9.8
#: stage timer names, in step order, for the profile columns (others go to "rest")
STAGES = (
    "forces",
    "broad phase",
    "fcl update",
    "narrow phase",
    "manifolds",
    "solve",
    "integrate",
    "sleep",
)
ROOT = Path(__file__).resolve().parents[1]


# ------------------------------------------------------------------------------------------
# scenes
# ------------------------------------------------------------------------------------------
def column_positions(n: int, height: float = 5.0, seed: int = 0):
    """A loose column of ``n`` cubes: 12 layers (fewer when n < 12) from 0.3 m up to
    ``height``, each layer a jittered square grid of 0.36 m pitch (more than a cube's
    0.35 m diagonal, so no two cubes start overlapping); random orientations."""
    rng = np.random.default_rng(seed)
    layers = min(n, 12)
    per_layer = int(np.ceil(n / layers))
    side = int(np.ceil(np.sqrt(per_layer)))
    pitch_y = (height - 0.3) / max(layers - 1, 1)
    positions, rotations = [], []
    for k in range(n):
        layer, cell = divmod(k, per_layer)
        row, col = divmod(cell, side)
        positions.append(
            [
                (col - (side - 1) / 2) * 0.36 + rng.uniform(-0.005, 0.005),
                0.3 + pitch_y * layer,
                (row - (side - 1) / 2) * 0.36 + rng.uniform(-0.005, 0.005),
            ]
        )
        q = rng.normal(size=4)
        rotations.append(q / np.linalg.norm(q))
    return positions, rotations


def pile_positions(n: int, seed: int = 0):
    """Loose grid of ``n`` drop positions and random unit quaternions [x, y, z, w]."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(min(n, 100))))
    positions, rotations = [], []
    for k in range(n):
        layer, cell = divmod(k, side * side)
        row, col = divmod(cell, side)
        positions.append(
            [
                (col - side / 2) * 0.25 + rng.uniform(-0.03, 0.03),
                0.3 + 0.3 * layer + rng.uniform(0, 0.05),
                (row - side / 2) * 0.25 + rng.uniform(-0.03, 0.03),
            ]
        )
        q = rng.normal(size=4)
        rotations.append(q / np.linalg.norm(q))
    return positions, rotations


def stack_positions(n: int = 10):
    return [[0.0, HALF + 0.201 * i, 0.0] for i in range(n)], [[0, 0, 0, 1.0]] * n


def pyramid_positions(base: int = 6):
    positions = []
    for level in range(base):
        for i in range(base - level):
            positions.append([(i - (base - 1 - level) / 2) * 0.202, HALF + level * 0.201, 0.0])
    return positions, [[0, 0, 0, 1.0]] * len(positions)


@contextlib.contextmanager
def sleeping_disabled(disabled: bool):
    """Switch rigidsim's sleeping off (an island would need infinite rest to sleep)."""
    saved = physics_settings.TIME_TO_SLEEP
    if disabled:
        physics_settings.TIME_TO_SLEEP = float("inf")
    try:
        yield
    finally:
        physics_settings.TIME_TO_SLEEP = saved


# ------------------------------------------------------------------------------------------
# measurements
# ------------------------------------------------------------------------------------------
def penetration(world) -> tuple[float, float]:
    """Deepest true overlaps of the cubes, m: ``(floor, pair)``, below the floor (y = 0) by
    their lowest corner, and between touching cubes by the separating-axis overlap (the
    smallest overlap over the 15 axes of two boxes, Ericson 4.4.1), not the manifold's
    bookkept point depths."""
    b, n = world.bodies, world.bodies.count
    ids = np.arange(1, n)[b.body_alive[1:n]]
    if len(ids) == 0:
        return 0.0, 0.0
    rotation = quat_to_matrix(b.body_rotation[:n])
    half = b.body_shape_half[:n]
    center = b.body_position[:n] + np.einsum("nij,nj->ni", rotation, b.body_shape_center[:n])
    # lowest corner: y of the center minus the box's half height along world Y
    lowest = center[ids, 1] - (np.abs(rotation[ids, 1, :]) * half[ids]).sum(axis=1)
    floor, deepest = max(0.0, float(-lowest.min())), 0.0
    store = world.manifolds
    rows = store.rows_with_points()
    pairs = store.bodies[rows]
    pairs = pairs[pairs[:, 0] != 0]
    if len(pairs):
        a, c = pairs[:, 0], pairs[:, 1]
        axes_a, axes_c = rotation[a], rotation[c]  # box axes = matrix columns
        cross = np.cross(axes_a[:, :, :, None], axes_c[:, :, None, :], axis=1)  # (p, 3, 3, 3)
        axes = np.concatenate([axes_a, axes_c, cross.reshape(len(a), 3, 9)], axis=2)  # (p,3,15)
        length = np.linalg.norm(axes, axis=1)  # (p, 15)
        usable = length > 1e-6  # parallel edges give no axis
        axes = axes / np.maximum(length, 1e-12)[:, None, :]
        # projected radius of box k on axis L: sum_i h_i |a_i . L|
        radius_a = (np.abs(np.einsum("pij,pik->pjk", axes_a, axes)) * half[a][:, :, None]).sum(1)
        radius_c = (np.abs(np.einsum("pij,pik->pjk", axes_c, axes)) * half[c][:, :, None]).sum(1)
        distance = np.abs(np.einsum("pi,pik->pk", center[c] - center[a], axes))
        overlap = np.where(usable, radius_a + radius_c - distance, np.inf).min(axis=1)
        deepest = max(deepest, float(overlap.max()))
    return floor, deepest


def energy(world) -> float:
    """Kinetic + potential energy of the dynamic bodies, J (potential: m g y)."""
    b, n = world.bodies, world.bodies.count
    ids = np.arange(1, n)[b.body_alive[1:n]]
    m, v, w = b.body_mass[ids], b.body_linear_velocity[ids], b.body_angular_velocity[ids]
    rotation = quat_to_matrix(b.body_rotation[ids])
    w_body = np.einsum("nji,nj->ni", rotation, w)  # R^T w: body-frame angular velocity
    kinetic = 0.5 * (m * (v * v).sum(1)).sum() + 0.5 * (b.body_inertia[ids] * w_body**2).sum()
    return float(kinetic + (m * GRAVITY * b.body_position[ids, 1]).sum())


#: s, penetration and energy drift are measured from this time on (the loose piles start
#: with overlapping cubes, and falling cubes first convert potential energy)
WATCH_FROM = 1.0


def run_rigidsim(positions, rotations, seconds, sleep=True, watch=True, vectorized=True):
    """Step a scene; wall time counts ``step_physics`` only (measurements are outside)."""
    with sleeping_disabled(not sleep):
        world, templates = make_world(floor_half=20.0)
        world.settings.use_vectorized = vectorized
        handle = register_primitive(templates, "cubeSolid", (HALF, HALF, HALF))
        boxes = []
        for p, q in zip(positions, rotations, strict=True):
            box = add(world, templates, handle, p)
            box.rotation = mn.Quaternion.from_xyzw(q)
            boxes.append(box)
        world.timer.reset()
        energy_start = None
        wall, cpu, settled, deepest = 0.0, 0.0, None, np.zeros(2)
        steps_before = world._time
        for frame in range(int(round(seconds / FRAME))):
            start, start_cpu = time.perf_counter(), time.process_time()
            world.step_physics(FRAME)
            wall += time.perf_counter() - start
            cpu += time.process_time() - start_cpu
            if (frame + 1) * FRAME >= WATCH_FROM - 1e-9:
                if energy_start is None:
                    energy_start = energy(world)
                if watch:
                    deepest = np.maximum(deepest, penetration(world))
            if settled is None and not world.bodies.body_awake[1 : world.bodies.count].any():
                settled = ((frame + 1) * FRAME, wall)
        steps = int(round((world._time - steps_before) / STEP))
        b, n = world.bodies, world.bodies.count
        speed = np.linalg.norm(b.body_linear_velocity[1:n], axis=1).max(initial=0.0)
        return {
            "wall": wall,
            "cpu": cpu,
            "steps": steps,
            "settled": settled,
            "final": np.array([np.asarray(box.translation) for box in boxes]),
            "asleep": sum(not box.awake for box in boxes),
            "profile": dict(world.profile),
            "deepest": deepest,
            "resting_depth": np.array(penetration(world)),
            "energy_change": energy(world) - (energy_start or energy(world)),
            "touching_pairs": len(world.manifolds.rows_with_points()),
            "end_speed": float(speed),
        }


def run_pybullet(positions, rotations, seconds, sleep=True):
    import pybullet as p

    client = p.connect(p.DIRECT)
    p.setGravity(0, -GRAVITY, 0, physicsClientId=client)
    p.setTimeStep(STEP, physicsClientId=client)
    plane = p.createCollisionShape(p.GEOM_BOX, halfExtents=[20, 0.05, 20], physicsClientId=client)
    p.createMultiBody(0, plane, basePosition=[0, -0.05, 0], physicsClientId=client)
    box = p.createCollisionShape(p.GEOM_BOX, halfExtents=[HALF] * 3, physicsClientId=client)
    bodies = [
        p.createMultiBody(
            1.0, box, basePosition=pos, baseOrientation=list(q), physicsClientId=client
        )
        for pos, q in zip(positions, rotations, strict=True)
    ]
    if not sleep:
        for body in bodies:
            p.changeDynamics(
                body,
                -1,
                activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
                physicsClientId=client,
            )
    steps, accumulated = 0, 0.0
    start, start_cpu = time.perf_counter(), time.process_time()
    for _ in range(int(round(seconds / FRAME))):  # the same accumulator as step_physics
        accumulated += FRAME
        while accumulated >= STEP:
            p.stepSimulation(physicsClientId=client)
            accumulated -= STEP
            steps += 1
    wall, cpu = time.perf_counter() - start, time.process_time() - start_cpu
    final = np.array(
        [p.getBasePositionAndOrientation(b, physicsClientId=client)[0] for b in bodies]
    )
    p.disconnect(client)
    return {"wall": wall, "cpu": cpu, "steps": steps, "final": final}


def have_pybullet() -> bool:
    try:
        import pybullet  # noqa: F401
    except ImportError:
        return False
    return True


def shares(profile: dict, wall: float) -> dict:
    """Fraction of the stepping wall time spent in each stage (``rest``: untimed work)."""
    # "collide" contains broad phase, fcl update, narrow phase and manifolds
    out = {name: profile.get(name, 0.0) / wall for name in STAGES}
    out["rest"] = max(0.0, 1.0 - sum(out.values()))
    return out


def quality(name, start, final):
    if name.startswith("stack"):
        return f"top drift {np.linalg.norm((final[-1] - start[-1])[[0, 2]]) * 1000:.2f} mm"
    if name.startswith("pyramid"):
        return f"max displacement {np.abs(final - start).max() * 100:.2f} cm"
    return f"lowest center {final[:, 1].min():.3f} m"


# ------------------------------------------------------------------------------------------
# report
# ------------------------------------------------------------------------------------------
def run_scene(name, positions, rotations, seconds, sleep, bullet, results, reference=False):
    ours = run_rigidsim(positions, rotations, seconds, sleep=sleep)
    theirs = run_pybullet(positions, rotations, seconds, sleep=sleep) if bullet else None
    start = np.array(positions)
    ms_step = ours["wall"] / ours["steps"] * 1000
    ms_sim = ours["wall"] / seconds * 1000
    cpu_step = ours["cpu"] / ours["steps"] * 1000
    if theirs:
        bullet_step = theirs["wall"] / theirs["steps"] * 1000
        ratio = ours["wall"] / theirs["wall"]
        cpu_ratio = ours["cpu"] / max(theirs["cpu"], 1e-9)
        bullet_text = f"{bullet_step:8.3f} {ratio:6.1f}x {cpu_ratio:6.1f}x"
        bullet_quality = quality(name, start, theirs["final"])
    else:
        bullet_step, ratio, bullet_text, bullet_quality = (
            float("nan"),
            float("nan"),
            "     n/a    n/a     n/a",
            "n/a",
        )
    split = shares(ours["profile"], ours["wall"])
    split_text = " ".join(f"{100 * split[k]:3.0f}" for k in (*STAGES, "rest"))
    print(
        f"{name:<11} {seconds:4.1f} {ms_step:8.3f} {cpu_step:8.3f} {ms_sim:8.0f} {bullet_text} "
        f"{ours['asleep']:4d}/{len(positions):<4d} "
        f"{ours['deepest'][0] * 1000:4.1f}/{ours['deepest'][1] * 1000:5.1f} "
        f"{ours['resting_depth'][0] * 1000:4.1f}/{ours['resting_depth'][1] * 1000:5.1f} "
        f"{ours['energy_change']:8.3f} "
        f"{ours['end_speed']:6.3f}  {quality(name, start, ours['final'])} | {bullet_quality}"
    )
    print(f"{'':<11} profile % {split_text}")
    if reference:
        slow = run_rigidsim(
            positions, rotations, seconds, sleep=sleep, watch=False, vectorized=False
        )
        print(
            f"{'':<11} reference path: {slow['wall'] / slow['steps'] * 1000:.2f} ms/step "
            f"({slow['wall'] / ours['wall']:.1f}x the vectorized path)"
        )
    if ours["settled"] is not None and name.startswith("pile"):
        sim, wall = ours["settled"]
        print(
            f"{'':<11} settled: all {len(positions)} asleep after {sim:.2f} s simulated, "
            f"{wall:.2f} s wall ({sim / wall:.2f}x real time)"
        )
    results[name] = dict(
        ours,
        ms_step=ms_step,
        cpu_step=cpu_step,
        ratio=ratio,
        bullet_step=bullet_step,
        start=start,
        n=len(positions),
        seconds=seconds,
    )


def sweep(sizes, seconds, bullet):
    """Scaling table of the moving column; returns rows for the plot."""
    print(
        "\nScaling: moving column (sleeping off); rigidsim per body in CPU time (the wall "
        "time of a loaded machine is too noisy); pairs/body: touching pairs at the end;\n"
        "ratio: wall vs pybullet. "
        f"{seconds:.1f} s simulated per size; shares of rigidsim's wall time in %"
    )
    print(
        f"{'N':>5} {'ms/step':>8} {'cpu ms':>8} {'cpu us/body':>11} {'pairs/body':>10} "
        f"{'bullet ms':>9} {'ratio':>6}  " + " ".join(f"{k[:6]:>6}" for k in (*STAGES, "rest"))
    )
    rows = []
    for n in sizes:
        positions, rotations = column_positions(n)
        ours = run_rigidsim(positions, rotations, seconds, sleep=False, watch=False)
        ms = ours["wall"] / ours["steps"] * 1000
        cpu = ours["cpu"] / ours["steps"] * 1000
        if bullet:
            theirs = run_pybullet(positions, rotations, seconds, sleep=False)
            bullet_ms = theirs["wall"] / theirs["steps"] * 1000
            bullet_cpu = theirs["cpu"] / theirs["steps"] * 1000
        else:
            bullet_ms = bullet_cpu = float("nan")
        split = shares(ours["profile"], ours["wall"])
        pairs = ours["touching_pairs"] / n
        print(
            f"{n:5d} {ms:8.3f} {cpu:8.3f} {1000 * cpu / n:11.1f} {pairs:10.2f} "
            f"{bullet_ms:9.3f} {ms / bullet_ms:6.1f}  "
            + " ".join(f"{100 * split[k]:6.1f}" for k in (*STAGES, "rest"))
        )
        rows.append((n, cpu, bullet_cpu, split))
    return rows


def plot(rows, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = np.array([r[0] for r in rows])
    ms = np.array([r[1] for r in rows])
    bullet = np.array([r[2] for r in rows])
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    axes[0].loglog(n, ms, "o-", label="rigidsim")
    axes[0].loglog(n, bullet, "s--", label="pybullet")
    axes[0].set(xlabel="cubes", ylabel="CPU ms per 0.008 s step", title="cost per step")
    axes[1].semilogx(n, 1000 * ms / n, "o-", label="rigidsim")
    axes[1].semilogx(n, 1000 * bullet / n, "s--", label="pybullet")
    axes[1].set(xlabel="cubes", ylabel="CPU us per body per step", title="cost per body")
    bottom = np.zeros(len(rows))
    for key in (*STAGES, "rest"):
        share = np.array([100 * r[3][key] for r in rows])
        axes[2].bar(np.arange(len(rows)), share, bottom=bottom, label=key)
        bottom += share
    axes[2].set_xticks(np.arange(len(rows)), [str(v) for v in n])
    axes[2].set(xlabel="cubes", ylabel="% of rigidsim's step", title="stage shares")
    axes[2].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    for ax in axes[:2]:
        ax.legend()
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("Moving column of 0.2 m cubes (sleeping off), 2-core shared machine")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    print(f"wrote {path}")


def report_targets(results, rows) -> None:
    """Issue 13's targets, each with its measured value and met / missed."""
    print("\nTargets (issue 13):")

    def line(text, value, ok):
        print(f"  [{'met   ' if ok else 'MISSED'}] {text}: {value}")

    if "column-100" in results:
        r = results["column-100"]
        line("column-100: <= 3 ms per 0.008 s step", f"{r['ms_step']:.2f} ms", r["ms_step"] <= 3)
        line("column-100: <= 5x pybullet", f"{r['ratio']:.1f}x", r["ratio"] <= 5)
    if "column-500" in results:
        r = results["column-500"]
        line(
            "column-500: <= 3x pybullet wall per simulated s", f"{r['ratio']:.1f}x", r["ratio"] <= 3
        )
    if "column-10" in results:
        r = results["column-10"]
        line("column-10: <= 0.4 ms per step", f"{r['ms_step']:.3f} ms", r["ms_step"] <= 0.4)
    if rows:
        per_body = {n: cpu / n for n, cpu, _, _ in rows}  # CPU ms: robust to the load
        sizes = sorted(per_body)
        mid = [s for s in sizes if s >= 100]
        if len(mid) >= 2:
            growth = per_body[mid[-1]] / per_body[mid[0]]
            line(
                f"CPU cost per body flat or falling, N={mid[0]}..{mid[-1]} (within 15 %)",
                f"x{growth:.2f}",
                growth <= 1.15,
            )
    if "stack-10" in results:
        r = results["stack-10"]
        drift = np.linalg.norm((r["final"][-1] - r["start"][-1])[[0, 2]])
        line(
            f"stack-10 stands {r['seconds']:.0f} s with < 1 mm drift",
            f"{drift * 1000:.2f} mm, lowest {r['final'][:, 1].min():.3f} m",
            drift < 1e-3 and r["final"][-1, 1] > 1.8,
        )
        line(
            "stack-10 energy drift <= 0 (no energy gained)",
            f"{r['energy_change'] * 1000:+.2f} mJ",
            r["energy_change"] <= 1e-3,
        )
    if results:
        floor = max(r["deepest"][0] for r in results.values())
        line(
            "nothing sinks into the floor deeper than the 2 cm speculative margin",
            f"{floor * 1000:.1f} mm",
            floor < 0.02,
        )
        pair = {name: r["deepest"][1] for name, r in results.items()}
        worst = max(pair, key=pair.get)
        line(
            "no two cubes overlap deeper than 2 cm (worst scene)",
            f"{pair[worst] * 1000:.1f} mm in {worst}",
            pair[worst] < 0.02,
        )
    for name in ("pile-100", "column-100"):
        if name in results:
            r = results[name]
            line(
                f"{name} at rest without jitter at the end (fastest body < 0.05 m/s)",
                f"{r['end_speed']:.3f} m/s, resting overlap "
                f"{r['resting_depth'].max() * 1000:.1f} mm",
                r["end_speed"] < 0.05,
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short runs, no 500 column")
    parser.add_argument("--sweep", action="store_true", help="scaling sweep 10..1000 + plot")
    parser.add_argument("--only-sweep", action="store_true", help="the scaling sweep only")
    parser.add_argument(
        "--reference",
        action="store_true",
        help="also run the reference path (use_vectorized=False)",
    )
    parser.add_argument("--plot", type=Path, default=ROOT / "docs" / "physics_scaling.png")
    args = parser.parse_args()
    bullet = have_pybullet()
    column_s = 2.0 if args.quick else 3.0
    quality_s = 2.0 if args.quick else 10.0
    results: dict = {}
    if not args.only_sweep:
        scenes = [
            ("column-10", column_positions(10), column_s, False),
            ("column-100", column_positions(100), column_s, False),
        ]
        if not args.quick:
            scenes.append(("column-500", column_positions(500), column_s, False))
        scenes += [
            ("pile-10", pile_positions(10), quality_s, True),
            ("pile-100", pile_positions(100), quality_s, True),
            ("stack-10", stack_positions(), quality_s, True),
            ("pyramid-6", pyramid_positions(), quality_s, True),
        ]
        print(
            "ms/step: wall per 0.008 s step (cpu ms: this process's CPU time, less "
            "sensitive to a loaded machine);\nratio: wall vs pybullet, cpu rat: CPU time vs "
            "pybullet; deep/rest mm: deepest overlap floor/cube-cube "
            f"(true geometry) from {WATCH_FROM:g} s on / at the end;\ndE J: energy change "
            f"from {WATCH_FROM:g} s to the end; v end: fastest body at the end, m/s."
        )
        print(
            f"{'scene':<11} {'sim':>4} {'ms/step':>8} {'cpu ms':>8} {'ms/sim s':>8} "
            f"{'bullet':>8} {'ratio':>7} {'cpu rat':>7} {'asleep':>9} {'deep mm':>10} "
            f"{'rest mm':>10} {'dE J':>8} {'v end':>6}"
            "  quality (rigidsim | pybullet)"
        )
        print(f"{'':<11} profile % = " + " ".join(STAGES) + " rest")
        for name, (positions, rotations), seconds, sleep in scenes:
            run_scene(name, positions, rotations, seconds, sleep, bullet, results, args.reference)
    rows = []
    if args.sweep or args.only_sweep:
        sizes = (10, 30, 100, 300) if args.quick else (10, 30, 100, 300, 1000)
        rows = sweep(sizes, 1.0 if args.quick else 2.0, bullet)
        plot(rows, args.plot)
    report_targets(results, rows)


if __name__ == "__main__":
    main()
