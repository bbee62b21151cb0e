"""``python -m engine.tutorial``: run Habitat's managed rigid object tutorial end to end.

Runs every section of the tutorial in order on the demo apartment, with a progress bar per
section (in simulated world seconds), writes the nine videos and a ``summary.json`` to
``--output-dir`` and prints a table: world time, frames and wall time per section, split into
physics, rendering and encoding (see :mod:`engine.tutorial.recording`). ``--jobs N`` runs
groups of sections in N worker processes (:mod:`engine.tutorial.parallel`); the videos are
the same bit for bit.

Example
-------
    python -m engine.tutorial --output-dir ./tutorial_output
    python -m engine.tutorial --fast --no-make-video --seed 3
    python -m engine.tutorial --jobs 1 --sections basics,dynamic_control
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Sequence

from engine.tutorial.context import SectionResult
from engine.tutorial.parallel import run_in_parallel
from engine.tutorial.report import SUMMARY_LEGEND, format_summary, write_summary
from engine.tutorial.runner import (
    SECTION_NAMES,
    SECTIONS,
    run_sections,
    select_sections,
)
from engine.tutorial.scene_setup import FAST_RESOLUTION, TUTORIAL_RESOLUTION

__all__ = ["SECTIONS", "SECTION_NAMES", "main", "parse_args", "run_sections", "run_tutorial"]


def parse_args(argv: Sequence[str] | None = None) -> argparse.Namespace:
    """Command-line options of the tutorial job."""
    parser = argparse.ArgumentParser(
        prog="python -m engine.tutorial",
        description="Run Habitat's managed rigid object tutorial end to end on the demo "
        "apartment: nine videos, summary.json and a timing table.",
    )
    parser.add_argument(
        "--output-dir", default="./tutorial_output", help="folder for the videos and summary.json"
    )
    parser.add_argument(
        "--no-make-video", dest="make_video", action="store_false", help="simulate only"
    )
    height, width = FAST_RESOLUTION
    fast_help = f"render {height} x {width} instead of 544 x 720 (same simulated durations)"
    parser.add_argument("--fast", action="store_true", help=fast_help)
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    parser.add_argument(
        "--jobs",
        type=int,
        default=os.cpu_count() or 1,
        help="worker processes running groups of sections at once (default: all cores); "
        "the videos are the same bit for bit whatever the number",
    )
    parser.add_argument(
        "--sections",
        type=lambda text: text.split(","),
        default=None,
        help="comma-separated section names to record (default: all): " + ", ".join(SECTION_NAMES),
    )
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error(f"--jobs must be >= 1, got {args.jobs}")
    return args


def run_tutorial(
    output_dir: str,
    make_video: bool = True,
    fast: bool = False,
    seed: int = 0,
    progress: bool = True,
    keep_observations: bool = False,
    jobs: int = 1,
    sections: Sequence[str] | None = None,
    group_report: list | None = None,
) -> list[SectionResult]:
    """Run the tutorial's sections and return their results in the tutorial's order.

    Parameters
    ----------
    output_dir : str
        Folder for the ``<video>.mp4`` files (created if missing).
    make_video : bool
        Render and encode the videos; False only simulates (frames are still counted).
    fast : bool
        Render at ``FAST_RESOLUTION`` instead of the tutorial's 544 x 720.
    seed : int
        Seeds the simulator and the navmesh section's random turns.
    progress : bool
        Show a tqdm bar per section (per group of sections with ``jobs > 1``).
    keep_observations : bool
        Keep every observation dict in the results (memory heavy at full resolution).
    jobs : int
        Worker processes; with more than one, groups of sections run at once
        (:mod:`engine.tutorial.parallel`) and give the same videos bit for bit.
    sections : sequence of str or None
        Names of the sections to run (``SECTION_NAMES``); default all. The sections before
        them still run, without video, to build the world they start from.
    group_report : list or None
        With ``jobs > 1``: gets one dict per group of sections (estimated, wall and CPU
        seconds of its worker, render threads).
    """
    selected = select_sections(sections)
    if jobs > 1:
        return run_in_parallel(
            selected,
            jobs,
            group_report,
            output_dir=output_dir,
            make_video=make_video,
            fast=fast,
            seed=seed,
            progress=progress,
            keep_observations=keep_observations,
        )
    return run_sections(selected, output_dir, make_video, fast, seed, progress, keep_observations)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``python -m engine.tutorial``; returns the process exit code."""
    args = parse_args(argv)
    start = time.perf_counter()
    groups: list[dict] = []
    results = run_tutorial(
        args.output_dir,
        args.make_video,
        args.fast,
        args.seed,
        progress=not args.quiet,
        jobs=args.jobs,
        sections=args.sections,
        group_report=groups,
    )
    resolution = FAST_RESOLUTION if args.fast else TUTORIAL_RESOLUTION
    settings = {"resolution": list(resolution), "seed": args.seed, "make_video": args.make_video}
    settings["jobs"] = args.jobs
    settings["wall_time"] = time.perf_counter() - start
    if groups:
        settings["groups"] = groups
    summary_path = write_summary(results, settings, args.output_dir)
    print(format_summary(results))
    print(SUMMARY_LEGEND)
    for group in groups:  # --jobs N: what each worker did, in the order they started
        print(
            f"group {', '.join(group['sections'])}: {group['wall_seconds']:.1f} s wall, "
            f"{group['cpu_seconds']:.1f} s CPU (estimated {group['estimated_seconds']:.0f} s), "
            f"{group['render_threads'] or 'default'} render thread(s), worker {group['worker']}"
        )
    print(f"whole job: {settings['wall_time']:.1f} s wall; summary: {summary_path}")
    return 0
