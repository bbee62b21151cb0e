"""Time the tutorial notebook cell by cell: wall, physics, render and encode seconds.

Run on demand (not a test)::

    .venv/bin/python benchmarks/bench_notebook.py                     # this checkout
    .venv/bin/python benchmarks/bench_notebook.py --baseline /tmp/old  # old checkout, then this
    .venv/bin/python benchmarks/bench_notebook.py --fast               # 96 x 128 frames

Executes ``notebooks/managed_rigid_object_tutorial.ipynb`` top to bottom with nbclient in a
fresh kernel whose ``PYTHONPATH`` is the checkout being measured (full size: three 544 x 720
sensors, unless ``--fast``), in a temporary folder. A first injected cell wraps
``Simulator.step_physics`` (physics), ``Simulator.get_sensor_observations`` (render) and
``render.video.make_video`` (encode: composing, ffmpeg and the inline display) with
timers; after every notebook cell an injected cell prints and resets them, with the CPU
seconds the cell used (the kernel's threads and its finished children, ffmpeg): on a shared
machine CPU time is steadier than wall time. Wall time per cell comes from nbclient's
execution timestamps (the CPU of living child processes, such as the render worker, is read
with psutil when it is installed). With ``--baseline`` the other checkout's
notebook runs first, then this one, in the same invocation (compare ratios: the machine is
shared).
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from datetime import datetime
from pathlib import Path

import nbformat
from nbclient import NotebookClient

REPO = Path(__file__).resolve().parents[1]
NOTEBOOK = "notebooks/managed_rigid_object_tutorial.ipynb"
MARK = "RIGIDSIM_BENCH "

INSTALL_TIMERS = """
import resource as _resource
import time as _time
import engine as _engine
import render.video as _video

_bench = {"physics": 0.0, "render": 0.0, "encode": 0.0}

def _cpu_seconds():
    # CPU time of the kernel (all threads), of its finished children (ffmpeg) and of its
    # living ones (the render worker process; needs psutil, else they count when they end)
    children = _resource.getrusage(_resource.RUSAGE_CHILDREN)
    living = 0.0
    try:
        import psutil as _psutil

        for child in _psutil.Process().children(recursive=True):
            try:
                times = child.cpu_times()
                living += times.user + times.system
            except _psutil.Error:
                pass
    except ImportError:
        pass
    return _time.process_time() + children.ru_utime + children.ru_stime + living

_cpu_start = _cpu_seconds()

def _timed(function, key):
    def wrapper(*args, **kwargs):
        start = _time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            _bench[key] += _time.perf_counter() - start
    return wrapper

_engine.Simulator.step_physics = _timed(_engine.Simulator.step_physics, "physics")
_engine.Simulator.get_sensor_observations = _timed(
    _engine.Simulator.get_sensor_observations, "render")
_video.make_video = _timed(_video.make_video, "encode")
"""

REPORT_TIMERS = """
import json as _json
_bench["cpu"] = _cpu_seconds() - _cpu_start
print("RIGIDSIM_BENCH " + _json.dumps(_bench))
_bench.update(physics=0.0, render=0.0, encode=0.0)
_cpu_start = _cpu_seconds()
"""


def cell_label(source: str, index: int) -> str:
    """The cell's ``# [section]`` tag, else its first line."""
    for line in source.splitlines():
        line = line.strip("# ").strip()
        if line.startswith("[") and line.endswith("]"):
            return line.strip("[]")
    first = source.strip().splitlines()[0] if source.strip() else ""
    return f"cell {index}: {first[:30]}"


def run_notebook(root: Path, fast: bool, timeout: int = 1800) -> list[dict]:
    """Execute ``root``'s notebook; per code cell: label, wall, physics, render, encode (s)."""
    notebook = nbformat.read(root / NOTEBOOK, as_version=4)
    cells = [nbformat.v4.new_code_cell(INSTALL_TIMERS)]
    labels = []
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type != "code":
            continue
        cells.append(cell)
        cells.append(nbformat.v4.new_code_cell(REPORT_TIMERS))
        labels.append(cell_label(cell.source, index))
    notebook.cells = cells
    os.environ["PYTHONPATH"] = str(root)
    os.environ["RIGIDSIM_FAST"] = "1" if fast else "0"
    os.environ.setdefault("MPLBACKEND", "Agg")
    with tempfile.TemporaryDirectory() as work:
        client = NotebookClient(
            notebook, timeout=timeout, kernel_name="python3",
            resources={"metadata": {"path": work}},
        )  # fmt: skip
        client.execute()
    rows = []
    for k, label in enumerate(labels):
        cell, report = notebook.cells[1 + 2 * k], notebook.cells[2 + 2 * k]
        stamps = cell.metadata.get("execution", {})
        begin = datetime.fromisoformat(stamps["iopub.execute_input"].replace("Z", "+00:00"))
        end = datetime.fromisoformat(stamps["shell.execute_reply"].replace("Z", "+00:00"))
        text = "".join(o.get("text", "") for o in report.outputs if o.output_type == "stream")
        timers = json.loads(text.split(MARK, 1)[1].splitlines()[0])
        rows.append({"cell": label, "wall": (end - begin).total_seconds(), **timers})
    return rows


def format_rows(title: str, rows: list[dict]) -> str:
    """A markdown table of the rows with a total line."""
    lines = [
        f"{title}",
        "",
        "| cell | wall s | physics s | render s | encode s | CPU s |",
        "|---|---|---|---|---|---|",
    ]
    for row in rows:
        if row["wall"] >= 0.05:
            lines.append(
                f"| {row['cell']} | {row['wall']:.1f} | {row['physics']:.1f} | "
                f"{row['render']:.1f} | {row['encode']:.1f} | {row['cpu']:.1f} |"
            )
    keys = ("wall", "physics", "render", "encode", "cpu")
    total = {k: sum(r[k] for r in rows) for k in keys}
    lines.append(
        f"| **total** | **{total['wall']:.1f}** | {total['physics']:.1f} | "
        f"{total['render']:.1f} | {total['encode']:.1f} | {total['cpu']:.1f} |"
    )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", type=Path, help="another checkout to run first")
    parser.add_argument("--fast", action="store_true", help="96 x 128 frames")
    parser.add_argument("--json", type=Path, help="also write the rows to this file")
    args = parser.parse_args()
    results = {}
    if args.baseline is not None:
        results["baseline"] = run_notebook(args.baseline.resolve(), args.fast)
        print(format_rows(f"baseline: {args.baseline}", results["baseline"]), flush=True)
    results["this checkout"] = run_notebook(REPO, args.fast)
    print(format_rows(f"this checkout: {REPO}", results["this checkout"]))
    if args.json is not None:
        args.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
