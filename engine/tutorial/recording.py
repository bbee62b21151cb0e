"""Frame capture for the tutorial job: step, render, encode, and time each stage.

Habitat's tutorial collects every observation of a section in a list and encodes the list
with ``vut.make_video`` at the end. At 544 x 720 with three sensors one frame is about
4.7 MB, so the 600-frame ``robot_control`` section would hold 2.8 GB. The job therefore
streams: each frame is rendered and handed to a :class:`render.video.BackgroundVideoWriter`,
whose thread composes it (``compose_video_frame``: the pixels of ``make_video_frame``,
which ``make_video`` uses) and feeds ffmpeg while the simulation goes on. The resulting
file is the one ``make_video`` would write from the same observations.

Wall time of a section is split into three parts:

- rendering: ``sim.get_sensor_observations()`` (all three sensors);
- encoding: the time the simulation *waited* for the encoder (a full queue, and finishing
  the file at the end of the section); the encoder thread's own busy time is
  ``SectionTimings.encoding_background``;
- physics: everything else, i.e. ``sim.step_physics`` and the control code of the section.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from typing import Any

import numpy as np

from render import video as vut


@dataclass
class VideoSpec:
    """What one section's video shows, with Habitat's ``make_video`` arguments.

    Attributes
    ----------
    name : str
        File stem (``sim_basics`` ...); the file is ``<output_dir>/<name>.mp4``.
    primary_obs : str
        Sensor uuid of the full-frame image.
    primary_obs_type : str
        ``"color"``, ``"depth"`` or ``"semantic"``.
    overlay_settings : list of dict or None
        Habitat overlay dicts (``obs``, ``type``, ``dims`` (w, h), ``pos`` (x, y), ``border``).
    fps : int
        Frames per second of the file; 60 = one frame per ``step_physics(1/60)`` call.
    depth_clip : float
        Depth in meters drawn white.
    """

    name: str
    primary_obs: str = "rgba_camera_1stperson"
    primary_obs_type: str = "color"
    overlay_settings: list[dict[str, Any]] | None = None
    fps: int = 60
    depth_clip: float = 10.0


def _compose_frame(video: VideoSpec, observation: dict[str, np.ndarray]) -> np.ndarray:
    """The video frame of one observation, exactly as ``make_video`` composes it."""
    return vut.compose_video_frame(
        observation,
        video.primary_obs,
        video.primary_obs_type,
        video.overlay_settings,
        video.depth_clip,
    )


@dataclass
class SectionTimings:
    """Wall-clock seconds spent in one section, by stage."""

    total: float = 0.0
    rendering: float = 0.0
    encoding: float = 0.0
    encoding_background: float = 0.0

    @property
    def physics(self) -> float:
        """Seconds not spent rendering or encoding: stepping and control code."""
        return max(self.total - self.rendering - self.encoding, 0.0)


@dataclass
class SectionRecorder:
    """Counts, renders and encodes the frames of one tutorial section.

    Parameters
    ----------
    sim : Simulator
        The tutorial's simulator.
    video : VideoSpec or None
        The video to write; None simulates only (``--no-make-video``).
    video_path : str or None
        Output file (``.mp4``) when ``video`` is given.
    keep_observations : bool
        Also keep every observation dict in ``observations`` (memory heavy at full size).
    on_frame : callable or None
        Called after each frame with the world time advanced since the previous frame (s),
        e.g. a progress bar's ``update``.
    """

    sim: Any
    video: VideoSpec | None = None
    video_path: str | None = None
    keep_observations: bool = False
    on_frame: Callable[[float], Any] | None = None
    frames: int = 0
    observations: list[dict[str, np.ndarray]] = field(default_factory=list)
    timings: SectionTimings = field(default_factory=SectionTimings)
    _writer: Any = None
    _last_world_time: float = 0.0
    _start_wall: float = 0.0

    def __post_init__(self) -> None:
        if self.video is not None and not self.video_path:
            raise ValueError(f"video_path must be given with video={self.video.name!r}")
        self._start_wall = time.perf_counter()
        self._last_world_time = self.sim.get_world_time()

    @property
    def renders(self) -> bool:
        """True when frames are rendered (a video is written or observations are kept)."""
        return self.video is not None or self.keep_observations

    def step(self, dt: float = 1.0 / 60.0) -> None:
        """``sim.step_physics(dt)`` then capture one frame (the tutorial's loop body)."""
        self.sim.step_physics(dt)
        self.capture()

    def capture(self) -> None:
        """Count one frame; render it and append it to the video when recording."""
        self.frames += 1
        if self.renders:
            start = time.perf_counter()
            observation = self.sim.get_sensor_observations()
            self.timings.rendering += time.perf_counter() - start
            if self.keep_observations:
                self.observations.append(observation)
            if self.video is not None:
                self._encode(observation, self.video)
        if self.on_frame is not None:
            world_time = self.sim.get_world_time()
            self.on_frame(world_time - self._last_world_time)
            self._last_world_time = world_time

    def _encode(self, observation: dict[str, np.ndarray], video: VideoSpec) -> None:
        """Queue the frame for the encoder thread (opened at the first frame)."""
        if self._writer is None:
            if not self.video_path:
                raise ValueError(f"video_path must be given with video={video.name!r}")
            # the encoder settings of render.video.save_video (H.264 in an mp4 container)
            options = vut.mp4_options(video.fps)
            start = time.perf_counter()
            compose = partial(_compose_frame, video)
            self._writer = vut.BackgroundVideoWriter(self.video_path, options, compose)
            self.timings.encoding += time.perf_counter() - start
        self._writer.append(observation)

    def close(self) -> str | None:
        """Finish the video file and the section's wall clock; return the video path."""
        if self._writer is not None:
            writer, self._writer = self._writer, None
            writer.close()
            self.timings.encoding += writer.wait_seconds
            self.timings.encoding_background += writer.busy_seconds
        self.timings.total = time.perf_counter() - self._start_wall
        return self.video_path if self.video is not None and self.frames > 0 else None
