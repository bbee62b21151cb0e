"""Benchmark rigidsim's physics against pybullet on the same scenes (on demand).

Scenes (0.2 m cubes of 1 kg on a floor, fixed step 0.008 s in both engines, driven by 1/60 s
frames through the same accumulator):

* ``column-N``: N cubes dropped from a loose column 5 m high (12 layers, random
  orientations), **sleeping switched off in both engines**, so every body moves (or is
  simulated as if it could) for the whole run: the cost of a scene that keeps moving
  (issue 13; N = 10, 100, 500);
* ``pile-N``: N cubes dropped in a loose grid, sleeping on (N = 10, 100): time to settle;
* ``stack-10``: a vertical stack of 10 cubes, 10 s (quality: lateral drift of the top cube,
  energy drift); ``stack-20`` the same with 20 cubes;
* ``pyramid-6``: a pyramid with a base of 6 cubes (quality: largest displacement);
  ``pyramid-10`` a 10-layer pyramid;
* ``plane-column-N``: the column on Habitat's ``plane.glb`` (a triangle-mesh stage, as every
  Habitat scene is) with **default sleeping** in both engines (N = 100, 500), and
  ``apartment-30``: 30 cubes dropped on the demo apartment's coffee table and floor; pybullet
  collides with the same triangles as a static mesh. ``settle`` prints when every body fell
  asleep in each engine.

Timings are CPU time (``time.process_time``) per fixed step, medians of ``--repeats``
interleaved runs (rigidsim, pybullet and, with ``--baseline PATH``, another rigidsim
checkout run in a subprocess, for the "x of the baseline's step" targets): other processes
load the machine, and ratios measured in one run are what to compare.

pybullet's bodies are btRigidBody (``useMaximalCoordinates=True``), the body Habitat's
``BulletRigidObject`` builds, on the same triangles (a static concave mesh), at the same step,
sleeping as Habitat leaves it (``physics_scenes``); ``--multibody`` adds a column timing
pybullet's btMultiBody, labelled so (not what Habitat uses).

Reported per scene: ms of wall time per fixed step and per simulated second, pybullet's
figures and the ratio, NumPy operations per step (``op_counter``: deterministic, counted
over ``physics_scenes.OPS_WINDOW`` in a separate untimed run; ``--no-ops`` skips it), bodies
asleep at the end, the largest contact penetration over the run and at the end, the energy
change (J), the fastest body at the end (jitter), and where rigidsim's time went
(``world.profile``, the stage timers). ``--sweep`` adds the scaling table (10 to 1000 cubes
in the moving column): ms per step, per body, each stage's share, and writes
``docs/physics_scaling.png``. The last block prints the speed targets and the quality gates,
each with whether it is met (``physics_targets.py``). Ratios measured
in one run are the numbers to compare; absolute times vary a lot on a shared machine.

Usage::

    python benchmarks/bench_physics.py               # targets: columns, stack, piles
    python benchmarks/bench_physics.py --baseline ../main --repeats 3
    python benchmarks/bench_physics.py --sweep       # + scaling sweep and plot
    python benchmarks/bench_physics.py --quick       # 2 s columns, no 500, short quality runs
    python benchmarks/bench_physics.py --reference   # also time the reference path
                                                     # (use_vectorized=False) on each scene
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
from datetime import date
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from op_counter import KINDS  # noqa: E402
from physics_scenes import (  # noqa: E402
    WATCH_FROM,
    apartment_positions,
    column_positions,
    count_operations,
    have_pybullet,
    physics_settings,
    pile_positions,
    pyramid_positions,
    run_pybullet,
    run_rigidsim,
    stack_positions,
)
from physics_targets import report_speed_targets, report_targets  # noqa: E402

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
def baseline_cpu(checkout: Path, scene: str, seconds: float, sleep: bool) -> float | None:
    """CPU ms per step of ``scene`` (:func:`physics_scenes.named_scene`) stepped by the
    rigidsim checkout ``checkout`` in a subprocess: this checkout's scene code on that
    checkout's ``engine`` (run in its folder, so ``engine`` resolves there); None if it
    fails."""
    code = (
        "import json, sys; sys.path.insert(0, sys.argv[1]); import physics_scenes as s; "
        "(p, q), stage = s.named_scene(sys.argv[2]); "
        "r = s.run_rigidsim(p, q, float(sys.argv[3]), sleep=sys.argv[4] == '1', watch=False, "
        "stage=stage); print(json.dumps(1000 * r['cpu'] / r['steps']))"
    )
    args = [str(ROOT / "benchmarks"), scene, str(seconds), "1" if sleep else "0"]
    run = subprocess.run(
        [sys.executable, "-c", code, *args],
        env=dict(os.environ, PYTHONPATH=str(checkout)),
        cwd=checkout,
        capture_output=True,
        text=True,
    )
    if run.returncode != 0:
        print(f"baseline run failed: {run.stderr.strip().splitlines()[-1:]}")
        return None
    return float(json.loads(run.stdout.strip().splitlines()[-1]))


def settle_text(settled: float | None, asleep: int | None, n: int) -> str:
    """The settle line: "all asleep after T s", or "not all asleep by the end (N of M)"
    when the scene never fully slept; ``asleep`` None is pybullet, whose probe is every
    velocity exactly zero (checked every 0.1 s), not a count of sleeping bodies."""
    if settled is not None:
        return f"all asleep after {settled:.2f} s"
    if asleep is None:
        return "never every velocity exactly 0 by the end"
    return f"not all asleep by the end ({asleep} of {n})"


def first(settled: tuple | None) -> float | None:
    """The simulated seconds of rigidsim's ``settled`` (seconds, wall), None if unsettled."""
    return None if settled is None else settled[0]


def run_scene(name, scene, bullet, results, options):
    """Run ``scene`` (positions, rotations, seconds, sleep, stage) ``options.repeats`` times
    interleaved with pybullet (and the baseline checkout); print one report line."""
    (positions, rotations), seconds, sleep, stage = scene
    cpu_ours, cpu_bullet, cpu_base = [], [], []
    runs_ours, runs_bullet = [], []  # the first run of each engine gives the quality figures
    for repeat in range(options.repeats):
        runs_ours.append(
            run_rigidsim(positions, rotations, seconds, sleep=sleep, stage=stage, watch=not repeat)
        )
        cpu_ours.append(runs_ours[-1]["cpu"] / runs_ours[-1]["steps"] * 1000)
        if bullet:
            runs_bullet.append(
                run_pybullet(positions, rotations, seconds, sleep=sleep, stage=stage)
            )
            cpu_bullet.append(runs_bullet[-1]["cpu"] / runs_bullet[-1]["steps"] * 1000)
        if options.baseline and name.startswith(("column", "plane-column", "apartment")):
            cpu_base.append(baseline_cpu(options.baseline, name, seconds, sleep))
    ours = runs_ours[0]
    theirs = runs_bullet[0] if bullet else None
    start = np.array(positions)
    ms_step = ours["wall"] / ours["steps"] * 1000
    ms_sim = ours["wall"] / seconds * 1000
    cpu_step = statistics.median(cpu_ours)
    base_step = statistics.median(cpu_base) if cpu_base and None not in cpu_base else None
    if theirs:
        bullet_step = statistics.median(cpu_bullet)
        ratio = ours["wall"] / theirs["wall"]
        cpu_ratio = cpu_step / max(bullet_step, 1e-9)
        bullet_text = f"{bullet_step:8.3f} {ratio:6.1f}x {cpu_ratio:6.1f}x"
        bullet_quality = quality(name, start, theirs["final"])
    else:
        bullet_step, ratio, cpu_ratio, bullet_text, bullet_quality = (
            float("nan"),
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
    ops = None
    if options.ops and name.startswith(("column", "plane-column", "apartment")):
        ops, counter = count_operations(positions, rotations, sleep=sleep, stage=stage)
        steps = max(1, round(counter.total / max(ops, 1e-9)))
        kinds = ", ".join(f"{k} {counter.counts[k] / steps:.0f}" for k in KINDS)
        print(
            f"{'':<11} NumPy operations/step {ops:,.0f} ({kinds}); bytecodes/step "
            f"{counter.instructions / steps:,.0f}"
        )
    if options.multibody and bullet:
        multi = run_pybullet(
            positions, rotations, seconds, sleep=sleep, stage=stage, multibody=True
        )
        multi_step = multi["cpu"] / multi["steps"] * 1000
        print(
            f"{'':<11} pybullet btMultiBody (not Habitat's body): {multi_step:.3f} CPU ms/step, "
            f"rigidsim {cpu_step / multi_step:.1f}x of it"
        )
    if base_step is not None:
        print(
            f"{'':<11} baseline checkout: {base_step:.3f} CPU ms/step, this one "
            f"{cpu_step / base_step:.2f}x of it"
        )
    if sleep:
        n = len(positions)
        ours_settled = settle_text(first(ours["settled"]), ours["asleep"], n)
        bullet_settled = settle_text(theirs["settled"], None, n) if theirs else "n/a"
        print(f"{'':<11} settle: {ours_settled} (pybullet: {bullet_settled})")
    if options.reference:
        slow = run_rigidsim(
            positions, rotations, seconds, sleep=sleep, watch=False, vectorized=False
        )
        print(
            f"{'':<11} reference path: {slow['wall'] / slow['steps'] * 1000:.2f} ms/step "
            f"({slow['wall'] / ours['wall']:.1f}x the vectorized path)"
        )
    if ours["settled"] is not None and name.startswith("pile") and options.verbose:
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
        cpu_ratio=cpu_ratio,
        base_ratio=None if base_step is None else cpu_step / base_step,
        bullet_step=bullet_step,
        ops=ops,
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
        f"{'bullet ms':>9} {'ratio':>6} {'b cpu':>6} {'cpu rat':>7}  "
        + " ".join(f"{k[:6]:>6}" for k in (*STAGES, "rest"))
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
            f"{bullet_ms:9.3f} {ms / bullet_ms:6.1f} {bullet_cpu:6.2f} {cpu / bullet_cpu:7.2f}  "
            + " ".join(f"{100 * split[k]:6.1f}" for k in (*STAGES, "rest"))
        )
        rows.append((n, cpu, bullet_cpu, split))
    return rows


def sleep_report(bullet: bool, sizes=(100, 500), seconds: float = 10.0) -> None:
    """When piles of ``sizes`` cubes (:func:`physics_scenes.pile_positions`, box floor) fall
    asleep in each engine with its default sleeping: rigidsim's ``settings`` and Bullet's
    btRigidBody defaults, which Habitat keeps (it never calls ``setSleepingThresholds``)."""
    print(
        f"\nSleeping: piles on the box floor, {seconds:g} s, default sleeping in both engines"
        f"\n  rigidsim: |v| < {physics_settings.SLEEP_LINEAR_VELOCITY:g} m/s and |w| < "
        f"{physics_settings.SLEEP_ANGULAR_VELOCITY:g} rad/s for "
        f"{physics_settings.TIME_TO_SLEEP:g} s (every body of an island); Bullet (Habitat): "
        "0.8 m/s, 1.0 rad/s, 2.0 s (gDeactivationTime), per island"
    )
    for n in sizes:
        positions, rotations = pile_positions(n)
        ours = run_rigidsim(positions, rotations, seconds, sleep=True, watch=False)
        ours_text = settle_text(first(ours["settled"]), ours["asleep"], n)
        theirs_text = "n/a"
        if bullet:
            theirs = run_pybullet(positions, rotations, seconds, sleep=True)
            theirs_text = settle_text(theirs["settled"], None, n)
        print(f"  pile-{n}: rigidsim {ours_text}; pybullet {theirs_text} (checked every 0.1 s)")


def machine_name() -> str:
    """The CPU model (``lscpu``'s "Model name"), or the platform's processor string."""
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return platform.processor() or platform.machine()
    names = [line.split(":", 1)[1].strip() for line in out.splitlines() if "Model name" in line]
    return names[0] if names else platform.machine()


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
    fig.suptitle(
        "Moving column of 0.2 m cubes (sleeping off), CPU time per step, pybullet "
        "btRigidBody (as Habitat); "
        f"{machine_name()}, {date.today().isoformat()} (shared, loaded)"
    )
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    print(f"wrote {path}")


def scenes(quick: bool) -> list:
    """``(name, ((positions, rotations), seconds, sleep, stage))`` of the report."""
    column_s, quality_s = (2.0, 2.0) if quick else (3.0, 10.0)
    sizes = (10, 100) if quick else (10, 100, 500)
    out = [(f"column-{n}", (column_positions(n), column_s, False, "box")) for n in sizes]
    out += [
        (f"plane-column-{n}", (column_positions(n), column_s, True, "plane")) for n in sizes[1:]
    ]
    out.append(("apartment-30", (apartment_positions(30), column_s, True, "apartment")))
    out += [
        ("pile-10", (pile_positions(10), quality_s, True, "box")),
        ("pile-100", (pile_positions(100), quality_s, True, "box")),
        ("stack-10", (stack_positions(), quality_s, True, "box")),
        ("pyramid-6", (pyramid_positions(), quality_s, True, "box")),
    ]
    if not quick:  # awake for 10 s: sleeping off
        out.append(("stack-20", (stack_positions(20), quality_s, False, "box")))
        out.append(("pyramid-10", (pyramid_positions(10), quality_s, False, "box")))
    return out


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
    parser.add_argument("--repeats", type=int, default=3, help="interleaved timing runs")
    parser.add_argument("--baseline", type=Path, help="a rigidsim checkout to compare with")
    parser.add_argument("--only", help="comma-separated scene names to run")
    parser.add_argument("--verbose", action="store_true", help="also print pile settle times")
    parser.add_argument(
        "--sleep", action="store_true", help="when piles of 100 and 500 cubes fall asleep"
    )
    parser.add_argument(
        "--no-ops", dest="ops", action="store_false", help="skip counting operations per step"
    )
    parser.add_argument(
        "--multibody", action="store_true", help="also time pybullet's btMultiBody (labelled)"
    )
    parser.add_argument("--plot", type=Path, default=ROOT / "docs" / "physics_scaling.png")
    args = parser.parse_args()
    bullet = have_pybullet()
    results: dict = {}
    if not args.only_sweep:
        print(
            "ms/step: wall per 0.008 s step; cpu ms: this process's CPU time per step (median "
            "of the repeats);\nratio: wall vs pybullet, cpu rat: CPU time vs "
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
        chosen = set(args.only.split(",")) if args.only else None
        for name, scene in scenes(args.quick):
            if chosen is None or name in chosen:
                run_scene(name, scene, bullet, results, args)
    rows = []
    if args.sweep or args.only_sweep:
        sizes = (10, 30, 100, 300) if args.quick else (10, 30, 100, 300, 1000)
        rows = sweep(sizes, 1.0 if args.quick else 2.0, bullet)
        plot(rows, args.plot)
    if args.sleep:
        sleep_report(bullet)
    report_speed_targets(results)
    report_targets(results, rows)


if __name__ == "__main__":
    main()
