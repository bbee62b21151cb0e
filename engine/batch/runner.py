"""``run_batch``: many independent episodes, on one core, all cores, or a Ray cluster.

The pipeline of a batch:

1. seed every episode from ``(batch seed, index)`` (:func:`~engine.batch.episodes.episode_seed`);
2. with ``output_dir``: open the result store, and with ``resume=True`` take the episodes
   already finished from it;
3. ship the episode function to the backend (pickled once) and run the other episodes;
4. write each result as it arrives and advance the progress bar (done, failed, rate);
5. return all results in input order.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Any

from tqdm.auto import tqdm

from engine.batch.backends import BACKENDS, WorkerPool, run_process, run_ray, run_serial
from engine.batch.episodes import EpisodeResult, EpisodeTask, episode_seed, serialize_episode_fn
from engine.batch.store import ResultStore, json_round_trip

# More episodes than this would only fill memory with records: split the batch.
MAX_EPISODES = 10_000_000


def run_batch(
    episode_fn: Callable[..., Any],
    params: Sequence[Any],
    backend: str = "process",
    workers: int | None = None,
    seed: int = 0,
    output_dir: str | os.PathLike | None = None,
    resume: bool = False,
    progress: bool = True,
    max_retries: int = 2,
    ray_address: str | None = None,
    pool: WorkerPool | None = None,
) -> list[EpisodeResult]:
    """Run ``episode_fn(params[i], seed_i)`` for every ``i``; return the records in order.

    Parameters
    ----------
    episode_fn : callable
        ``episode_fn(params, seed) -> dict`` (or any picklable value); it may also take a
        keyword ``episode_dir`` (a folder of its own, given with ``output_dir``).
    params : sequence
        One entry per episode (usually a dict); JSON serializable when ``output_dir`` is set.
    backend : {"process", "ray", "serial"}
        Local worker processes, Ray tasks, or a loop in this process.
    workers : int or None
        Episodes running at once; default: all cores (``process``), the cluster's CPUs
        (``ray``).
    seed : int
        Batch seed; episode ``i`` gets :func:`episode_seed(seed, i) <episode_seed>`.
    output_dir : path or None
        Folder for ``results.jsonl`` (one line per episode, written as it finishes) and
        the episodes' own files.
    resume : bool
        Keep the finished episodes found in ``output_dir`` and run only the others.
    progress : bool
        Show a tqdm bar: episodes done, failed and the rate.
    max_retries : int
        ``ray``: times a task is rerun after its worker died.
    ray_address : str or None
        ``ray``: address of an existing cluster (default: ``$RAY_ADDRESS``, else a local one).
    pool : WorkerPool or None
        ``process``: run on these worker processes (already started, kept running after
        the batch) instead of starting a pool for this batch; ``workers`` must be None or
        the pool's size.

    Returns
    -------
    list of EpisodeResult
        ``results[i]`` is episode ``i``'s record: ``status`` "ok" (``value``), "failed"
        (``error``, ``traceback``) or "lost" (its worker died).
    """
    params = _check_arguments(params, backend, workers, seed, output_dir, resume, max_retries)
    _check_pool(pool, backend, workers)
    if workers is None and backend == "process":
        workers = os.cpu_count() or 1
    seeds = [episode_seed(seed, index) for index in range(len(params))]
    store, results = None, {}
    if output_dir is not None:
        description = {
            "seed": seed,
            "n_episodes": len(params),
            "backend": backend,
            "episode_fn": _qualified_name(episode_fn),
        }
        store = ResultStore(output_dir, description, resume)
        results = store.finished(params) if resume else {}
    tasks = [
        EpisodeTask(i, params[i], seeds[i], store.episode_dir(i) if store else None)
        for i in range(len(params))
        if i not in results
    ]
    bar = _ProgressBar(len(params), results.values(), progress)
    try:
        for result in _backend_results(
            backend, episode_fn, tasks, workers, max_retries, ray_address, pool
        ):
            if store is not None:
                result = store.write(result)
            results[result.index] = result
            bar.add(result)
    finally:
        bar.close()
        if store is not None:
            store.close()
    return [results[index] for index in range(len(params))]


def _backend_results(backend, episode_fn, tasks, workers, max_retries, ray_address, pool):
    """The backend's results, in the order episodes finish."""
    if not tasks:
        return iter(())
    if backend == "serial":
        return run_serial(episode_fn, tasks)
    payload = serialize_episode_fn(episode_fn)  # pickled once for all workers
    if backend == "process":
        return run_process(payload, tasks, workers, max_retries, pool)
    return run_ray(payload, tasks, workers, max_retries, ray_address)


def _check_arguments(params, backend, workers, seed, output_dir, resume, max_retries) -> list:
    """Validate the arguments up front (nothing runs or is written on bad input)."""
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; choose one of {BACKENDS}")
    if isinstance(params, str | bytes) or not isinstance(params, Sequence):
        raise TypeError(f"params must be a sequence (one entry per episode), got {params!r}")
    if len(params) > MAX_EPISODES:
        raise ValueError(f"{len(params)} episodes is more than {MAX_EPISODES}: split the batch")
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int) or workers < 1
    ):
        raise ValueError(f"workers must be a positive int or None, got {workers!r}")
    episode_seed(seed, 0)  # type and range of the seed
    if isinstance(max_retries, bool) or not isinstance(max_retries, int) or max_retries < 0:
        raise ValueError(f"max_retries must be an int >= 0, got {max_retries!r}")
    if resume and output_dir is None:
        raise ValueError("resume=True needs the output_dir of the batch to resume")
    if output_dir is not None:
        for index, entry in enumerate(params):
            try:
                json_round_trip(entry)
            except (TypeError, ValueError) as error:
                raise TypeError(
                    f"params[{index}] is not JSON serializable (needed with output_dir): {error}"
                ) from error
    return list(params)


def _check_pool(pool, backend, workers) -> None:
    if pool is None:
        return
    if not isinstance(pool, WorkerPool):
        raise TypeError(f"pool must be an engine.batch.WorkerPool, got {pool!r}")
    if backend != "process":
        raise ValueError(f"pool= runs the process backend, not backend={backend!r}")
    if workers is not None and workers != pool.workers:
        raise ValueError(f"workers={workers} but the pool has {pool.workers} workers")


def _qualified_name(episode_fn: Callable[..., Any]) -> str:
    module = getattr(episode_fn, "__module__", "?")
    return f"{module}.{getattr(episode_fn, '__qualname__', repr(episode_fn))}"


class _ProgressBar:
    """tqdm bar over episodes: ``batch 40%|####  | 40/100 [00:05, 7.9 ep/s, failed=1]``."""

    def __init__(self, total: int, finished, enabled: bool) -> None:
        finished = list(finished)
        self.failed = sum(not r.ok for r in finished)
        self.bar = tqdm(
            total=total,
            initial=len(finished),
            desc="batch",
            unit="ep",
            disable=not enabled,
            dynamic_ncols=True,
        )
        self.bar.set_postfix(failed=self.failed, refresh=False)

    def add(self, result: EpisodeResult) -> None:
        if not result.ok:
            self.failed += 1
            self.bar.set_postfix(failed=self.failed, refresh=False)
        self.bar.update(1)

    def close(self) -> None:
        self.bar.close()
