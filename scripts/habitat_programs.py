"""Run Habitat-sim's own example programs and tests against rigidsim, changing only imports.

A user brings a copy of habitat-sim (a checkout, or a bare git directory such as a mirror); this
script exports its ``examples/`` and ``tests/`` into a work folder and rewrites only the import
lines there:

    import habitat_sim               ->  import engine as habitat_sim
    import habitat_sim.utils.common  ->  import engine.utils.common; import engine as habitat_sim
    from habitat_sim.x import y      ->  from engine.x import y
    import magnum as mn              ->  from engine import mn
    from magnum import Vector3       ->  from engine.mn import Vector3

Data paths are changed by a folder of links, ``<work>/data`` (the stand-ins; each program still
opens the path it names):

- ``scene_datasets/habitat-test-scenes/{skokloster-castle,van-gogh-room,apartment_1}.glb`` and
  ``.navmesh``: rigidsim's demo apartment (so hard-coded positions and path lengths differ);
- ``scene_datasets/mp3d_example/17DRP5sb8fy/17DRP5sb8fy.glb`` and ``.navmesh`` (the ECCV
  notebooks' mp3d scene): the demo apartment again;
- ``scene_datasets/mp3d_example/mp3d.scene_dataset_config.json``: a generated dataset config
  whose only stage template is the demo apartment's (no semantic annotations: the semantic
  scene is empty);
- ``replica_cad/``: a generated ReplicaCAD-like scene dataset (``replicaCAD.scene_dataset_config
  .json``, ``configs/{stages,objects,scenes}``): the demo apartment as ``frl_apartment_stage``,
  demo objects under ReplicaCAD's names (``frl_apartment_chair_01`` is the cracker box, scaled
  3x) and a scene instance ``v3_sc0_staging_00`` placing four of them;
- ``objects/example_objects``, ``objects/locobot_merged``: rigidsim's demo objects;
- ``test_assets``: Habitat's MIT test assets (``../shared/assets/habitat/data`` or
  ``RIGIDSIM_HABITAT_DATA``), plus the demo's ``test_assets`` files they lack.

Nothing of habitat-sim is copied into this repository: the work folder is temporary unless
``--keep`` names one.

The programs and their arguments are those Habitat's own ``tests/test_examples.py`` runs. Usage:

    python scripts/habitat_programs.py --habitat-sim PATH [--only NAME] [--tests [PYTEST_ARGS]]

(``--tests tests/test_sensors.py -x`` runs the files named, ``--tests -k gfx`` all of them)

prints one line per program (ran to the end, or the last line of its error) and the count.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
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

#: Habitat's data paths -> the stand-ins (paths relative to the demo data or the test assets)
STAND_INS = {
    "scene_datasets/habitat-test-scenes/skokloster-castle": "demo:scene_datasets/demo/apartment",
    "scene_datasets/habitat-test-scenes/van-gogh-room": "demo:scene_datasets/demo/apartment",
    "scene_datasets/habitat-test-scenes/apartment_1": "demo:scene_datasets/demo/apartment",
    "scene_datasets/mp3d_example/17DRP5sb8fy/17DRP5sb8fy": "demo:scene_datasets/demo/apartment",
}
#: scene dataset configs Habitat's programs name, generated: (path under data/, JSON content)
GENERATED_CONFIGS = (
    # the mp3d example dataset: its one stage, the demo apartment linked above
    (
        "scene_datasets/mp3d_example/mp3d.scene_dataset_config.json",
        {"stages": {"paths": {".json": ["../demo"]}}, "objects": {"paths": {".json": []}}},
    ),
)
# ReplicaCAD (the coordinate frame tutorial): a scene dataset of the same layout, generated
_REPLICA = "replica_cad"
_REPLICA_OBJECTS = {  # stand-in object name -> (demo asset, scale, mass kg)
    "frl_apartment_chair_01": ("objects/example_objects/cheezit.glb", 3.0, 5.0),
    "frl_apartment_bowl_07": ("objects/example_objects/chefcan.glb", 1.0, 0.4),
    "frl_apartment_kitchen_utensil_01": ("objects/example_objects/banana.glb", 1.0, 0.1),
}
GENERATED_LINKS = (  # (path under data/, path in the demo data)
    (f"{_REPLICA}/stages/frl_apartment_stage.glb", "scene_datasets/demo/apartment.glb"),
    (f"{_REPLICA}/stages/frl_apartment_stage.navmesh", "scene_datasets/demo/apartment.navmesh"),
    *(
        (f"{_REPLICA}/objects/{name}.glb", asset)
        for name, (asset, _, _) in _REPLICA_OBJECTS.items()
    ),
)
GENERATED_CONFIGS += (
    (
        f"{_REPLICA}/replicaCAD.scene_dataset_config.json",
        {
            "stages": {"paths": {".json": ["configs/stages"]}},
            "objects": {"paths": {".json": ["configs/objects"]}},
            "scene_instances": {"paths": {".json": ["configs/scenes"]}},
        },
    ),
    (
        f"{_REPLICA}/configs/stages/frl_apartment_stage.stage_config.json",
        {"render_asset": "../../stages/frl_apartment_stage.glb", "up": [0, 1, 0],
         "front": [0, 0, -1], "nav_asset": "../../stages/frl_apartment_stage.navmesh"},
    ),
    *(
        (
            f"{_REPLICA}/configs/objects/{name}.object_config.json",
            {"render_asset": f"../../objects/{name}.glb", "scale": [scale] * 3, "mass": mass},
        )
        for name, (_, scale, mass) in _REPLICA_OBJECTS.items()
    ),
    (  # the demo apartment's floor is at y = -1.45 m
        f"{_REPLICA}/configs/scenes/v3_sc0_staging_00.scene_instance.json",
        {
            "translation_origin": "asset_local",
            "stage_instance": {"template_name": "stages/frl_apartment_stage"},
            "object_instances": [
                {"template_name": "objects/frl_apartment_chair_01", "motion_type": "DYNAMIC",
                 "translation": [1.5, -1.13, -0.5], "rotation": [0.924, 0, 0.383, 0]},
                {"template_name": "objects/frl_apartment_chair_01", "motion_type": "DYNAMIC",
                 "translation": [0.5, -1.13, 1.5], "rotation": [1, 0, 0, 0]},
                {"template_name": "objects/frl_apartment_bowl_07", "motion_type": "STATIC",
                 "translation": [2.0, -0.82, -1.0], "rotation": [1, 0, 0, 0]},
                {"template_name": "objects/frl_apartment_kitchen_utensil_01",
                 "motion_type": "DYNAMIC", "translation": [2.2, -0.86, -1.1],
                 "rotation": [0.707, 0, 0.707, 0]},
            ],
        },
    ),
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


def link_data(work: Path, demo: Path, assets: Path) -> None:
    """Build ``work/data``: Habitat's data layout as links to the demo data and the test assets."""
    data = work / "data"
    for sub in ("objects", "scene_datasets/demo"):
        (data / sub).parent.mkdir(parents=True, exist_ok=True)
        (data / sub).symlink_to(demo / sub, target_is_directory=True)
    test_assets = data / "test_assets"
    shutil.copytree(assets / "test_assets", test_assets, symlinks=True)
    for extra in (demo / "test_assets").rglob("*"):
        target = test_assets / extra.relative_to(demo / "test_assets")
        if extra.is_file() and not target.exists():
            target.parent.mkdir(parents=True, exist_ok=True)
            target.symlink_to(extra)
    for config in assets.glob("*.json"):
        (data / config.name).symlink_to(config)
    for habitat_name, stand_in in STAND_INS.items():
        source = demo / stand_in.removeprefix("demo:")
        for suffix in (".glb", ".navmesh"):
            link = data / (habitat_name + suffix)
            link.parent.mkdir(parents=True, exist_ok=True)
            link.symlink_to(source.with_suffix(suffix))
    for relative, target in GENERATED_LINKS:
        (data / relative).parent.mkdir(parents=True, exist_ok=True)
        (data / relative).symlink_to(demo / target)
    for relative, content in GENERATED_CONFIGS:
        (data / relative).parent.mkdir(parents=True, exist_ok=True)
        (data / relative).write_text(json.dumps(content, indent=2) + "\n", encoding="utf-8")


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
    parser.add_argument("--tests", nargs=argparse.REMAINDER, help="run Habitat's pytest tests")
    options = parser.parse_args()
    sys.path.insert(0, str(REPO_ROOT))
    from engine.demo import demo_data_path

    assets = Path(
        os.environ.get("RIGIDSIM_HABITAT_DATA", REPO_ROOT.parent / "shared/assets/habitat/data")
    )
    work = options.keep or Path(tempfile.mkdtemp(prefix="habitat-programs-"))
    if not (work / "examples").exists():
        work.mkdir(parents=True, exist_ok=True)
        export_tree(options.habitat_sim.resolve(), work)
        print(f"rewrote {rewrite_imports(work)} import lines in {work}")
        link_data(work, demo_data_path().resolve(), assets.resolve())
    if options.tests is not None:
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO_ROOT), str(work / "tests")]))
        pytest = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"]
        named = any(arg.startswith("tests/") for arg in options.tests)  # else every test file
        paths = [] if named else ["tests"]
        return subprocess.run([*pytest, *paths, *options.tests], cwd=work, env=env).returncode
    programs = [p for p in example_programs() if not options.only or options.only in p[0]]
    passed = 0
    for name, script, argv in programs:
        ok, last = run_program(work, script, argv, options.timeout)
        passed += ok
        print(f"{'PASS' if ok else 'FAIL'}  {name:<60} {last[:160]}", flush=True)
    print(f"{passed} of {len(programs)} programs ran to the end")
    return 0 if passed == len(programs) else 1


if __name__ == "__main__":
    sys.exit(main())
