"""How a full render is shared between the simulator's process and the render worker, and
how a frame's parts become observations.

A full render of the worker's camera group is split at an image row: this process renders
rows ``0 .. split - 1`` and the worker the rest (``render_frame(rows=)``: each rasterizes
and shades only its rows). ``next_split`` moves the split from frame to frame so that both
finish together, a damped step toward balance:

    move = 1/2 * surplus / (2 * per_row)

``surplus`` (s) is how much later the worker finished than this process: the time this
process waited for the worker's reply when it waited, else the worker's stage times minus
this process's busy time. ``per_row`` (s) is the worker's row-proportional time (its
rasterization and shading; the per-frame stages, vertex transform to shading setup, are
paid by both processes) divided by its rows. A row moved from there to here shifts about
twice its time between the two, hence the 2. The split stays a whole number of shading
bands (``render.frame.band_rows``).

Observations are fresh arrays (callers keep them): ``copy_out`` copies the buffers a group's
sensors read, or only their top rows (the part this process rendered, copied while the
worker may still be rendering), and ``copy_rows`` adds the worker's rows.
"""

from __future__ import annotations

import numpy as np

from engine.sensors.cameras import CameraSensor, SensorType
from render.camera import Camera
from render.frame import FrameBuffers, band_rows
from render.settings import DEFAULT_SETTINGS, RenderSettings

#: seconds of waiting for the worker's reply beyond which the worker was the later one
WAITED_FOR_THE_WORKER = 0.0003
#: stages of ``render_frame`` (its ``timings``) whose cost does not depend on the rows drawn
PER_FRAME_STAGES = ("transform", "cull", "assemble + clip", "setup", "shade setup")
#: the FrameBuffers field each sensor type reads (other types: the semantic ids)
_BUFFER_OF = {SensorType.COLOR: "rgba", SensorType.DEPTH: "depth"}


def next_split(
    split: int,
    camera: Camera,
    worker_timings: dict,
    busy_here: float,
    waited: float = 0.0,
    settings: RenderSettings = DEFAULT_SETTINGS,
) -> int:
    """The split row of the next frame (see the module docstring).

    ``split``: this frame's (rows ``0 .. split - 1`` rendered here); ``worker_timings``:
    the worker's ``render_frame`` stage times (ms); ``busy_here``: seconds this process
    spent rendering its part and copying it out; ``waited``: seconds it then waited for
    the worker's reply; ``settings``: the render's (their shading bands).
    """
    busy_there = sum(worker_timings.values()) / 1e3
    rows_there = camera.height - split
    if rows_there <= 0:
        return split
    per_frame = sum(worker_timings.get(stage, 0.0) for stage in PER_FRAME_STAGES) / 1e3
    per_row = (busy_there - per_frame) / rows_there
    if per_row <= 0.0:
        return split
    surplus = busy_there - busy_here - (per_frame if split == 0 else 0.0)
    if waited > WAITED_FOR_THE_WORKER:
        surplus = waited
    move = 0.5 * surplus / (2.0 * per_row)  # damped: times are noisy
    step = band_rows(camera, settings)
    rounded = int(round((split + move) / step)) * step
    return min(max(rounded, 0), max(0, (camera.height // step - 1) * step))


def rows_there(split: int, mode: str, camera: Camera) -> tuple[int, int] | None:
    """The rows the worker renders of a group's frame: below the split of a shared full
    render, else all (None)."""
    if mode == "full" and split > 0:
        return (split, camera.height)
    return None


def buffer_name(sensor: CameraSensor) -> str:
    """The FrameBuffers field the sensor reads: rgba, depth or ids."""
    return _BUFFER_OF.get(sensor.spec.sensor_type, "ids")


def copy_out(
    members: list[CameraSensor], frame: FrameBuffers, rows: int | None = None
) -> dict[str, np.ndarray]:
    """Fresh arrays of the buffers the group's sensors read (uuid -> array), holding the
    frame's first ``rows`` rows (None: all; ``copy_rows`` fills the rest)."""
    arrays = {}
    for sensor in members:
        buffer = getattr(frame, buffer_name(sensor))
        if rows is None:
            arrays[sensor.uuid] = buffer.copy()
        else:
            arrays[sensor.uuid] = np.empty_like(buffer)
            arrays[sensor.uuid][:rows] = buffer[:rows]
    return arrays


def copy_rows(
    members: list[CameraSensor], frame: FrameBuffers, arrays: dict[str, np.ndarray], first: int
) -> None:
    """Copy the frame's rows from ``first`` on into the group's arrays (``copy_out``)."""
    for sensor in members:
        buffer = getattr(frame, buffer_name(sensor))
        arrays[sensor.uuid][first:] = buffer[first:]
