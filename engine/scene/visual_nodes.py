"""An object's visual scene nodes: one node per component of its render asset.

Habitat builds, for every rigid object, a small scene graph under the object's root and
returns it as ``obj.visual_scene_nodes`` (``PhysicsObjectBindings``): the object's *visual
node*, the node that holds the template's scale, the asset's root node, then one node per
node of the asset file in the file's order (depth first, glTF nodes without a mesh, such as
lights and cameras, included). Each mesh is drawn by the node of the file node that holds
it, so ``visual_scene_nodes[k].semantic_id = n`` relabels one part of an object (Habitat's
``semantic_id_tutorial`` does it to two faces of ``transform_box.glb``).

rigidsim bakes the file's node transforms, the template's scale and the centre of mass into
the mesh vertices when it loads an asset, so every node below the visual node has the
identity transform; the order and the part each node draws are Habitat's.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path

from engine.scene.graph import Drawable, SceneNode

__all__ = ["build_visual_nodes", "gltf_node_names"]


def gltf_node_names(path: str | Path) -> list[str] | None:
    """Names of a ``.glb`` / ``.gltf`` file's nodes in scene order (depth first, children
    in file order); None for other files or a file without a scene."""
    path = Path(path)
    try:
        if path.suffix.lower() == ".glb":
            data = path.read_bytes()
            length = struct.unpack("<I", data[12:16])[0]  # first chunk: the JSON
            document = json.loads(data[20 : 20 + length])
        elif path.suffix.lower() == ".gltf":
            document = json.loads(path.read_text(encoding="utf-8"))
        else:
            return None
    except (OSError, ValueError, struct.error):
        return None
    nodes = document.get("nodes", [])
    scenes = document.get("scenes", [])
    if not scenes:
        return None
    names: list[str] = []

    def visit(index: int) -> None:
        node = nodes[index]
        names.append(str(node.get("name", f"node{index}")))
        for child in node.get("children", []):
            visit(child)

    for index in scenes[document.get("scene", 0)].get("nodes", []):
        visit(index)
    return names


def build_visual_nodes(
    visual: SceneNode, drawables: list[Drawable], asset_path: str
) -> list[SceneNode]:
    """Hang ``drawables`` (one per mesh, named after their file node) on component nodes
    below ``visual``; return Habitat's ``visual_scene_nodes`` list (module docstring)."""
    scale_node = SceneNode(visual, name="scale")
    root = SceneNode(scale_node, name="asset root")
    names = gltf_node_names(asset_path) or [d.mesh.name for d in drawables]
    components = [SceneNode(root, name=name) for name in names]
    free = list(components)
    for drawable in drawables:
        match = next((node for node in free if node.name == drawable.mesh.name), None)
        if match is None:  # a mesh the file's node list does not name
            match = SceneNode(root, name=drawable.mesh.name)
            components.append(match)
        else:
            free.remove(match)
        match.drawables.append(drawable)
    return [visual, scale_node, root, *components]
