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
import random
import time
from collections.abc import Callable, Sequence
from functools import partial

from tqdm.auto import tqdm

import engine as habitat_sim
from engine.demo import demo_data_path
from engine.tutorial.context import SectionResult, TutorialContext
from engine.tutorial.recording import SectionRecorder, VideoSpec
from engine.tutorial.report import SUMMARY_LEGEND, format_summary, write_summary
from engine.tutorial.scene_setup import (
    FAST_RESOLUTION,
    TUTORIAL_RESOLUTION,
    make_configuration,
    place_agent,
)
from engine.tutorial.sections_agent import embodied_agent, embodied_agent_navmesh
from engine.tutorial.sections_control import (
    kinematic_update,
    local_velocity_control,
    velocity_control,
)
from engine.tutorial.sections_objects import (
    basics,
    dynamic_control,
    kinematic_interactions,
    object_user_configurations,
)

# (progress label, section function, simulated world seconds) in the tutorial's order.
SECTIONS: list[tuple[str, Callable[[TutorialContext], SectionResult], float]] = [
    ("basics", basics, 1.5),
    ("user attributes", object_user_configurations, 0.0),
    ("dynamic control", dynamic_control, 3.0),
    ("kinematic interactions", kinematic_interactions, 1.5),
    ("kinematic update", kinematic_update, 1.0),
    ("velocity control", velocity_control, 2.0),
    ("local velocity control", local_velocity_control, 1.5),
    ("embodied agent", embodied_agent, 10.0),
    ("navmesh, sliding", partial(embodied_agent_navmesh, allow_sliding=True), 6.0),
    ("navmesh, no sliding", partial(embodied_agent_navmesh, allow_sliding=False), 6.0),
]
# The name each section reports (SectionResult.name, summary.json), in the same order.
SECTION_NAMES = [
    "basics",
    "object_user_configurations",
    "dynamic_control",
    "kinematic_interactions",
    "kinematic_update",
    "velocity_control",
    "local_velocity_control",
    "embodied_agent",
    "embodied_agent_navmesh_sliding",
    "embodied_agent_navmesh_no_sliding",
]


# progress in simulated world seconds and video frames, e.g.
# "basics                   60%|######    | 0.90/1.50 world s, frame 54 [00:01]"
BAR_FORMAT = (
    "{desc:<24}{percentage:3.0f}%|{bar:30}| {n:.2f}/{total:.2f} world s{postfix} [{elapsed}]"
)
# ProgressFn(section label, frames recorded in it, world seconds done over the selected
# sections): how a worker process of --jobs N reports to the parent's bars.
ProgressFn = Callable[[str, int, float], object]


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
        from engine.tutorial.parallel import run_in_parallel  # it imports this module

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


def select_sections(names: Sequence[str] | None) -> list[int]:
    """Indices into ``SECTIONS`` of the named sections (all when ``names`` is None)."""
    if names is None:
        return list(range(len(SECTIONS)))
    unknown = [name for name in names if name not in SECTION_NAMES]
    if unknown or not names:
        raise ValueError(f"unknown sections {unknown or names!r}; choose from {SECTION_NAMES}")
    return sorted({SECTION_NAMES.index(name) for name in names})


def run_sections(
    selected: Sequence[int],
    output_dir: str,
    make_video: bool = True,
    fast: bool = False,
    seed: int = 0,
    progress: bool = True,
    keep_observations: bool = False,
    render_processes: int | None = None,
    on_progress: ProgressFn | None = None,
) -> list[SectionResult]:
    """Run sections ``0 .. max(selected)`` in order on one simulator; record those in
    ``selected`` and return their results.

    The others run without rendering (rendering never changes the simulation), so every
    recorded section starts from exactly the world the full tutorial would give it.
    ``render_processes`` sets the renderer's worker processes (None: its default).
    ``on_progress`` is called at every recorded frame and when a replayed section starts.
    """
    if make_video:
        os.makedirs(output_dir, exist_ok=True)
    resolution = FAST_RESOLUTION if fast else TUTORIAL_RESOLUTION
    data_path = str(demo_data_path())
    with habitat_sim.Simulator(make_configuration(data_path, resolution, seed)) as sim:
        if render_processes is not None:
            sim.get_renderer().processes = render_processes
        place_agent(sim)
        simulate_only = partial(_new_recorder, sim, output_dir, False, False, None)
        context = TutorialContext(sim, data_path, simulate_only, random.Random(seed))
        results = []
        done = 0.0  # world seconds of the recorded sections already finished
        for index, (label, section, world_seconds) in enumerate(SECTIONS[: max(selected) + 1]):
            if index not in selected:  # a prerequisite: simulate only
                if on_progress is not None:
                    on_progress(f"{label} (replay, no video)", 0, done)
                context.new_recorder = simulate_only
                section(context)
                continue
            bar = tqdm(total=world_seconds, desc=label, bar_format=BAR_FORMAT, disable=not progress)
            with bar:
                advance = SectionProgress(bar, label, done, on_progress)
                context.new_recorder = partial(
                    _new_recorder, sim, output_dir, make_video, keep_observations, advance
                )
                results.append(section(context))
            done += world_seconds
    return results


class SectionProgress:
    """Per-frame progress of one recorded section: its bar and the ``on_progress`` report."""

    def __init__(self, bar: tqdm, label: str, done_before: float, report: ProgressFn | None):
        self.bar, self.label, self.report = bar, label, report
        self.done_before = done_before  # world seconds of the sections recorded before it
        self.frames = 0
        self.world = 0.0

    def __call__(self, world_dt: float) -> None:
        """One frame of ``world_dt`` simulated seconds (the last may overshoot: clamped)."""
        self.frames += 1
        step = min(world_dt, max(float(self.bar.total) - self.world, 0.0))
        self.world += step
        self.bar.set_postfix_str(f"frame {self.frames}", refresh=False)
        self.bar.update(step)
        if self.report is not None:
            self.report(self.label, self.frames, self.done_before + self.world)


def _new_recorder(
    sim: habitat_sim.Simulator,
    output_dir: str,
    make_video: bool,
    keep_observations: bool,
    on_frame: Callable[[float], object] | None,
    video: VideoSpec | None,
) -> SectionRecorder:
    """The recorder of one section: streams its video when ``make_video`` is on."""
    if not make_video:
        video = None
    path = os.path.join(output_dir, video.name + ".mp4") if video is not None else None
    return SectionRecorder(sim, video, path, keep_observations=keep_observations, on_frame=on_frame)


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
