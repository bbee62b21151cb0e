"""The split row of a shared full render moves toward balance (engine.sensors.frame_sharing)."""

from __future__ import annotations

from engine.sensors.frame_sharing import PER_FRAME_STAGES, next_split, rows_there
from render.camera import Camera
from render.frame import band_rows

CAMERA = Camera((544, 720))
STEP = band_rows(CAMERA)  # 22 rows of 720 pixels


def worker_times(per_row_ms: float, rows: int, per_frame_ms: float = 2.0) -> dict:
    """Stage times (ms) of a worker that spent ``per_row_ms`` on each of its ``rows``."""
    times = {stage: per_frame_ms / len(PER_FRAME_STAGES) for stage in PER_FRAME_STAGES}
    times["shade"] = per_row_ms * rows
    return times


def test_a_late_worker_gives_rows_here_and_an_early_one_takes_them():
    split = 10 * STEP
    rows = CAMERA.height - split
    # worker busy 2 + 0.05 * 324 = 18.2 ms; here 12 ms: it was 6.2 ms later
    later = next_split(split, CAMERA, worker_times(0.05, rows), busy_here=0.012)
    # half the surplus over twice a row's time: 0.5 * 6.2 / 0.1 = 31 rows, about 1.4 bands
    assert later == split + STEP
    earlier = next_split(split, CAMERA, worker_times(0.05, rows), busy_here=0.030)
    assert earlier < split and earlier % STEP == 0
    balanced = next_split(split, CAMERA, worker_times(0.05, rows), busy_here=0.0182)
    assert balanced == split


def test_a_measured_wait_is_the_worker_lateness():
    split = 10 * STEP
    times = worker_times(0.05, CAMERA.height - split)
    # by its stage times the worker was early, but this process waited 9 ms for its reply
    assert next_split(split, CAMERA, times, busy_here=0.030, waited=0.009) > split
    assert next_split(split, CAMERA, times, busy_here=0.030, waited=0.0001) < split


def test_the_split_stays_whole_bands_inside_the_frame():
    times = worker_times(0.05, CAMERA.height)
    first = next_split(0, CAMERA, times, busy_here=0.0)  # 27.2 ms late: 136 rows
    assert first == round(136 / STEP) * STEP
    very_late = next_split(0, CAMERA, times, busy_here=0.0, waited=1.0)
    assert very_late == (CAMERA.height // STEP - 1) * STEP  # the worker keeps a band
    assert next_split(STEP, CAMERA, worker_times(0.05, 500), busy_here=1.0) == 0
    assert rows_there(0, "full", CAMERA) is None  # not shared: the worker renders all
    assert rows_there(3 * STEP, "full", CAMERA) == (3 * STEP, CAMERA.height)
    assert rows_there(3 * STEP, "layer", CAMERA) is None
