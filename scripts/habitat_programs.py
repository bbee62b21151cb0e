"""Run Habitat-sim's own example programs and tests against rigidsim, changing only imports.

A user brings a copy of habitat-sim (a checkout, or a bare git directory such as a mirror); this
script exports its ``examples/`` and ``tests/`` into a work folder and rewrites only the import
lines there:

    import habitat_sim               ->  import engine as habitat_sim
    import habitat_sim.utils.common  ->  import engine.utils.common; import engine as habitat_sim
    from habitat_sim.x import y      ->  from engine.x import y
    import magnum as mn              ->  from engine import mn
    from magnum import Vector3       ->  from engine.mn import Vector3

Data paths are changed by a folder of stand-ins, ``<work>/data`` (each program still opens the
path it names; built by ``habitat_stand_ins.py``, which lists them): rigidsim's demo apartment
for Habitat's test scenes (moved for skokloster-castle so that ``example.py``'s hard-coded goal
is on its navmesh; hard-coded positions and path lengths still differ), rigidsim's demo
objects, and Habitat's MIT test assets (``tests/habitat_data``, or the copy
``RIGIDSIM_HABITAT_DATA`` names).

Nothing of habitat-sim is copied into this repository: the work folder is temporary unless
``--keep`` names one.

The programs and their arguments are those Habitat's own ``tests/test_examples.py`` runs. Usage:

    python scripts/habitat_programs.py --habitat-sim PATH [--only NAME] [--example-frames N]
                                       [--tests [PYTEST_ARGS]]

prints one line per program (ran to the end, or the last line of its error; its run time) and
the count. ``--example-frames N`` runs ``example.py`` for N frames (``--max_frames N``) instead
of its default 1000, for a quicker pass over its 48 flag combinations.
"""

from __future__ import annotations

import argparse
import itertools
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]

#: (name, script, arguments) as Habitat's tests/test_examples.py runs them (in-scope programs only)
EXAMPLE_FLAGS = (
    "--compute_shortest_path",
    "--compute_action_shortest_path",
    "--enable_physics",
    "--semantic_sensor",
    "--depth_sensor",
    "--recompute_navmesh",
)
TUTORIALS = (
    ("asset_viewer", "examples/tutorials/nb_python/asset_viewer.py",
     "--no-show-video --no-make-video"),
    ("stereo_agent", "examples/tutorials/stereo_agent.py", "--no-display"),
    ("lighting", "examples/tutorials/lighting_tutorial.py", "--no-show-images"),
    ("managed_rigid_object", "examples/tutorials/nb_python/managed_rigid_object_tutorial.py",
     "--no-show-video --no-make-video"),
    ("new_actions", "examples/tutorials/new_actions.py", ""),
    ("eccv_navigation", "examples/tutorials/nb_python/ECCV_2020_Navigation.py",
     "--no-make-video --no-display"),
    ("semantic_id", "examples/tutorials/semantic_id_tutorial.py", "--no-show-images"),
    ("async_rendering", "examples/tutorials/async_rendering.py", ""),
    ("eccv_interactivity", "examples/tutorials/nb_python/ECCV_2020_Interactivity.py",
     "--no-make-video --no-display"),
    ("eccv_advanced_features", "examples/tutorials/nb_python/ECCV_2020_Advanced_Features.py",
     "--no-make-video --no-display"),
    ("coordinate_frame", "examples/tutorials/nb_python/coordinate_frame_tutorial.py",
     "--no-show-video --no-make-video"),
    ("benchmark", "examples/benchmark.py", ""),
)  # fmt: skip

IMPORT_LINE = re.compile(r"^(\s*)(import|from)\s+(habitat_sim|magnum)\b(.*)$")


def example_programs() -> list[tuple[str, str, list[str]]]:
    """Every (name, script, argv) that Habitat's tests run, ``example.py`` with its flag sets."""
    programs = [(name, script, args.split()) for name, script, args in TUTORIALS]
    for count in range(len(EXAMPLE_FLAGS) + 1):
        for flags in itertools.combinations(EXAMPLE_FLAGS, count):
            if "--compute_action_shortest_path" in flags and "--enable_physics" in flags:
                continue
            name = "example" + "".join(flag.replace("--", " ") for flag in flags)
            programs.append((name, "examples/example.py", list(flags)))
    return programs


def rewrite_import(line: str) -> str:
    """Return ``line`` with a habitat_sim / magnum import pointed at rigidsim (others unchanged)."""
    match = IMPORT_LINE.match(line)
    if match is None:
        return line
    indent, keyword, package, rest = match.groups()
    target = "engine" if package == "habitat_sim" else "engine.mn"
    if keyword == "from":
        return f"{indent}from {target}{rest}"
    if package == "magnum":
        if rest.strip().startswith("as "):
            return f"{indent}from engine import mn as {rest.strip()[3:]}"
        return f"{indent}import engine.mn as magnum{rest}"
    if rest.startswith("."):  # import habitat_sim.utils.common [as x]
        if " as " in rest:
            return f"{indent}import {target}{rest}"
        return f"{indent}import {target}{rest}; import engine as habitat_sim"
    return f"{indent}import engine as habitat_sim{rest}"


def export_tree(habitat_sim: Path, work: Path) -> None:
    """Copy habitat-sim's examples/ and tests/ into ``work`` (from a checkout or a git dir).

    ``work`` becomes a git repository too: the notebooks find their data through
    ``git.Repo(".", search_parent_directories=True).working_tree_dir``.
    """
    if (habitat_sim / "examples").is_dir():
        for folder in ("examples", "tests"):
            shutil.copytree(habitat_sim / folder, work / folder)
    else:
        archive = subprocess.run(
            ["git", "-C", str(habitat_sim), "archive", "HEAD", "examples", "tests"],
            check=True,
            capture_output=True,
        ).stdout
        subprocess.run(["tar", "-x", "-C", str(work)], input=archive, check=True)
    subprocess.run(["git", "init", "-q", str(work)], check=True)


def rewrite_imports(work: Path) -> int:
    """Rewrite the import lines of every Python file under ``work``; return how many changed."""
    changed = 0
    for path in work.rglob("*.py"):
        lines = path.read_text(encoding="utf-8").splitlines(keepends=True)
        new = [
            rewrite_import(line.rstrip("\n")) + ("\n" if line.endswith("\n") else "")
            for line in lines
        ]
        changed += sum(a != b for a, b in zip(lines, new, strict=True))
        path.write_text("".join(new), encoding="utf-8")
    return changed


def run_program(work: Path, script: str, argv: list[str], timeout: float) -> tuple[bool, str]:
    """Run one program as Habitat's tests do (its folder on sys.path); return (ok, last line)."""
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join([str(REPO_ROOT), str(work)]), MPLBACKEND="Agg"
    )
    command = [sys.executable, str(work / script), *argv]
    try:
        done = subprocess.run(
            command, cwd=work, env=env, capture_output=True, text=True, timeout=timeout
        )
    except subprocess.TimeoutExpired:
        return False, f"timed out after {timeout:.0f} s"
    if done.returncode == 0:
        return True, "ran to the end"
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    return False, lines[-1] if lines else f"exit code {done.returncode}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--habitat-sim", type=Path, required=True, help="checkout or git directory")
    parser.add_argument("--only", help="run the programs whose name contains this text")
    parser.add_argument("--timeout", type=float, default=600.0, help="seconds per program")
    parser.add_argument("--keep", type=Path, help="work folder to keep (default: temporary)")
    parser.add_argument(
        "--example-frames", type=int, help="frames per example.py run (default: its 1000)"
    )
    parser.add_argument("--tests", nargs=argparse.REMAINDER, help="run Habitat's pytest tests")
    options = parser.parse_args()
    sys.path.insert(0, str(REPO_ROOT))
    from habitat_stand_ins import link_data

    from engine.demo import demo_data_path

    assets = Path(os.environ.get("RIGIDSIM_HABITAT_DATA", REPO_ROOT / "tests" / "habitat_data"))
    work = options.keep or Path(tempfile.mkdtemp(prefix="habitat-programs-"))
    if not (work / "examples").exists():
        work.mkdir(parents=True, exist_ok=True)
        export_tree(options.habitat_sim.resolve(), work)
        print(f"rewrote {rewrite_imports(work)} import lines in {work}")
        link_data(work, demo_data_path().resolve(), assets.resolve())
    if options.tests is not None:
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO_ROOT), str(work / "tests")]))
        pytest = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"]
        named = any(arg.startswith("tests") for arg in options.tests)  # else every test file
        chosen = options.tests if named else ["tests", *options.tests]
        return subprocess.run([*pytest, *chosen], cwd=work, env=env).returncode
    programs = [p for p in example_programs() if not options.only or options.only in p[0]]
    passed = 0
    for name, script, argv in programs:
        if options.example_frames is not None and script == "examples/example.py":
            argv = [*argv, "--max_frames", str(options.example_frames)]
        started = time.monotonic()
        ok, last = run_program(work, script, argv, options.timeout)
        seconds = time.monotonic() - started
        passed += ok
        print(f"{'PASS' if ok else 'FAIL'}  {name:<60} {seconds:6.0f} s  {last[:160]}", flush=True)
    print(f"{passed} of {len(programs)} programs ran to the end")
    return 0 if passed == len(programs) else 1


if __name__ == "__main__":
    sys.exit(main())
