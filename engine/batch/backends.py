"""Where episodes run: in this process, in a pool of local processes, or on a Ray cluster.

Every backend takes the pickled episode function and a list of :class:`EpisodeTask` and
yields one :class:`EpisodeResult` per task, in the order they finish.

- ``serial``: a plain loop in this process (for debugging: breakpoints and prints work).
- ``process``: ``concurrent.futures.ProcessPoolExecutor`` with the ``spawn`` start method
  (a fresh interpreter per worker: no state copied from the parent by ``fork``). At most
  ``workers`` episodes are in flight. When a worker process dies (killed, out of memory,
  a crash in native code), the pool breaks (``BrokenProcessPool``) and every episode in
  flight fails with it, although only one of them killed it. The pool is then rebuilt and
  those suspects run again one at a time: a suspect that breaks the pool on its own is
  reported ``"lost"``, the others finish normally.
- ``ray``: Ray tasks (``@ray.remote(max_retries=...)``); Ray reruns a task whose worker
  died, on any node of the cluster, up to ``max_retries`` times, then reports it lost.
  Ray is imported only here, so it stays an optional extra.
"""

from __future__ import annotations

import importlib
import multiprocessing
import os
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from engine.batch.episodes import (
    EpisodeResult,
    EpisodeTask,
    call_episode,
    lost_result,
    run_episode,
)

BACKENDS = ("serial", "process", "ray")
# Local Ray clusters listen on loopback only (Ray reads this before it picks its address).
RAY_LOOPBACK_ENV = "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"


def run_serial(
    episode_fn: Callable[..., Any], tasks: Sequence[EpisodeTask]
) -> Iterator[EpisodeResult]:
    """Run the episodes one after another in this process (the function is not pickled:
    closures and breakpoints work)."""
    for task in tasks:
        yield call_episode(episode_fn, task)


# ------------------------------------------------------------------------------------------
# process: a local pool of spawned worker processes
# ------------------------------------------------------------------------------------------
def _new_pool(workers: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"))


def run_process(
    payload: bytes, tasks: Sequence[EpisodeTask], workers: int, max_retries: int
) -> Iterator[EpisodeResult]:
    """Run the episodes on ``workers`` spawned processes; survive workers that die.

    ``max_retries`` is unused: a suspect of a broken pool always gets one solo run.
    """
    pending: deque[EpisodeTask] = deque(tasks)
    suspects: deque[EpisodeTask] = deque()  # in flight when a worker died: rerun alone
    running: dict[Future, tuple[EpisodeTask, bool]] = {}  # future -> (task, runs alone)
    pool = _new_pool(workers)
    try:
        while pending or suspects or running:
            _submit(pool, running, pending, suspects, workers, payload)
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            broken = False
            for future in done:
                task, alone = running.pop(future)
                try:
                    yield future.result()
                except BrokenProcessPool:
                    broken = True
                    if alone:
                        yield lost_result(task, "BrokenProcessPool: the worker process died")
                    else:
                        suspects.append(task)
            if broken:
                # every other episode in flight went down with the pool: all are suspects
                suspects.extend(task for task, _ in running.values())
                running.clear()
                pool.shutdown(wait=True, cancel_futures=True)
                pool = _new_pool(workers)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _submit(
    pool: ProcessPoolExecutor,
    running: dict,
    pending: deque,
    suspects: deque,
    workers: int,
    payload: bytes,
) -> None:
    """Fill the pool: one suspect alone, else up to ``workers`` pending episodes."""
    if any(alone for _, alone in running.values()):
        return  # a suspect is on trial: nothing runs beside it
    if suspects:
        if not running:
            task = suspects.popleft()
            running[pool.submit(run_episode, payload, task)] = (task, True)
        return
    while pending and len(running) < workers:
        task = pending.popleft()
        running[pool.submit(run_episode, payload, task)] = (task, False)


# ------------------------------------------------------------------------------------------
# ray: tasks on a local or remote Ray cluster
# ------------------------------------------------------------------------------------------
def _connect_ray(address: str | None, workers: int | None):
    """Import Ray and connect: to ``address`` / ``$RAY_ADDRESS`` if given, else start a
    local cluster on loopback. Returns ``(ray, started_here)``."""
    address = address or os.environ.get("RAY_ADDRESS") or None
    if address is None:
        os.environ.setdefault(RAY_LOOPBACK_ENV, "0")
    try:
        ray = importlib.import_module("ray")
    except ImportError as error:
        raise ImportError("backend='ray' needs Ray: pip install 'rigidsim[ray]'") from error
    if ray.is_initialized():
        return ray, False
    if address is not None:
        ray.init(address=address, log_to_driver=False)
    else:
        ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False)
    return ray, True


def run_ray(
    payload: bytes,
    tasks: Sequence[EpisodeTask],
    workers: int | None,
    max_retries: int,
    address: str | None = None,
) -> Iterator[EpisodeResult]:
    """Run the episodes as Ray tasks, at most ``workers`` (default: the cluster's CPUs) in
    flight; a task whose worker died is retried ``max_retries`` times, then reported lost."""
    ray, started_here = _connect_ray(address, workers)
    running: dict = {}  # ObjectRef -> task
    try:
        remote_episode = ray.remote(num_cpus=1, max_retries=max_retries)(run_episode)
        in_flight = workers or max(int(ray.cluster_resources().get("CPU", 1)), 1)
        payload_ref = ray.put(payload)
        pending: deque[EpisodeTask] = deque(tasks)
        while pending or running:
            while pending and len(running) < in_flight:
                task = pending.popleft()
                running[remote_episode.remote(payload_ref, task)] = task
            done, _ = ray.wait(list(running), num_returns=1)
            task = running.pop(done[0])
            try:
                yield ray.get(done[0])
            except (ray.exceptions.WorkerCrashedError, ray.exceptions.NodeDiedError) as error:
                yield lost_result(
                    task, f"{type(error).__name__}: the worker died {max_retries + 1} times"
                )
    finally:
        for ref in running:  # stopped early (Ctrl-C): do not leave tasks running
            ray.cancel(ref, force=True)
        if started_here:
            ray.shutdown()
