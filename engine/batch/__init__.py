"""Many simulations at once: a batch runner for independent episodes.

``run_batch(episode_fn, params, backend=...)`` runs ``episode_fn(params[i], seed_i)`` for
every entry of ``params`` (a parameter sweep, a set of navigation episodes...), each in its
own simulator, and returns one :class:`EpisodeResult` per episode in input order:

    from engine.batch import run_batch

    def drop(params, seed):
        ...                                   # build a Simulator, drop a ball, measure
        return {"bounce_height": h}

    results = run_batch(drop, [{"restitution": r} for r in (0.2, 0.5, 0.8)],
                        backend="process", workers=2, output_dir="runs/drops")

Backends (:mod:`engine.batch.backends`): ``"serial"`` (this process), ``"process"`` (all
local cores, ``concurrent.futures`` worker processes; keep a :class:`WorkerPool` to reuse
them across batches) and ``"ray"`` (a local or remote
Ray cluster, optional extra ``rigidsim[ray]``). Seeds depend only on the batch seed and the
episode index (:mod:`engine.batch.episodes`), so every backend and worker count gives the
same results. With ``output_dir`` the results are written as they finish
(:mod:`engine.batch.store`) and ``resume=True`` continues an interrupted batch.

May import: the standard library and the optional Ray extra; an episode function brings
its own simulator, so nothing of ``engine`` is imported here. The tutorial builds on it.
"""

from engine.batch.backends import WorkerPool
from engine.batch.episodes import EpisodeResult, episode_seed, worker_cache
from engine.batch.runner import run_batch
from engine.batch.store import read_results

__all__ = [
    "EpisodeResult",
    "WorkerPool",
    "episode_seed",
    "read_results",
    "run_batch",
    "worker_cache",
]
