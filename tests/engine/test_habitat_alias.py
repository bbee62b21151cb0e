"""The opt-in import alias (engine.habitat_compat.alias): same module objects, never shadowing
a real Habitat-sim or Magnum unless forced, and the start-up hook of rigidsim-habitat-alias."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
import types
from collections.abc import Iterator
from pathlib import Path

import pytest

import engine
from engine.habitat_compat import alias

REPO_ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def installed() -> Iterator[None]:
    alias.install()
    try:
        yield
    finally:
        alias.uninstall()


def test_alias_gives_rigidsim_modules_themselves(installed: None) -> None:
    import corrade
    import habitat_sim
    import habitat_sim.utils.common
    import magnum
    import magnum.trade
    from habitat_sim.physics import ManagedRigidObject

    assert habitat_sim is engine
    assert magnum is engine.mn and magnum.trade is engine.mn.trade
    assert corrade is importlib.import_module("engine.habitat_compat.corrade")
    assert sys.modules["habitat_sim.physics"] is engine.physics
    assert habitat_sim.utils.common is importlib.import_module("engine.utils.common")
    # class identity: an object made through one spelling is an instance of the other's class
    assert ManagedRigidObject is engine.physics.ManagedRigidObject
    assert isinstance(magnum.Vector3(1, 2, 3), engine.mn.Vector3)
    # the rigidsim module keeps its own spec (the import system overwrote it with the alias's)
    assert engine.physics.__spec__.name == "engine.physics"
    assert engine.mn.trade.__spec__.name == "engine.mn.trade"


def test_renamed_modules_are_real_paths(installed: None) -> None:
    from habitat_sim._ext.habitat_sim_bindings import Configuration
    from habitat_sim.sim import SimulatorBackend, SimulatorConfiguration

    assert Configuration is engine.bindings.Configuration
    assert SimulatorConfiguration is engine.SimulatorConfiguration
    assert SimulatorBackend is importlib.import_module("engine.habitat_compat.sim").SimulatorBackend
    import habitat_sim

    # attribute chains as habitat-lab writes them in annotations, after `import habitat_sim`
    assert habitat_sim._ext.habitat_sim_bindings.Configuration is Configuration
    assert habitat_sim.sim.SimulatorBackend is SimulatorBackend


def test_names_outside_rigidsim_fail_as_usual(installed: None) -> None:
    with pytest.raises(ModuleNotFoundError, match="habitat_sim.no_such_module"):
        importlib.import_module("habitat_sim.no_such_module")
    with pytest.raises(ImportError):
        exec("from magnum import NoSuchName", {})


def test_install_twice_is_one_finder_and_uninstall_removes_the_names() -> None:
    alias.install()
    alias.install()
    try:
        assert sum(finder is alias._FINDER for finder in sys.meta_path) == 1
        import habitat_sim  # noqa: F401
    finally:
        alias.uninstall()
    assert not alias.is_installed()
    assert "habitat_sim" not in sys.modules and "magnum" not in sys.modules
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("habitat_sim")
    assert engine.physics.MotionType.DYNAMIC == 2  # rigidsim itself is untouched


def _fake_real_package(folder: Path, name: str) -> Path:
    package = folder / name
    package.mkdir()
    init = package / "__init__.py"
    init.write_text("REAL = True\n")
    return init


def test_refuses_while_a_real_habitat_sim_is_importable(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    init = _fake_real_package(tmp_path, "habitat_sim")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(alias.AliasConflictError, match="habitat_sim at .*habitat_sim") as error:
        alias.install()
    assert str(init) in str(error.value) and "force=True" in str(error.value)
    assert not alias.is_installed()
    alias.install(force=True)
    try:
        import habitat_sim

        assert habitat_sim is engine  # forced: rigidsim wins over the real package
    finally:
        alias.uninstall()
    assert importlib.import_module("habitat_sim").REAL  # and the real one is back
    sys.modules.pop("habitat_sim")


def test_refuses_a_real_magnum_already_imported_even_when_forced(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setitem(sys.modules, "magnum", types.ModuleType("magnum"))
    with pytest.raises(alias.AliasConflictError, match="magnum.*already imported"):
        alias.install(force=True)
    assert not alias.is_installed()


def test_startup_install_reads_its_switch_and_only_warns(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv(alias.ENVIRONMENT_SWITCH, "off")
    assert alias.install_at_startup() is False and not alias.is_installed()
    monkeypatch.delenv(alias.ENVIRONMENT_SWITCH)
    _fake_real_package(tmp_path, "magnum")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.warns(RuntimeWarning, match="magnum at"):
        assert alias.install_at_startup() is False
    assert not alias.is_installed()
    monkeypatch.setenv(alias.ENVIRONMENT_SWITCH, "force")
    try:
        assert alias.install_at_startup() is True
        assert importlib.import_module("magnum") is engine.mn
    finally:
        alias.uninstall()


def run_with_start_up_hook(code: str, *extra_path: Path) -> str:
    """Run ``code`` in a fresh interpreter after the .pth line of scripts/habitat_alias (as the
    installed distribution does at start-up); returns what it prints."""
    pth = (REPO_ROOT / "scripts" / "habitat_alias" / "rigidsim_habitat_alias.pth").read_text()
    folders = [*extra_path, REPO_ROOT, REPO_ROOT / "scripts" / "habitat_alias"]
    path = os.pathsep.join(str(folder) for folder in folders)
    result = subprocess.run(
        [sys.executable, "-c", pth.strip() + "\n" + code],
        env={**os.environ, "PYTHONPATH": path},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    return result.stdout.strip()


def test_start_up_hook_imports_nothing_until_an_aliased_name_is_imported() -> None:
    code = (
        "import sys\nassert 'engine' not in sys.modules\n"
        "import magnum as mn, habitat_sim, engine\n"
        "from habitat_sim.physics import ManagedArticulatedObject\n"
        "assert habitat_sim is engine and mn is engine.mn\n"
        "print('aliased')\n"
    )
    assert run_with_start_up_hook(code) == "aliased"


def test_start_up_hook_and_an_explicit_install_make_one_alias() -> None:
    code = (
        "import sys\nfrom engine.habitat_compat import alias\n"
        "alias.install()  # its look-up for a real habitat_sim wakes the hook, which installs\n"
        "assert sum(finder is alias._FINDER for finder in sys.meta_path) == 1\n"
        "import habitat_sim, engine\nassert habitat_sim is engine\n"
        "alias.uninstall()\n"
        "try:\n    import habitat_sim\nexcept ModuleNotFoundError:\n    print('removed')\n"
    )
    assert run_with_start_up_hook(code) == "removed"


def test_start_up_hook_leaves_a_real_habitat_sim_in_place(tmp_path: Path) -> None:
    _fake_real_package(tmp_path, "habitat_sim")
    code = (
        "import warnings\nwarnings.simplefilter('error')\n"
        "try:\n    import habitat_sim\nexcept RuntimeWarning as warning:\n"
        "    print('warned:', 'habitat_sim at' in str(warning))\n"
        "warnings.simplefilter('ignore')\nimport habitat_sim\nprint('real:', habitat_sim.REAL)\n"
    )
    assert run_with_start_up_hook(code, tmp_path).splitlines() == ["warned: True", "real: True"]
