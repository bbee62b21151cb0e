"""``python -m engine.tutorial --jobs N``: groups of tutorial sections in worker processes.

The sections hand objects to each other (``basics`` loads the templates the others use,
the clamp travels from ``kinematic_update`` to the velocity-control sections, the navmesh
sections start where ``embodied_agent`` left the agent) and share one world. To run them at
once without changing a pixel, each worker builds a fresh simulator and runs the tutorial
from the start up to its last section, rendering and encoding only its own sections; the
sections before them run without rendering. Rendering never changes the simulation (a test
checks that ``--no-make-video`` gives the same world bit for bit), so every recorded section
starts from exactly the world of the one-process run and writes exactly the same video.

Scheduling is longest processing time first (Graham's LPT rule): the groups are sorted by
their estimated seconds (own sections plus the physics-only replay of the sections before
them, ``SECTION_SECONDS``) and handed out in that order, each to the first worker that is
free (:func:`engine.batch.run_batch`, ``backend="process"``). There are two groups (see
``GROUPS``): on two cores they run side by side.

Threads: one process already uses more than one core (two render threads for the two
camera groups, a background encoder, ffmpeg). With several workers on few cores those
threads only compete, so each worker renders on ``cores // workers`` threads (at least one)
unless ``RIGIDSIM_RENDER_THREADS`` says otherwise. The encoder is left alone: its settings
must be the same in every mode for the videos to be identical.
"""

from __future__ import annotations

import os
import resource
import tempfile
import threading
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from tqdm.auto import tqdm

from engine.batch import run_batch
from engine.demo import demo_data_path
from engine.tutorial.context import SectionResult
from engine.tutorial.runner import BAR_FORMAT, SECTION_NAMES, SECTIONS, run_sections

# Sections recorded together by one worker. A group replays (physics only) every section
# before its first one, so groups that start late pay for it: the navmesh pair replays the
# whole tutorial before it, and the first eight sections are cheapest in one group that
# replays nothing. The two groups cost about the same (38 and 36 CPU s at 544 x 720 on this
# project's idle machine; as four groups the second half paid about 2 s more in replays),
# and no split of the sections can end before the navmesh pair, which replays everything.
NAVMESH_PAIR = ("embodied_agent_navmesh_sliding", "embodied_agent_navmesh_no_sliding")
GROUPS: tuple[tuple[str, ...], ...] = (
    NAVMESH_PAIR,
    tuple(name for name in SECTION_NAMES if name not in NAVMESH_PAIR),
)
# Wall seconds of each section at 544 x 720 in one process, (recorded, replayed without
# rendering = its physics seconds): a --jobs 1 run on this project's 2-core machine (97 s).
# Only their order matters: they sort the groups, longest first.
SECTION_SECONDS: dict[str, tuple[float, float]] = {
    "basics": (1.8, 0.6),
    "object_user_configurations": (0.0, 0.0),
    "dynamic_control": (4.1, 2.1),
    "kinematic_interactions": (1.6, 0.7),
    "kinematic_update": (0.8, 0.2),
    "velocity_control": (1.3, 0.2),
    "local_velocity_control": (1.1, 0.2),
    "embodied_agent": (34.9, 5.8),
    "embodied_agent_navmesh_sliding": (24.4, 1.4),
    "embodied_agent_navmesh_no_sliding": (26.8, 1.9),
}


def estimated_seconds(group: Sequence[int]) -> float:
    """A group's estimated wall seconds: its own sections recorded, the ones before it
    replayed without rendering."""
    total = 0.0
    for index in range(max(group) + 1):
        recorded, replayed = SECTION_SECONDS[SECTION_NAMES[index]]
        total += recorded if index in group else replayed
    return total


def plan_groups(selected: Sequence[int]) -> list[list[int]]:
    """The section indices of each group that has selected sections, longest group first."""
    groups = []
    for names in GROUPS:
        indices = [SECTION_NAMES.index(name) for name in names]
        chosen = [index for index in indices if index in selected]
        if chosen:
            groups.append(chosen)
    return sorted(groups, key=estimated_seconds, reverse=True)


def render_threads_per_worker(workers: int) -> int:
    """Render threads of each worker: the cores shared out, at least one."""
    return max(1, (os.cpu_count() or 1) // workers)


def run_group(params: dict[str, Any], seed: int) -> dict[str, Any]:
    """Worker side: a fresh simulator runs the tutorial up to the group's last section and
    records the group's sections (``seed`` of the batch is unused: the tutorial's own
    ``params["seed"]`` seeds every group alike). Returns the sections' results and the
    group's wall and CPU seconds (this process and its finished children, e.g. ffmpeg)."""
    settings = dict(params)
    sections = settings.pop("sections")
    threads = settings.pop("render_threads")
    progress_file = settings.pop("progress_file", None)
    if threads is not None:
        os.environ["RIGIDSIM_RENDER_THREADS"] = str(threads)  # read by the new simulator
    wall, cpu = time.perf_counter(), _cpu_seconds()
    report = ProgressWriter(progress_file) if progress_file is not None else None
    results = run_sections(sections, on_progress=report, **settings)
    if report is not None:  # the last frames may have fallen between two writes
        report("done", 0, sum(SECTIONS[index][2] for index in sections), force=True)
    return {
        "sections": results,
        "wall_seconds": time.perf_counter() - wall,
        "cpu_seconds": _cpu_seconds() - cpu,
        "render_threads": threads,
    }


class ProgressWriter:
    """Worker side of the progress: the running section, its frame and the group's world
    seconds done, written to a small file at most every ``interval`` seconds (and at every
    change of section) for :class:`GroupBars` in the parent to read."""

    def __init__(self, path: str, interval: float = 0.25):
        self.path, self.interval = Path(path), interval
        self.last_time, self.last_label = 0.0, ""

    def __call__(self, label: str, frames: int, world_done: float, force: bool = False) -> None:
        now = time.perf_counter()
        if not force and label == self.last_label and now - self.last_time < self.interval:
            return
        self.last_time, self.last_label = now, label
        scratch = self.path.with_suffix(".tmp")
        scratch.write_text(f"{label}\t{frames}\t{world_done:.4f}\n", encoding="utf-8")
        scratch.replace(self.path)  # atomic: the parent never reads half a line


class GroupBars:
    """Parent side: one bar per group, naming the section its worker runs and its frame.

    A thread polls the workers' progress files (:class:`ProgressWriter`) four times a second;
    ``run_batch`` itself shows no bar (it would say ``0/2`` for minutes).
    """

    def __init__(self, groups: Sequence[Sequence[int]], folder: str):
        self.files = [Path(folder) / f"group-{k}.txt" for k in range(len(groups))]
        self.bars = [
            tqdm(
                total=sum(SECTIONS[index][2] for index in group),
                desc=f"worker {k + 1}: starting",
                bar_format="{desc:<44}" + BAR_FORMAT.removeprefix("{desc:<24}"),
                position=k,
            )
            for k, group in enumerate(groups)
        ]
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.poll, name="tutorial-progress", daemon=True)

    def __enter__(self) -> GroupBars:
        self.thread.start()
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.stop.set()
        self.thread.join()
        self.refresh()
        for bar in self.bars:
            bar.close()

    def poll(self) -> None:
        while not self.stop.wait(0.25):
            self.refresh()

    def refresh(self) -> None:
        for k, (path, bar) in enumerate(zip(self.files, self.bars, strict=True)):
            try:
                label, frames, world = path.read_text(encoding="utf-8").rstrip("\n").split("\t")
            except (OSError, ValueError):  # not written yet
                continue
            bar.set_description_str(f"worker {k + 1}: {label}", refresh=False)
            bar.set_postfix_str(f"frame {frames}" if int(frames) else "", refresh=False)
            bar.update(min(float(world), float(bar.total)) - bar.n)


def _cpu_seconds() -> float:
    """User + system CPU seconds of this process and its waited-for children."""
    own, children = (
        resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
    )
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def run_in_parallel(
    selected: Sequence[int],
    jobs: int,
    group_report: list | None = None,
    **settings: Any,
) -> list[SectionResult]:
    """Run the groups of ``selected`` sections on ``jobs`` processes; results in order.

    ``settings``: ``output_dir``, ``make_video``, ``fast``, ``seed``, ``progress``,
    ``keep_observations`` as for :func:`engine.tutorial.runner.run_sections`. With
    ``group_report`` (a list), one dict per group is appended: its sections, estimated,
    wall and CPU seconds and render threads.
    """
    demo_data_path()  # generate the demo dataset once, before the workers read it
    progress = settings.pop("progress", True)
    groups = plan_groups(selected)
    workers = min(jobs, len(groups))
    threads = (
        None if os.environ.get("RIGIDSIM_RENDER_THREADS") else render_threads_per_worker(workers)
    )
    if workers >= (os.cpu_count() or 1):
        # the groups keep every core busy: a render worker process per simulator would
        # only add its overhead (measured: more CPU and wall time with --jobs 2 on 2 cores)
        settings.setdefault("render_processes", 0)
    params = [
        {"sections": group, "progress": False, "render_threads": threads, **settings}
        for group in groups
    ]
    if progress:
        with tempfile.TemporaryDirectory(prefix="rigidsim-tutorial-") as folder:
            for k, group_params in enumerate(params):
                group_params["progress_file"] = str(Path(folder) / f"group-{k}.txt")
            with GroupBars(groups, folder):
                results = run_batch(
                    run_group, params, backend="process", workers=workers, progress=False
                )
        for group_params in params:
            del group_params["progress_file"]  # the error message below prints the params
    else:
        results = run_batch(run_group, params, backend="process", workers=workers, progress=False)
    failed = [r for r in results if not r.ok]
    if failed:
        raise RuntimeError(
            f"tutorial group {failed[0].params['sections']} failed: "
            f"{failed[0].error}\n{failed[0].traceback or ''}"
        )
    if group_report is not None:
        for group, result in zip(groups, results, strict=True):
            group_report.append(
                {
                    "sections": [SECTION_NAMES[index] for index in group],
                    "estimated_seconds": round(estimated_seconds(group), 1),
                    "wall_seconds": round(result.value["wall_seconds"], 2),
                    "cpu_seconds": round(result.value["cpu_seconds"], 2),
                    "render_threads": result.value["render_threads"],
                    "worker": result.worker,
                }
            )
    sections = [section for result in results for section in result.value["sections"]]
    return sorted(sections, key=lambda section: SECTION_NAMES.index(section.name))
