"""``magnum.scenetools``: Magnum's scene-processing functions, as placeholders.

Magnum's ``scenetools.absolute_field_transformations3d(scene, field)`` composes an imported
scene's node transforms into world transforms. rigidsim imports scenes with trimesh
(:func:`engine.scene.assets.load_meshes` already applies every node's world transform) and never
produces the ``trade`` scene data this function takes, so it raises ``NotImplementedError``.
"""

from __future__ import annotations

from engine.core.placeholder import placeholder_function

__all__ = ["absolute_field_transformations3d"]

absolute_field_transformations3d = placeholder_function(
    "magnum.scenetools.absolute_field_transformations3d",
    "Magnum's scene tools work on magnum.trade scene data, which rigidsim never produces",
    "engine.scene.assets.load_meshes(path) returns meshes moved by their nodes' world transforms",
    module=__name__,
)
