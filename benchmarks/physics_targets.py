"""The targets and quality gates of ``bench_physics.py``: each printed with whether it is met.

Speed: CPU time per 0.008 s step as a ratio to pybullet's btRigidBody in the same run, and
NumPy operations per step (``op_counter``). Quality: stacks and pyramids stand, nothing sinks
deeper than the 2 cm speculative margin, no two cubes overlap deeper than 2 cm, piles come
to rest, and the CPU cost per body stays flat from 100 cubes up (within 15 %). ``results``
maps a scene name to its report dict (``bench_physics.run_scene``); ``rows`` are the
scaling sweep's ``(n, cpu ms, pybullet cpu ms, shares)``.
"""

from __future__ import annotations

import numpy as np


def top_drift(result: dict) -> float:
    """Horizontal (x, z) distance the top cube of a stack moved from its start, m."""
    return float(np.linalg.norm((result["final"][-1] - result["start"][-1])[[0, 2]]))


def _line(text: str, value: str, ok: bool) -> None:
    print(f"  [{'met   ' if ok else 'MISSED'}] {text}: {value}")


def report_speed_targets(results) -> None:
    """The speed targets: CPU per step as ratios to pybullet's btRigidBody in the same run,
    and the NumPy operations per step of plane-column-100 (``op_counter``)."""
    print(
        "\nSpeed targets (CPU time per 0.008 s step vs pybullet btRigidBody, medians of the "
        "repeats; NumPy operations per step):"
    )
    for name, limit in (
        ("column-10", 25.0),
        ("plane-column-100", 4.0),
        ("plane-column-500", 2.0),
        ("apartment-30", 4.0),
    ):
        if name in results:
            r = results[name]
            _line(
                f"{name}: <= {limit:g}x pybullet", f"{r['cpu_ratio']:.2f}x", r["cpu_ratio"] <= limit
            )
    r = results.get("plane-column-100")
    if r and r.get("ops") is not None:
        _line(
            "plane-column-100: <= 2,000 operations per step", f"{r['ops']:,.0f}", r["ops"] <= 2000
        )
    r = results.get("column-10")
    if r and r["base_ratio"] is not None:
        print(f"  column-10: {r['base_ratio']:.2f}x the baseline checkout's step")


def report_targets(results, rows) -> None:
    """The quality gates (unchanged from issue 13) and the scaling target."""
    print("\nQuality gates:")
    line = _line
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
        drift = top_drift(r)
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
    if "stack-20" in results:
        r = results["stack-20"]
        drift = top_drift(r)
        line(
            f"stack-20 stands {r['seconds']:.0f} s awake (top above 3.8 m)",
            f"top drift {drift * 100:.2f} cm, top at {r['final'][-1, 1]:.3f} m",
            r["final"][-1, 1] > 3.8,
        )
    if "pyramid-10" in results:
        r = results["pyramid-10"]
        moved = np.abs(r["final"] - r["start"]).max()
        line(
            f"pyramid-10 stands {r['seconds']:.0f} s awake (every cube within 5 cm)",
            f"max displacement {moved * 100:.2f} cm",
            moved < 0.05,
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
            "no two cubes overlap deeper than 2 cm (worst scene; impacts of the 5 m column)",
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
