"""Mutation testing of rigidsim's kernels with cosmic-ray (on demand, never in CI).

A *mutant* is the code with one small change (``+`` -> ``-``, ``<`` -> ``<=``, a constant
plus one, ``and`` -> ``or``, a loop that runs zero times, a removed decorator). The tests
*kill* a mutant when they fail on it. A mutant that changes nothing observable (``x * 1.0``
-> ``x / 1.0``) is *equivalent*: no test can kill it, so it is listed, with its reason, in
``scripts/mutation_equivalents.toml`` and left out of the score::

    score = killed / (sampled - equivalent)

How one module is run
---------------------
1. The worktree is copied (without ``.git`` and ``.venv``) to a temporary directory; cosmic-ray
   mutates files of that copy only, never the checkout you work in.
2. ``cosmic-ray init`` lists every mutant of the module. Mutants that only produce a type
   error on floats (arithmetic <-> bitwise/shift, ``//``, ``%``, ``is``, ``in``) are dropped:
   they would be "killed" by any test that runs the line. From the rest a fixed, seeded
   sample (``MODULES[...].sample`` mutants, or ``--per-module``; seed 26) is drawn; the
   others are marked skipped.
3. Stage 1 runs the module's own tests (``MODULES[...].fast``) with ``pytest -x``; stage 2
   re-runs only the survivors against the wider set (``MODULES[...].wide``).
4. The report ``benchmarks/results/mutation-<date>.md`` (written by ``mutation_report.py``)
   lists each module's score, every survivor (line, original and mutated text) and every
   equivalent mutant with its reason.

Usage::

    bash scripts/mutation.sh                       # every module below
    bash scripts/mutation.sh navmesh/step_filter.py engine/physics/solver/integrate.py
    bash scripts/mutation.sh --per-module 20 render/camera.py
    bash scripts/mutation.sh --recheck navmesh/geodesic_field.py   # after adding tests: re-run only
                                                           # the report row's survivors
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import random
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import toml  # a dependency of cosmic-ray (tomllib is Python >= 3.11 only)
from mutation_report import ModuleResult, code_version, write_report

ROOT = Path(__file__).resolve().parents[1]
EQUIVALENTS = ROOT / "scripts" / "mutation_equivalents.toml"
THRESHOLD = 0.90


@dataclass(frozen=True)
class Module:
    """Test subsets of one mutated module (paths relative to the repository root)."""

    fast: tuple[str, ...]  # stage 1: the module's own tests, run with -x on every mutant
    wide: tuple[str, ...]  # stage 2: run only on stage-1 survivors
    sample: int = 60  # mutants drawn per run (``--per-module`` overrides)
    timeout: float = 900.0  # seconds per mutant and stage (a hang counts as killed)


PHYS = "tests/physics/"
REND = "tests/render/"
NAV = "tests/navmesh/"
# 60 sampled mutants per kernel, as in the first measurement; 30 for
# reference_solver, whose tests take 45 s per mutant. A full run of both stages takes about
# three hours on 2 cores; run the modules you changed (see docs/testing.md).
MODULES: dict[str, Module] = {
    "engine/physics/solver/integrate.py": Module(
        (
            PHYS + "test_integration_laws.py",
            PHYS + "test_single_body.py",
            PHYS + "test_split_impulse.py",
        ),
        (PHYS + "test_contact_laws.py", PHYS + "test_solver_switches.py"),
    ),
    "engine/physics/solver/sleeping.py": Module(
        (PHYS + "test_sleep_islands.py",),
        (PHYS + "test_sleeping.py", PHYS + "test_lifecycle.py"),
    ),
    "engine/physics/objects/velocity_control.py": Module(
        (PHYS + "test_velocity_control_frames.py",),
        (PHYS + "test_single_body.py", PHYS + "test_velocity_control_friction.py"),
    ),
    "render/camera.py": Module(
        (REND + "test_camera.py",), (REND + "test_raster.py", REND + "test_frame.py")
    ),
    "navmesh/step_filter.py": Module(
        (NAV + "test_step_filter.py", NAV + "test_step_islands.py"), (NAV + "test_pathfinder.py",)
    ),
    "engine/physics/solver/sequential_impulses.py": Module(
        (PHYS + "test_solver_switches.py", PHYS + "test_split_impulse.py"),
        (
            PHYS + "test_contact_laws.py",
            PHYS + "test_reference_path.py",
            PHYS + "test_translation_invariance.py",
        ),
    ),
    "engine/physics/solver/contact_batch.py": Module(
        (PHYS + "test_manifolds_and_narrow_phase.py",),
        (PHYS + "test_reference_path.py", PHYS + "test_contact_laws.py"),
    ),
    "engine/physics/reference/reference_solver.py": Module(
        (PHYS + "test_reference_path.py",),
        (PHYS + "test_solver_switches.py", PHYS + "test_rolling_friction.py"),
        sample=30,
    ),
    "engine/physics/collision/box_box.py": Module(
        (PHYS + "test_box_box.py",), (PHYS + "test_manifolds_and_narrow_phase.py",)
    ),
    "engine/physics/collision/collide.py": Module(
        (
            PHYS + "test_closest_points.py",
            PHYS + "test_manifolds_and_narrow_phase.py",
            PHYS + "test_box_separation.py",
            PHYS + "test_round_stage_contacts.py",
            PHYS + "test_broad_phase_pairs.py",
            PHYS + "test_sphere_on_stage.py",
        ),
        (
            PHYS + "test_contact_laws.py",
            PHYS + "test_fall_through.py",
            PHYS + "test_contact_cache.py::test_sweep_and_prune_finds_the_brute_force_pairs",
        ),
    ),
    # the narrow phase of body pairs left collide.py for the pair table's batched rules
    "engine/physics/collision/batched_pairs.py": Module(
        (PHYS + "test_pair_table.py", PHYS + "test_manifolds_and_narrow_phase.py"),
        (
            PHYS + "test_box_box.py",
            PHYS + "test_contact_laws.py",
            PHYS + "test_capsule_contacts.py",
            PHYS + "test_round_stage_contacts.py",
        ),
    ),
    "render/raster.py": Module((REND + "test_raster.py",), (REND + "test_frame.py",)),
    "render/frame.py": Module(
        (REND + "test_frame.py",), (REND + "test_reference.py", REND + "test_layers.py")
    ),
    "render/reference.py": Module((REND + "test_reference.py",), (REND + "test_frame.py",)),
    "navmesh/geodesic_field.py": Module(
        (NAV + "test_paths.py", NAV + "test_fast_queries.py"),
        (NAV + "test_scenes.py", NAV + "test_polygons_and_field.py"),
        timeout=120.0,  # a mutant that never stops settling corners hangs (tests: ~15 s)
    ),
    "navmesh/heightfield.py": Module(
        (NAV + "test_build.py", NAV + "test_heightfield_spans.py"),
        (NAV + "test_scenes.py", NAV + "test_pathfinder.py"),
    ),
}

# Mutants that only raise TypeError on floats / numpy arrays (any test executing the line
# "kills" them) say nothing about the tests: they are not generated into the sample.
_ARITH = {"Add", "Sub", "Mul", "Div", "Pow"}
_BITS = {"BitAnd", "BitOr", "BitXor", "LShift", "RShift"}
_NEVER_TARGET = {"FloorDiv", "Mod", "Is", "IsNot", "In", "NotIn"}


def _informative(operator: str) -> bool:
    """False for operator replacements that only produce type errors (see above)."""
    parts = operator.split("/")[-1].split("_")
    if len(parts) != 3:
        return True
    _, source, target = parts
    if target in _NEVER_TARGET or target in {"LShift", "RShift"}:
        return False
    return not ((source in _ARITH and target in _BITS) or (source in _BITS and target in _ARITH))


def _copy_tree(dest: Path) -> None:
    """Copy the repository (sources and tests only) to ``dest``."""
    ignore = shutil.ignore_patterns(
        ".git", ".venv", "__pycache__", "*.pyc", ".mypy_cache", ".ruff_cache", ".pytest_cache"
    )
    for name in ("engine", "render", "navmesh", "tests", "pyproject.toml"):
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, dest / name, ignore=ignore)
        else:
            shutil.copy2(src, dest / name)


def _config(module: str, tests: tuple[str, ...], timeout: float) -> str:
    """A cosmic-ray TOML config running ``tests`` with the current interpreter."""
    existing = [t for t in tests if (ROOT / t.split("::")[0]).exists()]  # file or node id
    command = f"{sys.executable} -m pytest -q -x -p no:cacheprovider " + " ".join(existing)
    return (
        "[cosmic-ray]\n"
        f'module-path = "{module}"\n'
        f"timeout = {timeout}\n"
        "excluded-modules = []\n"
        f'test-command = "{command}"\n'
        '[cosmic-ray.distributor]\nname = "local"\n'
    )


def _cosmic_ray(work: Path, *args: str) -> None:
    env = dict(os.environ, PYTHONPATH=str(work))
    cosmic_ray = str(Path(sys.executable).parent / "cosmic-ray")
    subprocess.run([cosmic_ray, *args], cwd=work, env=env, check=True)


def _line_text(work: Path, module: str, line: int) -> str:
    return (work / module).read_text().splitlines()[line - 1].strip()


def _load_equivalents() -> dict[tuple[str, str, str], str]:
    """``(module, original line, mutated line) -> reason`` (lines stripped) from the TOML."""
    data = toml.loads(EQUIVALENTS.read_text()) if EQUIVALENTS.exists() else {}
    return {(e["module"], e["line"], e["mutant"]): e["reason"] for e in data.get("equivalent", [])}


def _mutated_line(work: Path, module: str, operator: str, occurrence: int, row: int) -> str:
    """The stripped source line ``row`` after the mutation (what the equivalents match)."""
    from cosmic_ray.mutating import mutate_code
    from cosmic_ray.plugins import get_operator

    mutated = mutate_code((work / module).read_text(), get_operator(operator)(), occurrence)
    lines = (mutated or "").splitlines()
    return lines[row - 1].strip() if row <= len(lines) else ""


def _jobs(session: Path) -> list[tuple[str, str, int, int, int]]:
    """``(job_id, operator, occurrence, line, col)`` of every mutant, in a stable order."""
    with sqlite3.connect(session) as db:
        rows = db.execute(
            "SELECT job_id, operator_name, occurrence, start_pos_row, start_pos_col "
            "FROM mutation_specs"
        ).fetchall()
    return sorted(rows, key=lambda r: (r[1], r[2]))


def _mark_skipped(session: Path, job_ids: list[str]) -> None:
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import WorkerOutcome, WorkResult

    with use_db(str(session), WorkDB.Mode.open) as db:
        db.set_multiple_results(job_ids, WorkResult(worker_outcome=WorkerOutcome.SKIPPED))


def _results(session: Path) -> dict[str, tuple[str, str | None, str | None]]:
    """``job_id -> (worker_outcome, test_outcome, output)``; cosmic-ray's output of a test
    run that hit the timeout is the word ``timeout`` (counted as killed)."""
    with sqlite3.connect(session) as db:
        rows = db.execute(
            "SELECT job_id, worker_outcome, test_outcome, output FROM work_results"
        ).fetchall()
    # SQLAlchemy stores the enum member names (SURVIVED, KILLED, ...)
    return {r[0]: (str(r[1]).lower(), str(r[2]).lower(), r[3]) for r in rows}


def _reset(session: Path, job_ids: list[str]) -> None:
    with sqlite3.connect(session) as db:
        db.executemany("DELETE FROM work_results WHERE job_id = ?", [(j,) for j in job_ids])


def _recheck_plan(earlier: ModuleResult, sample: list, to_run: list) -> tuple[list, list[tuple]]:
    """``(jobs to run, kills kept)`` for ``--recheck``: the earlier row's survivors that are
    not listed as equivalent now. Its kills stand: tests were only added since, and a test
    added cannot bring a killed mutant back. The library code must be unchanged (the same
    sample of lines and columns), or the module is to be run in full."""

    def key(e) -> tuple:  # operator, line, column
        return (e[0], e[1], e[2])

    sampled = {(j[1], j[3], j[4]) for j in sample}
    if not {key(e) for e in earlier.killed + earlier.survived} <= sampled:
        raise SystemExit(f"{earlier.module}: the code changed since its row; run it in full")
    running = {(j[1], j[3], j[4]) for j in to_run}
    survivors = {key(e) for e in earlier.survived}
    # a kill sharing (operator, line, column) with a survivor runs again: count it once
    kept = [tuple(e) for e in earlier.killed if key(e) in running and key(e) not in survivors]
    return [j for j in to_run if (j[1], j[3], j[4]) in survivors], kept


def run_module(
    work: Path,
    module: str,
    per_module: int | None,
    seed: int,
    list_only: bool = False,
    recheck: ModuleResult | None = None,
) -> ModuleResult:
    """Sample, run both stages and classify the mutants of one module (with ``recheck``, an
    earlier result of the same sample: only its survivors are run again)."""
    spec = MODULES[module]
    t0 = time.monotonic()
    code = code_version()  # the copy in ``work`` was made just now
    tag = module.replace("/", "_")
    session = work / f"{tag}.sqlite"
    fast_cfg, wide_cfg = work / f"{tag}.fast.toml", work / f"{tag}.wide.toml"
    fast_cfg.write_text(_config(module, spec.fast, spec.timeout))
    wide_cfg.write_text(_config(module, spec.fast + spec.wide, spec.timeout))
    _cosmic_ray(work, "init", str(fast_cfg), str(session))

    jobs = _jobs(session)
    informative = [j for j in jobs if _informative(j[1])]
    rng = random.Random(f"{seed}:{module}")
    n_sample = spec.sample if per_module is None else per_module
    if recheck is not None:
        n_sample = recheck.n_sampled
    sample = rng.sample(informative, min(n_sample, len(informative)))
    sampled_ids = {j[0] for j in sample}
    equivalents = _load_equivalents()
    equivalent, to_run, mutant_text = [], [], {}
    for job in sample:
        text = _line_text(work, module, job[3])
        mutant_text[job[0]] = _mutated_line(work, module, job[1], job[2], job[3])
        reason = equivalents.get((module, text, mutant_text[job[0]]))
        if reason is None:
            to_run.append(job)
        else:
            equivalent.append((job[1], job[3], job[4], text, mutant_text[job[0]], reason))
    killed: list[tuple] = []
    if recheck is not None:
        to_run, killed = _recheck_plan(recheck, sample, to_run)
    skipped = [j[0] for j in jobs if j[0] not in sampled_ids] + [
        j[0] for j in sample if j not in to_run
    ]
    _mark_skipped(session, skipped)
    if list_only:  # --list: print the sample for triage, run nothing
        for job in sorted(to_run, key=lambda j: (j[3], j[4])):
            text = _line_text(work, module, job[3])
            print(f"{module}:{job[3]}:{job[4]} {job[1]}\n    {text}\n    {mutant_text[job[0]]}")
        to_run = []
    print(
        f"[{module}] {len(jobs)} mutants, {len(informative)} informative, "
        f"{len(sample)} sampled, {len(equivalent)} known equivalent",
        flush=True,
    )

    if to_run:  # stage 1: the module's own tests, -x
        _cosmic_ray(work, "exec", str(fast_cfg), str(session))
    results = _results(session)
    survivors = [j[0] for j in to_run if results[j[0]][1] == "survived"]
    if survivors:  # stage 2: the wider test set, survivors only
        print(f"[{module}] stage 2 for {len(survivors)} survivors", flush=True)
        _reset(session, survivors)
        _cosmic_ray(work, "exec", str(wide_cfg), str(session))
        results = _results(session)

    survived = []
    for job in to_run:
        _worker, outcome, output = results[job[0]]
        entry = (job[1], job[3], job[4], _line_text(work, module, job[3]), mutant_text[job[0]])
        if outcome == "survived":
            survived.append(entry)
        else:
            killed.append(entry + ((output or "").strip() == "timeout",))
    return ModuleResult(
        module,
        len(jobs),
        len(sample),
        killed,
        survived,
        equivalent,
        time.monotonic() - t0 + (recheck.seconds if recheck else 0.0),
        code if recheck is None else f"{recheck.code}, survivors rechecked at {code}",
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("modules", nargs="*", help="module paths (default: all)")
    parser.add_argument(
        "--per-module", type=int, default=None, help="sampled mutants per module (all modules)"
    )
    parser.add_argument("--seed", type=int, default=26)
    parser.add_argument("--jobs", type=int, default=2, help="modules run in parallel")
    parser.add_argument("--list", action="store_true", help="print the sample, run no test")
    parser.add_argument(
        "--recheck",
        action="store_true",
        help="run again only the survivors of the modules' rows in the report (after adding "
        "tests; the library code must be unchanged)",
    )
    parser.add_argument("--report", type=Path, default=None, help="report path")
    args = parser.parse_args(argv)
    modules = args.modules or list(MODULES)
    unknown = [m for m in modules if m not in MODULES]
    if unknown:
        parser.error(f"unknown modules {unknown}; known: {list(MODULES)}")
    report = args.report or (
        ROOT / "benchmarks" / "results" / f"mutation-{datetime.date.today().isoformat()}.md"
    )
    results: list[ModuleResult] = []
    lock = threading.Lock()
    earlier: dict[str, ModuleResult] = {}
    if args.recheck:
        twin = report.with_suffix(".json")
        rows = json.loads(twin.read_text()) if twin.exists() else []
        earlier = {r["module"]: ModuleResult(**r) for r in rows}
        missing = [m for m in modules if m not in earlier]
        if missing:
            parser.error(f"--recheck: no row for {missing} in {twin}")

    def one(module: str) -> None:
        with tempfile.TemporaryDirectory(prefix="rigidsim-mutation-") as tmp:
            work = Path(tmp)
            _copy_tree(work)  # one copy per module: parallel jobs never share a mutated file
            result = run_module(
                work, module, args.per_module, args.seed, args.list, earlier.get(module)
            )
        with lock:
            results.append(result)
            results.sort(key=lambda r: modules.index(r.module))
            write_report(report, results, args.seed, list(MODULES))

    if args.list:
        for module in modules:
            with tempfile.TemporaryDirectory(prefix="rigidsim-mutation-") as tmp:
                _copy_tree(Path(tmp))
                run_module(Path(tmp), module, args.per_module, args.seed, list_only=True)
        return 0
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for future in [pool.submit(one, m) for m in modules]:
            future.result()
    print()
    ok = True
    for r in results:
        n = len(r.killed) + len(r.survived)
        passed = r.score >= THRESHOLD
        ok &= passed
        print(
            f"{r.module:40s} {len(r.killed):3d}/{n:3d} killed = {100 * r.score:5.1f} %  "
            f"({len(r.equivalent)} equivalent)  {'OK' if passed else 'BELOW 90 %'}"
        )
    print(f"report: {report.relative_to(ROOT) if report.is_relative_to(ROOT) else report}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
