"""The mutation report of ``scripts/mutation.py``: one row per kernel, its survivors and its
equivalent mutants, written as ``benchmarks/results/mutation-<date>.md`` with a JSON twin.

A row (:class:`ModuleResult`) holds the module's killed, surviving and equivalent mutants and
the commit it was measured on; its score is ``killed / (killed + survived)``, equivalent
mutants left out. A run over a few modules replaces their rows in the day's report and keeps
the others (the JSON twin holds them), so one report covers every module run that day.
"""

from __future__ import annotations

import dataclasses
import datetime
import json
import os
import platform
import subprocess
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@dataclass
class ModuleResult:
    module: str
    n_mutants: int
    n_sampled: int
    killed: list[tuple]  # (operator, line, col, original, mutated, hit the timeout)
    survived: list[tuple]  # (operator, line, col, original text, mutated text)
    equivalent: list[tuple]  # (operator, line, col, original text, mutated text, reason)
    seconds: float
    code: str = ""  # the commit measured (``git describe``-style, "+dirty" for local edits)

    @property
    def score(self) -> float:
        total = len(self.killed) + len(self.survived)
        return len(self.killed) / total if total else 1.0


def code_version() -> str:
    """The checkout's commit, ``+dirty`` when the copied folders hold uncommitted edits."""
    try:
        head = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "engine", "render", "navmesh", "tests"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return head + ("+dirty" if dirty else "")


def _cpu_model() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return platform.processor() or "unknown CPU"
    for line in out.splitlines():
        if line.startswith("Model name:"):
            return line.split(":", 1)[1].strip()
    return "unknown CPU"


def _merge_earlier(path: Path, results: list[ModuleResult], order: list[str]) -> list[ModuleResult]:
    """This run's results plus those of earlier runs of the same day for other modules.

    Every report has a JSON twin (``.json``); a run over a few modules updates their rows
    and keeps the others, so the dated report always covers every module run that day.
    """
    twin = path.with_suffix(".json")
    earlier = json.loads(twin.read_text()) if twin.exists() else []
    done = {r.module for r in results}
    kept = [ModuleResult(**r) for r in earlier if r["module"] not in done]
    merged = sorted(kept + results, key=lambda r: order.index(r.module))
    twin.write_text(json.dumps([dataclasses.asdict(r) for r in merged], indent=1) + "\n")
    return merged


def write_report(path: Path, results: list[ModuleResult], seed: int, order: list[str]) -> None:
    """Write the dated report (and its JSON twin) with this run's rows and the day's earlier
    rows of other modules, in ``order`` (the kernel table's order)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    results = _merge_earlier(path, results, order)
    today = datetime.date.today().isoformat()
    lines = [
        f"# Mutation run {today}",
        "",
        f"cosmic-ray, a seeded sample of mutants per module (seed {seed}), "
        f"{os.cpu_count()} cores, {_cpu_model()}. Produced by `bash scripts/mutation.sh`;",
        "how to read it: `docs/testing.md`. Score = killed / (sampled - equivalent).",
        "",
        "| module | mutants | sampled | equivalent | killed (by timeout) | survived | score "
        "| minutes | code |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        lines.append(
            f"| `{r.module}` | {r.n_mutants} | {r.n_sampled} | {len(r.equivalent)} | "
            f"{len(r.killed)} ({sum(k[-1] for k in r.killed)}) | {len(r.survived)} | "
            f"{100 * r.score:.0f} % | "
            f"{r.seconds / 60:.1f} | {r.code or 'not recorded'} |"
        )
    for r in results:
        lines += ["", f"## `{r.module}`", ""]
        lines.append("Survivors:" if r.survived else "Survivors: none.")
        for op, line, col, text, mutant in sorted(r.survived, key=lambda e: (e[1], e[2])):
            lines.append(f"- line {line}:{col} `{op}`: `{text}` -> `{mutant}`")
        heading = "Equivalent (excluded from the score):" if r.equivalent else "Equivalent: none."
        lines += ["", heading]
        for op, line, col, text, mutant, why in sorted(r.equivalent, key=lambda e: (e[1], e[2])):
            lines.append(f"- line {line}:{col} `{op}`: `{text}` -> `{mutant}`: {why}")
    path.write_text("\n".join(lines) + "\n")
