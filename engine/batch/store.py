"""The batch's folder on disk: results written as they arrive, read back to resume.

Layout of ``output_dir``::

    batch.json          the batch: seed, number of episodes, episode function
    results.jsonl       one JSON object per finished episode, in the order they finished
    episodes/00042/     files episode 42 saved (only for functions taking ``episode_dir``)

Each line is appended and flushed as soon as its episode finishes, so a batch killed at
any moment leaves every finished episode on disk (at worst a last half-written line, which
is ignored). ``resume=True`` reads the file back and runs only the episodes it lacks, or
whose worker died (``"lost"``). Values are stored as JSON: NumPy arrays and scalars become
lists and numbers.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from engine.batch.episodes import EpisodeResult

RESULTS_FILE = "results.jsonl"
BATCH_FILE = "batch.json"


def to_json_value(value: Any) -> Any:
    """``json.dumps`` hook: NumPy arrays to lists, NumPy scalars to Python numbers."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, set | frozenset | tuple):
        return list(value)
    raise TypeError(f"{type(value).__name__} is not JSON serializable")


def json_round_trip(value: Any) -> Any:
    """``value`` as it reads back from JSON (tuples become lists, arrays lists...)."""
    return json.loads(json.dumps(value, default=to_json_value))


class ResultStore:
    """Appends episode records to ``<output_dir>/results.jsonl`` and reads them back."""

    def __init__(
        self, output_dir: str | os.PathLike, description: dict[str, Any], resume: bool
    ) -> None:
        self.folder = Path(output_dir)
        self.results_path = self.folder / RESULTS_FILE
        self.folder.mkdir(parents=True, exist_ok=True)
        self._check_description(description, resume)
        self._handle = open(self.results_path, "a", encoding="utf-8")  # noqa: SIM115
        if self._handle.tell() and not self.results_path.read_bytes().endswith(b"\n"):
            self._handle.write("\n")  # end a line torn by a kill: the next record stays whole

    def _check_description(self, description: dict[str, Any], resume: bool) -> None:
        """Refuse to mix two different batches (or to overwrite one) in the same folder."""
        batch_path = self.folder / BATCH_FILE
        if batch_path.is_file() and resume:
            stored = json.loads(batch_path.read_text(encoding="utf-8"))
            for key in ("seed", "n_episodes"):
                if stored.get(key) != description[key]:
                    raise ValueError(
                        f"cannot resume: {batch_path} has {key}={stored.get(key)!r}, "
                        f"this batch has {key}={description[key]!r}"
                    )
            return
        if not resume and self.results_path.is_file() and self.results_path.stat().st_size:
            raise FileExistsError(
                f"{self.results_path} already holds results: pass resume=True to continue "
                "that batch, or choose another output_dir"
            )
        batch_path.write_text(json.dumps(description, indent=1), encoding="utf-8")

    def episode_dir(self, index: int) -> str:
        return str(self.folder / "episodes" / f"{index:05d}")

    def finished(self, params: Sequence[Any]) -> dict[int, EpisodeResult]:
        """Records already on disk, by index, except lost episodes (they run again).

        Raises ValueError if a stored episode had other parameters than ``params`` says.
        """
        records: dict[int, EpisodeResult] = {}
        for record in read_results(self.results_path):
            if record.status == "lost" or not 0 <= record.index < len(params):
                continue
            expected = json_round_trip(params[record.index])
            if record.params != expected:
                raise ValueError(
                    f"cannot resume: episode {record.index} ran with params {record.params!r}, "
                    f"this batch gives it {expected!r}"
                )
            records[record.index] = record
        return records

    def write(self, result: EpisodeResult) -> EpisodeResult:
        """Append one record, flush it to disk and return it.

        A value JSON cannot hold turns the record into a failed one (in memory too), so the
        file and the returned results always agree.
        """
        try:
            line = json.dumps(result.to_dict(), default=to_json_value)
        except (TypeError, ValueError) as error:
            result = replace(
                result,
                status="failed",
                value=None,
                error=f"TypeError: the episode's value is not JSON serializable "
                f"(needed with output_dir): {error}",
            )
            line = json.dumps(result.to_dict(), default=to_json_value)
        self._handle.write(line + "\n")
        self._handle.flush()
        os.fsync(self._handle.fileno())
        return result

    def close(self) -> None:
        self._handle.close()


def read_results(path: str | os.PathLike) -> list[EpisodeResult]:
    """Every complete record of a ``results.jsonl`` (a torn last line is skipped); for an
    index recorded twice (a lost episode run again) the last record wins."""
    path = Path(path)
    if path.is_dir():
        path = path / RESULTS_FILE
    if not path.is_file():
        return []
    by_index: dict[int, EpisodeResult] = {}
    with open(path, encoding="utf-8") as handle:
        for line in handle:
            try:
                record = EpisodeResult.from_dict(json.loads(line))
            except (json.JSONDecodeError, ValueError, TypeError):
                continue  # a line cut short when the batch was killed
            by_index[record.index] = record
    return [by_index[i] for i in sorted(by_index)]
