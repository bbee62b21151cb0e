"""Where episodes run: in this process, in a pool of local processes, or on a Ray cluster.

Every backend takes the pickled episode function and a list of :class:`EpisodeTask` and
yields one :class:`EpisodeResult` per task, in the order they finish.

- ``serial``: a plain loop in this process (for debugging: breakpoints and prints work).
- ``process``: ``concurrent.futures.ProcessPoolExecutor`` (:class:`WorkerPool`). Workers
  start from a fresh interpreter, never as a copy of the caller: ``forkserver`` (a clean
  server process that imported rigidsim once; each worker is a copy of it, ready in
  milliseconds) where the platform has it, else ``spawn``. At most ``workers`` chunks are
  in flight; short episodes travel several to a chunk. When a worker process dies (killed,
  out of memory, a crash in native code), the pool breaks (``BrokenProcessPool``) and every
  episode in flight fails with it, although only one of them killed it. The pool is then
  rebuilt and those suspects run again one at a time: a suspect that breaks the pool on its
  own is reported ``"lost"``, the others finish normally.
- ``ray``: Ray tasks (``@ray.remote(max_retries=...)``); Ray reruns a task whose worker
  died, on any node of the cluster, up to ``max_retries`` times, then reports it lost.
  Ray is imported only here, so it stays an optional extra.
"""

from __future__ import annotations

import importlib
import multiprocessing
import os
import time
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
    run_episodes,
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
# process: a local pool of worker processes
# ------------------------------------------------------------------------------------------
# What every worker imports before its first episode: the fork server imports these once and
# each worker starts as a copy of it, instead of every spawned interpreter importing rigidsim
# (about 0.5 s) and building its first Simulator (about 0.7 s of lazy imports) on its own.
WORKER_PRELOAD = ("__main__", "engine", "engine.simulator.simulator", "engine.batch")
# Episodes shorter than this go to a worker several at a time (one round trip per chunk).
CHUNK_SECONDS = 0.05


def worker_context() -> multiprocessing.context.BaseContext:
    """The start method of worker processes: ``forkserver`` with rigidsim preloaded where
    the platform has it (Linux, macOS), else ``spawn`` (Windows).

    Both start workers from a fresh interpreter, never as a copy of the caller (``fork``
    would copy its threads, locks and simulators): the fork server is a clean process that
    imported ``WORKER_PRELOAD`` and nothing else. Its preload list is set only until the
    server first starts (once per session); later pools fork from the same server.
    """
    if "forkserver" in multiprocessing.get_all_start_methods():
        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload(list(WORKER_PRELOAD))
        return context
    return multiprocessing.get_context("spawn")


def _worker_pid(pause: float) -> int:
    time.sleep(pause)  # long enough that one idle worker cannot take every start-up call
    return os.getpid()


class WorkerPool:
    """Local worker processes that can outlive one batch.

    ``run_batch(..., backend="process")`` starts a pool for the batch and stops it at the
    end; starting the workers is the fixed cost of a batch (about 1 s for the first pool of
    a session, which starts the fork server, about 0.1 s after). To pay it once for several
    batches (a notebook, a benchmark), keep a pool and pass it::

        with WorkerPool(2) as pool:
            pool.start()                                  # optional: start the workers now
            run_batch(drop, sweep_1, backend="process", pool=pool)
            run_batch(drop, sweep_2, backend="process", pool=pool)

    A worker that dies breaks the pool; the batch running on it restarts it.
    """

    def __init__(self, workers: int | None = None) -> None:
        if workers is not None and (
            isinstance(workers, bool) or not isinstance(workers, int) or workers < 1
        ):
            raise ValueError(f"workers must be a positive int or None, got {workers!r}")
        self.workers = workers or os.cpu_count() or 1
        self._executor: ProcessPoolExecutor | None = None

    @property
    def executor(self) -> ProcessPoolExecutor:
        """The running ``ProcessPoolExecutor`` (created on first use)."""
        if self._executor is None:
            self._executor = ProcessPoolExecutor(self.workers, mp_context=worker_context())
        return self._executor

    def start(self, timeout: float = 120.0) -> float:
        """Start every worker now and wait until each answers; returns the seconds it took."""
        begin = time.perf_counter()
        answered: set[int] = set()
        while len(answered) < self.workers and time.perf_counter() - begin < timeout:
            calls = [self.executor.submit(_worker_pid, 0.05) for _ in range(self.workers)]
            answered.update(call.result() for call in calls)
        return time.perf_counter() - begin

    def restart(self) -> None:
        """Replace a broken pool by a fresh one (after a worker died)."""
        self.shutdown()
        self._executor = ProcessPoolExecutor(self.workers, mp_context=worker_context())

    def shutdown(self) -> None:
        """Stop the workers (episodes not started yet are cancelled)."""
        if self._executor is not None:
            self._executor.shutdown(wait=True, cancel_futures=True)
            self._executor = None

    def __enter__(self) -> WorkerPool:
        return self

    def __exit__(self, *exc_info) -> None:
        self.shutdown()


def run_process(
    payload: bytes,
    tasks: Sequence[EpisodeTask],
    workers: int,
    max_retries: int,
    pool: WorkerPool | None = None,
) -> Iterator[EpisodeResult]:
    """Run the episodes on ``workers`` worker processes; survive workers that die.

    Episodes go out in chunks: one at a time until their wall time is known, then as many
    as take about ``CHUNK_SECONDS`` (never more than a quarter of a worker's share of
    what is left, so that the workers finish together). ``max_retries`` is unused: a
    suspect of a broken pool always gets one solo run. With ``pool`` the batch runs on
    those (possibly already started) workers and leaves them running.
    """
    own_pool = pool is None
    if pool is None:
        pool = WorkerPool(workers)
    workers = pool.workers
    pending: deque[EpisodeTask] = deque(tasks)
    suspects: deque[EpisodeTask] = deque()  # in flight when a worker died: rerun alone
    running: dict[Future, tuple[list[EpisodeTask], bool]] = {}  # future -> (chunk, alone)
    timing = _EpisodeTiming()
    try:
        while pending or suspects or running:
            _submit(pool.executor, running, pending, suspects, workers, payload, timing)
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            broken = False
            for future in done:
                chunk, alone = running.pop(future)
                try:
                    finished = future.result()
                except BrokenProcessPool:
                    broken = True
                    if alone:
                        yield lost_result(chunk[0], "BrokenProcessPool: the worker process died")
                    else:
                        suspects.extend(chunk)
                    continue
                for task, result in zip(chunk, finished, strict=True):
                    result.params = task.params  # not shipped back: the parent has them
                    timing.add(result.wall_time)
                    yield result
            if broken:
                # every other episode in flight went down with the pool: all are suspects
                suspects.extend(task for chunk, _ in running.values() for task in chunk)
                running.clear()
                pool.restart()
    finally:
        if own_pool:
            pool.shutdown()
        elif running:  # stopped early (Ctrl-C): do not leave the kept pool busy
            pool.restart()


class _EpisodeTiming:
    """Running mean of the episodes' wall times (sizes the chunks)."""

    def __init__(self) -> None:
        self.count, self.total = 0, 0.0

    def add(self, seconds: float) -> None:
        self.count += 1
        self.total += seconds

    def chunk_size(self, remaining: int, workers: int) -> int:
        """Episodes per submission: about ``CHUNK_SECONDS`` of work, 1 while unknown."""
        if self.count == 0:
            return 1
        mean = max(self.total / self.count, 1e-6)
        return max(1, min(int(CHUNK_SECONDS / mean), remaining // (4 * workers)))


def _submit(
    executor: ProcessPoolExecutor,
    running: dict,
    pending: deque,
    suspects: deque,
    workers: int,
    payload: bytes,
    timing: _EpisodeTiming,
) -> None:
    """Fill the pool: one suspect alone, else up to ``workers`` chunks of pending episodes."""
    if any(alone for _, alone in running.values()):
        return  # a suspect is on trial: nothing runs beside it
    if suspects:
        if not running:
            chunk = [suspects.popleft()]
            running[executor.submit(run_episodes, payload, chunk)] = (chunk, True)
        return
    while pending and len(running) < workers:
        size = timing.chunk_size(len(pending), workers)
        chunk = [pending.popleft() for _ in range(min(size, len(pending)))]
        running[executor.submit(run_episodes, payload, chunk)] = (chunk, False)


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
