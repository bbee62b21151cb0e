"""The main job's console: bars that name the running section and its frame.

No simulation runs here: the progress pieces are fed by hand (the job's own tests run it
with ``--quiet``).
"""

from __future__ import annotations

import io
from pathlib import Path

from tqdm import tqdm

from engine.tutorial.parallel import GroupBars, ProgressWriter
from engine.tutorial.report import COLUMNS, SUMMARY_LEGEND
from engine.tutorial.runner import BAR_FORMAT, SECTIONS, SectionProgress


def test_section_bar_counts_frames_and_clamps_world_time() -> None:
    reports: list[tuple[str, int, float]] = []
    stream = io.StringIO()
    with tqdm(total=0.05, desc="basics", bar_format=BAR_FORMAT, file=stream) as bar:
        advance = SectionProgress(bar, "basics", 1.5, lambda *r: reports.append(r))
        for _ in range(4):
            advance(1 / 60)  # the 4th frame overshoots 0.05 s: clamped
    assert [r[1] for r in reports] == [1, 2, 3, 4]
    assert reports[-1][2] == 1.5 + 0.05  # world seconds over the group: before + this one
    assert "frame 4" in stream.getvalue()
    assert "0.05/0.05 world s" in stream.getvalue()


def test_worker_bars_show_the_section_and_frame_the_worker_reported(tmp_path: Path) -> None:
    groups = [[8, 9], [0, 1, 2]]
    bars = GroupBars(groups, str(tmp_path))
    try:
        ProgressWriter(str(tmp_path / "group-0.txt"))("navmesh, sliding", 120, 2.0)
        ProgressWriter(str(tmp_path / "group-1.txt"))("basics (replay, no video)", 0, 0.0)
        bars.refresh()
        first, second = (str(bar) for bar in bars.bars)
        assert "worker 1: navmesh, sliding" in first and "frame 120" in first
        assert f"2.00/{SECTIONS[8][2] + SECTIONS[9][2]:.2f} world s" in first
        assert "worker 2: basics (replay, no video)" in second and "frame" not in second
    finally:
        for bar in bars.bars:
            bar.close()


def test_a_throttled_writer_still_reports_a_new_section_at_once(tmp_path: Path) -> None:
    path = tmp_path / "group-0.txt"
    write = ProgressWriter(str(path), interval=3600.0)
    write("basics", 1, 0.01)
    write("basics", 2, 0.02)  # within the interval: skipped
    assert path.read_text().split("\t")[1] == "1"
    write("dynamic control", 1, 1.52)  # a new section: written
    assert path.read_text().startswith("dynamic control\t1\t")
    write("dynamic control", 2, 1.53, force=True)
    assert path.read_text().split("\t")[1] == "2"


def test_the_legend_explains_every_numeric_column() -> None:
    for column in COLUMNS[1:7]:
        assert column in SUMMARY_LEGEND
