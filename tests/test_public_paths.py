"""Every module path Habitat code imports as ``habitat_sim.X`` imports as ``engine.X``.

``engine/`` is organised by concept (``scene/``, ``sensors/``, ``templates/``, ``nav/``,
``simulator/`` ...), while Habitat's programs, its tests and habitat-lab import
``habitat_sim.X`` paths; each such path stays importable as ``engine.X``, either as the folder
itself (a package whose ``__init__`` re-exports Habitat's names) or as a thin face module.
:data:`HABITAT_PATHS` lists those paths with the names Habitat code takes from each (read from
Habitat-sim's tests and examples and from habitat-lab). The names the notebooks, the example
programs and the documentation import or quote are read from those files, so a module moved
without its readers fails here.
"""

from __future__ import annotations

import ast
import importlib
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Habitat's module path (``habitat_sim`` -> ``engine``) -> names Habitat code imports from it
HABITAT_PATHS: dict[str, tuple[str, ...]] = {
    "engine": (
        "ActionSpec",
        "ActuationSpec",
        "Agent",
        "AgentConfiguration",
        "AgentState",
        "CameraSensorSpec",
        "Configuration",
        "EquirectangularSensorSpec",
        "FisheyeSensorDoubleSphereSpec",
        "FisheyeSensorModelType",
        "GreedyGeodesicFollower",
        "MultiGoalShortestPath",
        "NavMeshSettings",
        "PathFinder",
        "RigidState",
        "SceneGraph",
        "SceneNode",
        "SensorSubType",
        "SensorType",
        "ShortestPath",
        "Simulator",
        "SimulatorConfiguration",
        "built_with_bullet",
        "stage_id",
    ),
    "engine.agent": (
        "Agent",
        "AgentConfiguration",
        "AgentState",
        "SceneNodeControl",
        "ActuationSpec",
    ),
    "engine.agent.agent": ("ActionSpec", "AgentState", "SixDOFPose"),
    "engine.agent.controls": ("ActuationSpec", "ObjectControls", "SceneNodeControl"),
    "engine.agent.controls.controls": ("ActuationSpec", "SceneNodeControl"),
    "engine.agent.controls.default_controls": ("DEFAULT_CONTROLS",),
    "engine.agent.controls.pyrobot_noisy_controls": ("PyRobotNoisyActuationSpec",),
    "engine.attributes": ("ObjectAttributes", "StageAttributes", "PhysicsManagerAttributes"),
    "engine.attributes_managers": (
        "AssetAttributesManager",
        "ObjectAttributesManager",
        "PhysicsAttributesManager",
        "StageAttributesManager",
    ),
    "engine.bindings": ("Configuration", "RigidState", "SceneNode", "stage_id"),
    "engine.errors": ("GreedyFollowerError",),
    "engine.geo": ("FRONT", "UP", "GRAVITY", "Ray", "get_transformed_bb"),
    "engine.gfx": ("LightInfo", "LightPositionModel", "DEFAULT_LIGHTING_KEY", "NO_LIGHT_KEY"),
    "engine.logging": ("logger",),
    "engine.metadata": ("MetadataMediator",),
    "engine.nav": ("GreedyGeodesicFollower", "NavMeshSettings", "PathFinder", "ShortestPath"),
    "engine.physics": (
        "CollisionGroupHelper",
        "CollisionGroups",
        "ManagedRigidObject",
        "MotionType",
        "RayHitInfo",
        "RaycastResults",
        "RigidConstraintSettings",
        "RigidConstraintType",
        "RigidObjectManager",
        "VelocityControl",
    ),
    "engine.registry": ("registry", "register_move_fn", "get_move_fn"),
    "engine.scene": ("SceneGraph", "SceneNode", "SemanticRegion", "SemanticScene"),
    "engine.sensor": ("CameraSensor", "SensorFactory", "SensorSpec", "SensorType", "VisualSensor"),
    "engine.sensors": ("sensor_wrapper",),
    "engine.sensors.sensor_wrapper": ("Sensor",),
    "engine.simulator": ("Configuration", "Simulator", "SimulatorConfiguration", "Agent"),
    "engine.utils": ("common", "datasets_download", "profiling_utils", "settings", "viz_utils"),
    "engine.utils.common": (
        "d3_40_colors_rgb",
        "orthonormalize_rotation_shear",
        "quat_from_angle_axis",
        "quat_from_magnum",
        "quat_to_coeffs",
        "random_quaternion",
    ),
    "engine.utils.settings": ("default_sim_settings", "make_cfg"),
    "engine.utils.viz_utils": ("make_video",),
    "engine.utils.profiling_utils": ("range_push", "range_pop"),
}


@pytest.mark.parametrize("path", sorted(HABITAT_PATHS))
def test_habitat_path_imports_with_its_names(path: str) -> None:
    module = importlib.import_module(path)
    missing = [name for name in HABITAT_PATHS[path] if not hasattr(module, name)]
    assert missing == [], f"{path} lacks {missing}"


def imports_of(source: str) -> list[tuple[str, tuple[str, ...]]]:
    """``(module, names)`` of every ``import engine...`` / ``from engine... import`` in the
    Python ``source`` (names empty for ``import x``). Source that does not parse as a whole
    (a notebook magic, a table row quoting an import) is read line by line."""
    try:
        trees = [ast.parse(source)]
    except SyntaxError:
        trees = []
        for line in source.splitlines():
            if re.match(r"\s*(from|import) engine\b", line):
                try:
                    trees.append(ast.parse(line.strip()))
                except SyntaxError:
                    continue
    found = []
    for tree in trees:
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                if node.module.split(".")[0] == "engine":
                    names = tuple(a.name for a in node.names if a.name != "*")
                    found.append((node.module, names))
            elif isinstance(node, ast.Import):
                found += [(a.name, ()) for a in node.names if a.name.split(".")[0] == "engine"]
    return found


def markdown_code(path: Path) -> str:
    """The fenced code blocks of a page, one after the other."""
    blocks = re.findall(r"```[\w-]*\n(.*?)```", path.read_text("utf-8"), re.S)
    return "\n".join(blocks)


def notebook_code(path: Path) -> str:
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    code = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
    return "\n".join(line for line in code.splitlines() if not line.lstrip().startswith(("%", "!")))


def reader_imports() -> dict[tuple[str, tuple[str, ...]], str]:
    """Every engine import of the notebooks, examples and docs -> the first file with it."""
    sources = {p: notebook_code(p) for p in sorted((ROOT / "notebooks").glob("*.ipynb"))}
    sources |= {p: p.read_text("utf-8") for p in sorted((ROOT / "examples").glob("*.py"))}
    sources |= {p: markdown_code(p) for p in sorted((ROOT / "docs").glob("*.md"))}
    sources[ROOT / "README.md"] = markdown_code(ROOT / "README.md")
    found: dict[tuple[str, tuple[str, ...]], str] = {}
    for path, source in sources.items():
        for entry in imports_of(source):
            found.setdefault(entry, str(path.relative_to(ROOT)))
    return found


READER_IMPORTS = reader_imports()


def test_the_readers_import_something() -> None:
    modules = {module for module, _ in READER_IMPORTS}
    assert {"engine", "engine.utils.settings", "engine.demo"} <= modules


@pytest.mark.parametrize(
    ("module", "names"), sorted(READER_IMPORTS), ids=lambda v: v if isinstance(v, str) else None
)
def test_every_import_of_the_notebooks_examples_and_docs_works(
    module: str, names: tuple[str, ...]
) -> None:
    imported = importlib.import_module(module)
    missing = [n for n in names if not hasattr(imported, n)]
    for name in list(missing):  # ``from package import submodule``
        try:
            importlib.import_module(f"{module}.{name}")
            missing.remove(name)
        except ImportError:
            pass
    assert missing == [], f"{READER_IMPORTS[(module, names)]}: {module} lacks {missing}"


def resolves(dotted: str) -> bool:
    """Whether ``engine.a.b.C`` names a module or an attribute of one."""
    parts = dotted.split(".")
    for end in range(len(parts), 0, -1):
        try:
            found = importlib.import_module(".".join(parts[:end]))
        except ImportError:
            continue
        for part in parts[end:]:
            if not hasattr(found, part):
                return False
            found = getattr(found, part)
        return True
    return False


def test_every_dotted_engine_name_the_docs_quote_resolves() -> None:
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    quoted = {
        (page.name, dotted)
        for page in pages
        for code in re.findall(r"`([^`\n]+)`", page.read_text("utf-8"))
        for dotted in re.findall(r"(?<![\w./])engine(?:\.[A-Za-z_]\w*)+", code)
    }
    assert len(quoted) > 20
    wrong = sorted(f"{page}: {dotted}" for page, dotted in quoted if not resolves(dotted))
    assert wrong == [], "quoted but not importable:\n" + "\n".join(wrong)


def test_a_moved_path_is_found() -> None:
    assert not resolves("engine.scene_node.SceneNode")  # the module moved to engine.scene.graph
    assert resolves("engine.scene.graph.SceneNode") and resolves("engine.scene.SceneNode")
    assert imports_of("from engine.sensors.sensor_wrapper import Sensor  # Habitat's path") == [
        ("engine.sensors.sensor_wrapper", ("Sensor",))
    ]
