"""One episode of a batch: its seed, how it runs, and the record it leaves.

An *episode function* is any function ``episode_fn(params, seed) -> dict``: it builds its
own :class:`engine.Simulator` (or reuses one it built earlier in the same process, see
:func:`engine.batch.worker_cache`), runs, and returns plain values. When the batch has an
``output_dir`` and the function takes a keyword ``episode_dir``, it also gets a folder of its
own for arrays or videos.

Seeds: episode ``i`` of a batch seeded ``s`` gets

    seed_i = first 32-bit word of SeedSequence(entropy=s, spawn_key=(i,))

which is exactly the seed of ``np.random.SeedSequence(s).spawn(n)[i]``. It depends only on
``(s, i)``, never on the backend, the worker count or the order in which episodes finish, so
every backend returns the same results (NumPy's SeedSequence hashes entropy and spawn key
into well mixed, independent streams: O'Neill's PCG seeding, see ``numpy.random.bit_generator``).

The record of an episode is an :class:`EpisodeResult`: its index, parameters, seed, wall
time, and either its value (``status == "ok"``), the exception it raised with the traceback
(``"failed"``), or the note that its worker process died (``"lost"``).
"""

from __future__ import annotations

import importlib.util
import inspect
import os
import pickle
import socket
import sys
import time
import traceback
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "EpisodeResult",
    "EpisodeTask",
    "episode_seed",
    "run_episode",
    "serialize_episode_fn",
    "worker_cache",
]

STATUSES = ("ok", "failed", "lost")


def episode_seed(batch_seed: int, index: int) -> int:
    """The seed of episode ``index`` in a batch seeded ``batch_seed`` (a 32-bit int).

    Equal to ``np.random.SeedSequence(batch_seed).spawn(index + 1)[index]``'s first word.
    """
    if isinstance(batch_seed, bool) or not isinstance(batch_seed, int | np.integer):
        raise TypeError(f"the batch seed must be an int, got {batch_seed!r}")
    if batch_seed < 0:
        raise ValueError(f"the batch seed must be >= 0, got {batch_seed}")
    sequence = np.random.SeedSequence(entropy=int(batch_seed), spawn_key=(int(index),))
    return int(sequence.generate_state(1, dtype=np.uint32)[0])


@dataclass(frozen=True)
class EpisodeTask:
    """What a worker needs to run one episode."""

    index: int
    params: Any
    seed: int
    episode_dir: str | None = None


@dataclass
class EpisodeResult:
    """The record of one episode.

    Attributes
    ----------
    index : int
        Position of the episode in the batch's ``params``.
    params : any
        The episode's parameters, as given.
    seed : int
        Its seed (:func:`episode_seed`).
    status : str
        ``"ok"``, ``"failed"`` (it raised) or ``"lost"`` (its worker process died).
    value : any
        What the episode function returned (None unless ``status == "ok"``).
    error : str or None
        ``"ExceptionType: message"`` for a failed or lost episode.
    traceback : str or None
        The formatted traceback of a failed episode.
    wall_time : float
        Seconds the episode function ran (0 for a lost episode).
    worker : str
        ``host:pid`` of the process that ran it.
    """

    index: int
    params: Any
    seed: int
    status: str
    value: Any = None
    error: str | None = None
    traceback: str | None = None
    wall_time: float = 0.0
    worker: str = ""

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> EpisodeResult:
        if data.get("status") not in STATUSES:
            raise ValueError(f"not an episode record: status {data.get('status')!r}")
        fields: dict[str, Any] = {name: data.get(name) for name in cls.__dataclass_fields__}
        return cls(**fields)


def lost_result(task: EpisodeTask, reason: str) -> EpisodeResult:
    """The record of an episode whose worker process died before it could answer."""
    return EpisodeResult(task.index, task.params, task.seed, "lost", error=reason)


def _worker_name() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


def _accepts_episode_dir(episode_fn: Callable[..., Any]) -> bool:
    """True when ``episode_fn`` has a parameter named ``episode_dir`` (or ``**kwargs``)."""
    try:
        parameters = inspect.signature(episode_fn).parameters.values()
    except (TypeError, ValueError):
        return False
    return any(p.name == "episode_dir" or p.kind is p.VAR_KEYWORD for p in parameters)


def call_episode(episode_fn: Callable[..., Any], task: EpisodeTask) -> EpisodeResult:
    """Run one episode in this process; an exception becomes a ``"failed"`` record.

    ``KeyboardInterrupt`` is not caught: Ctrl-C stops the batch (it resumes later).
    """
    kwargs = {}
    if task.episode_dir is not None and _accepts_episode_dir(episode_fn):
        Path(task.episode_dir).mkdir(parents=True, exist_ok=True)
        kwargs["episode_dir"] = task.episode_dir
    start = time.perf_counter()
    try:
        value = episode_fn(task.params, task.seed, **kwargs)
    except (Exception, SystemExit) as error:
        return EpisodeResult(
            task.index,
            task.params,
            task.seed,
            "failed",
            error=f"{type(error).__name__}: {error}",
            traceback=traceback.format_exc(),
            wall_time=time.perf_counter() - start,
            worker=_worker_name(),
        )
    return EpisodeResult(
        task.index,
        task.params,
        task.seed,
        "ok",
        value=value,
        wall_time=time.perf_counter() - start,
        worker=_worker_name(),
    )


# ------------------------------------------------------------------------------------------
# Shipping the episode function to worker processes
# ------------------------------------------------------------------------------------------
def _importable(module_name: str | None) -> bool:
    """True when a fresh process can import ``module_name`` (not ``__main__``, not a file
    loaded by path such as a notebook cell or a pytest module in importlib mode)."""
    if module_name is None or module_name in ("__main__", "__mp_main__"):
        return False
    try:
        return importlib.util.find_spec(module_name) is not None
    except (ImportError, ValueError):
        return False


def serialize_episode_fn(episode_fn: Callable[..., Any]) -> bytes:
    """Pickle ``episode_fn`` so that a fresh (spawned) process can load it.

    A function of an importable module travels by reference (its module and name). One
    defined in a notebook, a script's ``__main__`` or a file Python cannot import by name
    travels by value with cloudpickle (installed with Ray: ``pip install rigidsim[ray]``).
    """
    if not callable(episode_fn):
        raise TypeError(f"episode_fn must be callable, got {episode_fn!r}")
    module_name = getattr(episode_fn, "__module__", None)
    if _importable(module_name):
        try:
            return pickle.dumps(episode_fn)
        except (pickle.PicklingError, AttributeError, TypeError):
            pass  # a lambda or a nested function: try by value below
    try:
        import cloudpickle
    except ImportError as error:
        raise TypeError(
            f"episode_fn {episode_fn!r} is defined in {module_name!r}, which worker "
            "processes cannot import; move it into a module or install cloudpickle "
            "(pip install rigidsim[ray])"
        ) from error
    module = sys.modules.get(module_name) if module_name else None
    by_value = module is not None and module_name not in ("__main__", "__mp_main__")
    if by_value:
        cloudpickle.register_pickle_by_value(module)
    try:
        return cloudpickle.dumps(episode_fn)
    finally:
        if by_value:
            cloudpickle.unregister_pickle_by_value(module)


# the episode function of the current batch, unpickled once per worker process
_LOADED: dict[bytes, Callable[..., Any]] = {}


def run_episode(payload: bytes, task: EpisodeTask) -> EpisodeResult:
    """Worker entry point: load the pickled episode function (once) and run ``task``."""
    episode_fn = _LOADED.get(payload)
    if episode_fn is None:
        _LOADED.clear()
        episode_fn = _LOADED[payload] = pickle.loads(payload)
    return call_episode(episode_fn, task)


# ------------------------------------------------------------------------------------------
# One simulator per worker, reused across episodes
# ------------------------------------------------------------------------------------------
_WORKER_OBJECTS: dict[Any, Any] = {}


def worker_cache(key: Any, factory: Callable[[], Any]) -> Any:
    """An object built once per process by ``factory()`` and reused by later episodes.

    Reuse is safe when every episode puts back what it changes (e.g. a simulator whose
    episodes only move the agent, reseed the pathfinder and remove the objects they add);
    results then do not depend on which worker ran which episode::

        sim = worker_cache("apartment", make_apartment_simulator)
    """
    if key not in _WORKER_OBJECTS:
        _WORKER_OBJECTS[key] = factory()
    return _WORKER_OBJECTS[key]
