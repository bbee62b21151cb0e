"""The benchmark's pybullet peer is the body Habitat uses: a btRigidBody, not a btMultiBody.

Habitat-sim's ``BulletRigidObject`` builds a ``btRigidBody``; pybullet builds one only when
``createMultiBody`` is given ``useMaximalCoordinates=True`` (otherwise a Featherstone
btMultiBody, about 2x slower per step, which would flatter rigidsim's ratios). These tests run
without pybullet: the benchmark's scene builders are driven against a recording stand-in
module put in ``sys.modules["pybullet"]``, and every ``createMultiBody`` call in
``benchmarks/`` is checked in the source as well.
"""

from __future__ import annotations

import ast
import sys
import types
from pathlib import Path

import numpy as np
import pytest

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


class RecordingPybullet(types.ModuleType):
    """A stand-in ``pybullet``: records every call as ``(name, args, kwargs)`` and returns
    what the benchmark code reads back (ids, zero velocities, poses, a depth buffer)."""

    DIRECT, GEOM_MESH, GEOM_BOX, GEOM_FORCE_CONCAVE_TRIMESH = 1, 5, 3, 1
    URDF_ENABLE_SLEEPING, ACTIVATION_STATE_DISABLE_SLEEPING, ER_TINY_RENDERER = 2048, 4, 65536

    def __init__(self) -> None:
        super().__init__("pybullet")
        self.calls: list[tuple[str, tuple, dict]] = []

    def __getattr__(self, name: str):
        if name.startswith("__"):
            raise AttributeError(name)

        def call(*args, **kwargs):
            self.calls.append((name, args, kwargs))
            if name == "getBaseVelocity":
                return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
            if name == "getBasePositionAndOrientation":
                return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)
            if name == "getCameraImage":
                width, height = args[0], args[1]
                return width, height, None, np.ones(width * height), None
            if name == "computeProjectionMatrixFOV":
                return [0.0] * 16
            return len(self.calls)  # an id for connect / create* calls

        return call

    def named(self, name: str) -> list[tuple[tuple, dict]]:
        return [(args, kwargs) for called, args, kwargs in self.calls if called == name]


@pytest.fixture
def fake_pybullet(monkeypatch) -> RecordingPybullet:
    fake = RecordingPybullet()
    monkeypatch.setitem(sys.modules, "pybullet", fake)
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    return fake


def bodies_with_mass_or_collision(fake: RecordingPybullet) -> list[dict]:
    """The keyword arguments of every ``createMultiBody`` call that builds a body with a mass
    or a collision shape (positional ``baseMass``, ``baseCollisionShapeIndex`` included)."""
    out = []
    for args, kwargs in fake.named("createMultiBody"):
        given = dict(zip(("baseMass", "baseCollisionShapeIndex"), args, strict=False))
        given.update(kwargs)
        if given.get("baseMass", 0) or given.get("baseCollisionShapeIndex", -1) != -1:
            out.append(given)
    return out


@pytest.mark.parametrize("sleep", [True, False])
def test_physics_scene_builds_btrigidbodies_on_a_concave_mesh(fake_pybullet, sleep):
    from physics_scenes import FRAME, STEP, column_positions, run_pybullet

    positions, rotations = column_positions(10)
    run_pybullet(positions, rotations, 2 * FRAME, sleep=sleep, stage="box")
    bodies = bodies_with_mass_or_collision(fake_pybullet)
    assert len(bodies) == 11  # the stage and 10 cubes
    assert all(body.get("useMaximalCoordinates") is True for body in bodies)
    # sleeping as Habitat leaves a btRigidBody (on) or off in both engines
    cubes = [body for body in bodies if body.get("baseMass", 0) > 0]
    assert len(cubes) == 10
    enabled = [bool(body.get("flags", 0) & fake_pybullet.URDF_ENABLE_SLEEPING) for body in cubes]
    assert enabled == [sleep] * 10
    # the stage: a static concave triangle mesh; the same fixed step
    (mesh_args, mesh_kwargs), *_ = fake_pybullet.named("createCollisionShape")
    assert mesh_args[0] == fake_pybullet.GEOM_MESH
    assert mesh_kwargs["flags"] == fake_pybullet.GEOM_FORCE_CONCAVE_TRIMESH
    assert [args[0] for args, _ in fake_pybullet.named("setTimeStep")] == [STEP]


def test_multibody_column_is_opt_in(fake_pybullet):
    from physics_scenes import FRAME, column_positions, run_pybullet

    positions, rotations = column_positions(3)
    run_pybullet(positions, rotations, FRAME, stage="box", multibody=True)
    bodies = bodies_with_mass_or_collision(fake_pybullet)
    assert [body["useMaximalCoordinates"] for body in bodies] == [False] * 4


def test_render_benchmark_bodies_are_btrigidbodies(fake_pybullet):
    from bench_render import pybullet_renderer

    from render import Camera, RenderMesh

    triangle = RenderMesh(
        vertices=np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), faces=np.array([[0, 1, 2]])
    )
    render = pybullet_renderer([triangle], Camera(resolution=(8, 8)), np.eye(4))
    assert render is not None and render().shape == (8, 8)
    calls = fake_pybullet.named("createMultiBody")
    assert calls and all(kwargs.get("useMaximalCoordinates") is True for _, kwargs in calls)


def test_every_create_multibody_call_in_benchmarks_names_the_body_kind():
    """Any ``createMultiBody`` call in ``benchmarks/`` (new scenes included) says which
    body it builds: ``useMaximalCoordinates`` given, True unless labelled as a multibody."""
    missing = []
    for path in sorted(BENCHMARKS.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "createMultiBody"
            ):
                keywords = {k.arg: k.value for k in node.keywords}
                value = keywords.get("useMaximalCoordinates")
                if value is None or (isinstance(value, ast.Constant) and value.value is not True):
                    missing.append(f"{path.name}:{node.lineno}")
    assert not missing, f"createMultiBody without useMaximalCoordinates=True: {missing}"
