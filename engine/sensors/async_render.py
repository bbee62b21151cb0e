"""Asynchronous rendering: Habitat's ``start_async_render_and_step_physics`` pattern.

Habitat lets a program render the sensors of the current frame while the physics computes
the next one::

    sim.start_async_render_and_step_physics(dt)   # render the world as it is, step it
    observations = sim.get_sensor_observations_async_finish()   # the frame before the step

Rules (Habitat's): ``start`` twice without ``finish`` raises ``RuntimeError``, and so does
``finish`` without ``start``; between the two, nothing else may draw or create or remove
sensors (``RuntimeError`` naming the call). ``step_physics`` may be called again (the render
shows the state at ``start``). The observations are those of the state at ``start``,
exactly what ``get_sensor_observations`` would have returned then.

How rigidsim overlaps the two: at ``start`` the renderer copies every pose it needs (the
render scenes' mesh poses, each camera's pose; the meshes themselves are immutable) and
submits every camera group to the **render worker process** (:mod:`render.worker`), which
renders from that snapshot while this process steps the physics: two processes, two cores,
no shared mutable state. ``finish`` collects the frames (and resamples the cube maps of
wide-angle sensors, after drawing the debug lines taken at ``start``,
:mod:`engine.sensors.line_overlay`). A group rendered asynchronously stays in the worker afterwards.
Without a worker (``processes = 0``) the snapshot renders on a thread (``threaded``: the
renderer's NumPy passes hold the GIL most of the time, so little overlaps) or, with
``threaded = False``, synchronously at ``start`` (the plain path). All three give the same
observations (tested); ``benchmarks/bench_render.py`` measures the overlap.
"""

from __future__ import annotations

from collections import OrderedDict
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any

from engine.sensors.cubemap import observe_later_with_cube_maps, observe_with_cube_maps
from engine.sensors.line_overlay import LineOverlay
from engine.sensors.observations import Observations

__all__ = ["AsyncRender"]


class AsyncRender:
    """The state of one simulator's asynchronous render (module docstring)."""

    #: True: render in the render worker process when the renderer has one
    use_worker = True
    #: without the worker: True renders on a thread, False synchronously at ``start``
    #: (the plain path; the same observations)
    threaded = True

    def __init__(self, sim: Any) -> None:
        self._sim = sim
        self._agent_ids: int | list[int] | None = None
        self._queued: list = []
        self._pending: Any = None
        self._pool: ThreadPoolExecutor | None = None

    @property
    def running(self) -> bool:
        return self._agent_ids is not None

    def check_idle(self, what: str) -> None:
        """Raise RuntimeError naming ``what`` while an asynchronous render is pending."""
        if self.running:
            raise RuntimeError(
                f"{what} is not allowed during an asynchronous render: call "
                "get_sensor_observations_async_finish first"
            )

    def enqueue(self, sensor: Any) -> None:
        self._queued.append(sensor)

    def start(self, agent_ids: int | list[int], dt: float | None) -> None:
        """Queue the agents' sensors, start their render, then step the physics by ``dt``."""
        sim = self._sim
        sim._check_open()
        if self.running:
            raise RuntimeError(
                "start_async_render_and_step_physics was already called.  "
                "Call get_sensor_observations_async_finish before calling this again.  "
                "Use step_physics to step physics additional times."
            )
        ids = [agent_ids] if isinstance(agent_ids, int) else list(agent_ids)
        self._queued = []
        for agent_id in ids:
            for sensor in sim._agent_sensors(agent_id):
                sensor.render_async()
        sensors, self._queued = self._queued, []
        objects = [sensor.sensor_object for sensor in sensors]
        lines = sim.take_debug_lines()  # drawn as the world is now, like the frames
        overlay = LineOverlay(lines, objects) if lines is not None else None
        renderer = sim._renderer
        in_worker = None
        if self.use_worker:
            in_worker = observe_later_with_cube_maps(renderer.observe_in_worker, objects, overlay)
        if in_worker is not None:  # rendering in the worker process already
            self._pending = self._collect_later(in_worker)
        elif self.threaded:
            render = observe_later_with_cube_maps(renderer.observe_later, objects, overlay)
            self._pending = self._thread_pool().submit(render)
        else:
            self._pending = Future()
            self._pending.set_result(observe_with_cube_maps(renderer.observe, objects, overlay))
        self._agent_ids = agent_ids
        self._sensors = sensors
        if dt is not None:
            sim.step_physics(dt)

    def finish(self) -> Any:
        """Wait for the render; the observations as ``get_sensor_observations`` shapes them."""
        if not self.running or self._pending is None:
            raise RuntimeError(
                "get_sensor_observations_async_finish was called before calling "
                "start_async_render_and_step_physics."
            )
        agent_ids, self._agent_ids = self._agent_ids, None
        pending, self._pending = self._pending, None
        frames = pending.result()
        for sensor in self._sensors:
            sensor._buffer = frames[sensor.uuid]
        single = isinstance(agent_ids, int)
        ids: list[int] = [agent_ids] if isinstance(agent_ids, int) else list(agent_ids or [])
        observations: dict[int, dict[str, Any]] = OrderedDict()
        for agent_id in ids:
            uuids = {s.uuid for s in self._sim._agent_sensors(agent_id)}
            observations[agent_id] = Observations(
                (s.uuid, s.get_observation_async()) for s in self._sensors if s.uuid in uuids
            )
        self._sensors = []
        return next(iter(observations.values())) if single else observations

    @staticmethod
    def _collect_later(collect: Any) -> Any:
        """A future-like whose ``result()`` collects the worker's frames."""

        class _Collect:
            def result(self) -> Any:
                return collect()

            def exception(self) -> Any:
                try:
                    collect()
                except Exception as error:  # noqa: BLE001 - reported by the caller
                    return error
                return None

        return _Collect()

    def _thread_pool(self) -> ThreadPoolExecutor:
        if self._pool is None:
            self._pool = ThreadPoolExecutor(1, thread_name_prefix="rigidsim-async-render")
        return self._pool

    def close(self) -> None:
        if self._pending is not None:
            self._pending.exception()  # wait: the render must not outlive the simulator
        self._agent_ids, self._pending = None, None
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None
