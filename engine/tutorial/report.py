"""The tutorial job's summary: a table on the terminal and ``summary.json`` beside the videos.

Per section: simulated world time (s), frames (``step_physics(1/60)`` calls, one video frame
each), wall time (s) split into physics (stepping and control code), rendering (three
sensors) and encoding (frame composition and H.264), and the video's path.
``summary.json`` also holds each section's physical outcomes (final poses, world frame,
meters, quaternions ``[x, y, z, w]``), which the tests read.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from typing import Any

from engine.tutorial.context import SectionResult

COLUMNS = ("section", "world s", "frames", "wall s", "physics", "render", "encode", "video")
# one line under the table: what its columns mean
SUMMARY_LEGEND = (
    "world s: simulated seconds; frames: video frames, one step_physics(1/60) each; "
    "wall s = physics (stepping, control code) + render (three sensors) + encode "
    "(composing frames, H.264), seconds of the process that ran the section"
)


def summary_rows(results: Sequence[SectionResult]) -> list[tuple[str, ...]]:
    """One row of formatted cells per section, then a total row."""
    rows: list[tuple[str, ...]] = []
    for r in results:
        t = r.timings
        cells: tuple[str, ...] = (r.name, f"{r.world_time:.3f}", str(r.frames), f"{t.total:.2f}")
        cells += (f"{t.physics:.2f}", f"{t.rendering:.2f}", f"{t.encoding:.2f}")
        rows.append(cells + (r.video_path or "-",))
    total = [sum(getattr(r.timings, k) for r in results) for k in ("total", "physics")]
    total += [sum(getattr(r.timings, k) for r in results) for k in ("rendering", "encoding")]
    world, frames = sum(r.world_time for r in results), sum(r.frames for r in results)
    rows.append(("total", f"{world:.3f}", str(frames), *(f"{x:.2f}" for x in total), ""))
    return rows


def format_summary(results: Sequence[SectionResult]) -> str:
    """The summary table as aligned plain text."""
    rows = [COLUMNS, *summary_rows(results)]
    widths = [max(len(row[i]) for row in rows) for i in range(len(COLUMNS))]
    lines = []
    for index, row in enumerate(rows):
        # text columns (section, video) align left, numbers right
        cells = [
            cell.ljust(width) if column in (0, 7) else cell.rjust(width)
            for column, (cell, width) in enumerate(zip(row, widths, strict=True))
        ]
        lines.append("  ".join(cells).rstrip())
        if index == 0 or index == len(rows) - 2:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


def summary_dict(results: Sequence[SectionResult], settings: dict[str, Any]) -> dict[str, Any]:
    """Everything of the run as plain JSON values (``settings``: resolution, seed, ...)."""
    sections = []
    for r in results:
        t = r.timings
        timings = {"total": t.total, "physics": t.physics, "rendering": t.rendering}
        timings["encoding"] = t.encoding
        timings["encoding_background"] = t.encoding_background
        sections.append(
            {
                "name": r.name,
                "frames": r.frames,
                "world_time": r.world_time,
                "video": r.video_path,
                "timings": timings,
                "outcomes": r.outcomes,
            }
        )
    return {"settings": settings, "sections": sections}


def write_summary(
    results: Sequence[SectionResult], settings: dict[str, Any], output_dir: str
) -> str:
    """Write ``<output_dir>/summary.json`` and return its path."""
    os.makedirs(output_dir, exist_ok=True)
    path = os.path.join(output_dir, "summary.json")
    with open(path, "w", encoding="utf-8") as handle:
        json.dump(summary_dict(results, settings), handle, indent=1)
    return path
