"""The scene: the scene graph, the assets its nodes draw, scene instances; Habitat's
``habitat_sim.scene`` names (``SceneGraph``, ``SceneNode``, the semantic scene)."""

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
