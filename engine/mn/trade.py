"""``magnum.trade``: Magnum's asset importers and the mesh/scene data they return, as placeholders.

In Magnum, ``trade.ImporterManager()`` finds importer plugins, ``manager.load_and_instantiate(
"AnySceneImporter")`` opens a file, and the importer returns ``trade.MeshData`` (attributes
named by ``trade.MeshAttribute``) and scene fields (``trade.SceneField``). habitat-lab creates
an ``ImporterManager`` when its receptacle module is imported and uses the importer only for
rearrange receptacle meshes. rigidsim loads assets with trimesh into NumPy meshes
(:func:`engine.scene.assets.load_meshes` returns :class:`engine.scene.assets.MeshData`), so:

- ``ImporterManager()`` constructs (habitat-lab calls it at import); every method raises
  ``NotImplementedError``;
- ``MeshData`` is a placeholder class (annotations work, constructing raises);
- ``MeshAttribute``, ``SceneField`` and ``MeshPrimitive`` (top-level ``magnum.MeshPrimitive``)
  are real enums with Magnum's member names (plain values: nothing in rigidsim consumes them).
"""

from __future__ import annotations

import enum

from engine.core.placeholder import Placeholder, PlaceholderObject

__all__ = ["ImporterManager", "MeshAttribute", "MeshData", "MeshPrimitive", "SceneField"]

_MISSING = "Magnum's asset importers (plugins returning trade.MeshData) are not available"
_INSTEAD = (
    "engine.scene.assets.load_meshes(path) loads a mesh file into NumPy arrays (assets.MeshData)"
)


class MeshPrimitive(enum.Enum):
    """Magnum's mesh primitive kinds (how a mesh's indices make points, lines or triangles)."""

    POINTS = enum.auto()
    LINES = enum.auto()
    LINE_LOOP = enum.auto()
    LINE_STRIP = enum.auto()
    TRIANGLES = enum.auto()
    TRIANGLE_STRIP = enum.auto()
    TRIANGLE_FAN = enum.auto()
    INSTANCES = enum.auto()
    FACES = enum.auto()
    EDGES = enum.auto()


class MeshAttribute(enum.Enum):
    """Magnum's names of per-vertex mesh attributes."""

    POSITION = enum.auto()
    TANGENT = enum.auto()
    BITANGENT = enum.auto()
    NORMAL = enum.auto()
    TEXTURE_COORDINATES = enum.auto()
    COLOR = enum.auto()
    JOINT_IDS = enum.auto()
    WEIGHTS = enum.auto()
    OBJECT_ID = enum.auto()


class SceneField(enum.Enum):
    """Magnum's names of per-object scene fields."""

    PARENT = enum.auto()
    TRANSFORMATION = enum.auto()
    TRANSLATION = enum.auto()
    ROTATION = enum.auto()
    SCALING = enum.auto()
    MESH = enum.auto()
    MESH_MATERIAL = enum.auto()
    LIGHT = enum.auto()
    CAMERA = enum.auto()
    SKIN = enum.auto()
    IMPORTER_STATE = enum.auto()


class MeshData(Placeholder):
    """Placeholder of Magnum's imported mesh (module docstring)."""

    habitat_name = "magnum.trade.MeshData"
    missing = _MISSING
    instead = _INSTEAD


class ImporterManager(PlaceholderObject):
    """Magnum's importer plugin manager: constructs; every method raises (module docstring)."""

    habitat_name = "magnum.trade.ImporterManager"
    missing = _MISSING
    instead = _INSTEAD
