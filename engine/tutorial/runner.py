"""The tutorial's sections in order, and running a selection of them on one simulator.

:data:`SECTIONS` lists Habitat's managed rigid object tutorial section by section (progress
label, section function, simulated world seconds); :func:`run_sections` runs sections
``0 .. max(selected)`` in order on one simulator and records the selected ones. Both
:mod:`engine.tutorial.cli` (one process) and :mod:`engine.tutorial.parallel` (groups of
sections in worker processes) call it.
"""

from __future__ import annotations

import os
import random
from collections.abc import Callable, Sequence
from functools import partial

from tqdm.auto import tqdm

import engine as habitat_sim
from engine.demo import demo_data_path
from engine.tutorial.context import SectionResult, TutorialContext
from engine.tutorial.recording import SectionRecorder, VideoSpec
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
