"""The scene: the scene graph, the assets its nodes draw, and scene instance files.

Habitat's ``habitat_sim.scene`` names are importable from here (``SceneGraph``,
``SceneNode``, the semantic scene ``SemanticScene`` and its parts). What is here, in
reading order:

1. :mod:`~engine.scene.graph`: ``SceneNode`` (a local translation-rotation-scaling pose, world
   pose = product down from the root), ``SceneGraph``, ``Drawable`` (a mesh a node draws);
2. :mod:`~engine.scene.primitives`: Habitat's 12 built-in primitive assets as triangle meshes;
3. :mod:`~engine.scene.assets`: glTF / GLB / OBJ / PLY files to ``MeshData`` (NumPy meshes);
4. :mod:`~engine.scene.visual_nodes`: an object's visual scene nodes, one per asset part;
5. :mod:`~engine.scene.instance`: Habitat's ``*.scene_instance.json`` (a stage and placed
   objects);
6. :mod:`~engine.scene.semantic`: the semantic scene, empty where a scene has no annotations.

May import: ``engine.core``, ``engine.mn`` and the small Habitat modules (``errors``,
``geo``, ``logging``). Physics, sensors, templates and the simulator build on this folder;
it never imports them.
"""

from engine.scene.semantic import (
    BBox,
    SceneGraph,
    SceneNode,
    SemanticCategory,
    SemanticLevel,
    SemanticObject,
    SemanticRegion,
    SemanticScene,
)

__all__ = [
    "BBox",
    "SceneGraph",
    "SceneNode",
    "SemanticCategory",
    "SemanticLevel",
    "SemanticObject",
    "SemanticRegion",
    "SemanticScene",
]
