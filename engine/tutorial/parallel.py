"""``python -m engine.tutorial --jobs N``: groups of tutorial sections in worker processes.

The sections hand objects to each other (``basics`` loads the templates the others use,
the clamp travels from ``kinematic_update`` to the velocity-control sections, the navmesh
sections start where ``embodied_agent`` left the agent) and share one world. To run them at
once without changing a pixel, each worker builds a fresh simulator and runs the tutorial
from the start up to its last section, rendering and encoding only its own sections; the
sections before them run without rendering. Rendering never changes the simulation (a test
checks that ``--no-make-video`` gives the same world bit for bit), so every recorded section
starts from exactly the world of the one-process run and writes exactly the same video.

The price is the physics of those prerequisite sections, a few seconds per group
(rendering and encoding are about 90 % of the job). The groups are ordered longest first and
run with :func:`engine.batch.run_batch` (``backend="process"``): on two cores the two
longest groups start together and the short ones fill in behind them.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

from engine.batch import run_batch
from engine.demo import demo_data_path
from engine.tutorial.cli import SECTION_NAMES, run_sections
from engine.tutorial.context import SectionResult

# Sections recorded together by one worker, longest group first (wall seconds at 544 x 720
# before rendering was sped up: 36 + 6 s of prerequisites, 29 + 3, 19 + 2, 17).
GROUPS: tuple[tuple[str, ...], ...] = (
    ("embodied_agent_navmesh_sliding", "embodied_agent_navmesh_no_sliding"),
    ("embodied_agent",),
    ("kinematic_interactions", "kinematic_update", "velocity_control", "local_velocity_control"),
    ("basics", "object_user_configurations", "dynamic_control"),
)


def plan_groups(selected: Sequence[int]) -> list[list[int]]:
    """The section indices of each group that has selected sections, longest group first."""
    groups = []
    for names in GROUPS:
        indices = [SECTION_NAMES.index(name) for name in names]
        chosen = [index for index in indices if index in selected]
        if chosen:
            groups.append(chosen)
    return groups


def run_group(params: dict[str, Any], seed: int) -> list[SectionResult]:
    """Worker side: a fresh simulator runs the tutorial up to the group's last section and
    records the group's sections (``seed`` of the batch is unused: the tutorial's own
    ``params["seed"]`` seeds every group alike)."""
    settings = dict(params)
    sections = settings.pop("sections")
    return run_sections(sections, **settings)


def run_in_parallel(selected: Sequence[int], jobs: int, **settings: Any) -> list[SectionResult]:
    """Run the groups of ``selected`` sections on ``jobs`` processes; results in order.

    ``settings``: ``output_dir``, ``make_video``, ``fast``, ``seed``, ``progress``,
    ``keep_observations`` as for :func:`engine.tutorial.cli.run_sections`.
    """
    demo_data_path()  # generate the demo dataset once, before the workers read it
    progress = settings.pop("progress", True)
    groups = plan_groups(selected)
    workers = min(jobs, len(groups))
    if workers >= (os.cpu_count() or 1):
        # the groups keep every core busy: a render worker process per simulator would
        # only add its overhead (measured: more CPU and wall time with --jobs 2 on 2 cores)
        settings.setdefault("render_processes", 0)
    params = [{"sections": group, "progress": False, **settings} for group in groups]
    results = run_batch(run_group, params, backend="process", workers=workers, progress=progress)
    failed = [r for r in results if not r.ok]
    if failed:
        raise RuntimeError(
            f"tutorial group {failed[0].params['sections']} failed: "
            f"{failed[0].error}\n{failed[0].traceback or ''}"
        )
    sections = [section for result in results for section in result.value]
    return sorted(sections, key=lambda section: SECTION_NAMES.index(section.name))
