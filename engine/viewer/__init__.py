"""A browser 3D viewer for rigidsim: the world, teaching overlays and replays (extra ``viewer``).

``pip install -e '.[viewer]'`` brings k3d (MIT), a Jupyter widget on three.js whose
JavaScript ships inside its pip package, so the viewer works offline and exports
self-contained HTML. The engine never imports this package: ``import engine`` works without
k3d, and a simulator that no viewer follows steps exactly as before.

In a notebook::

    from engine.viewer import Viewer
    viewer = Viewer(sim, follow=True)   # redraw after every sim.step_physics
    viewer.show()                       # the live 3D widget

- :class:`Viewer` (:mod:`engine.viewer.viewer`): live view, overlay switches, recording;
- :class:`Replay` (:mod:`engine.viewer.replay`): recorded frames, time slider, one HTML file;
- :mod:`engine.viewer.overlays`: what each overlay reads (public queries only) and draws;
- :mod:`engine.viewer.world_view`: the meshes and poses read from the scene graph;
- :mod:`engine.viewer.drawing`: frames to k3d drawables; :mod:`engine.viewer.server`: the
  live page on 127.0.0.1; :mod:`engine.viewer.demo`: the tutorial's replay
  (``python -m engine.viewer --demo-replay OUT.html``).

May import: the whole ``engine`` (public queries only), ``engine.tutorial`` (the demo
replay) and ``navmesh``; the engine never imports the viewer.
"""

from __future__ import annotations

try:
    import k3d  # noqa: F401 - checked here so that the error names the extra to install
except ImportError as error:  # pragma: no cover - depends on the environment
    raise ImportError(
        "engine.viewer needs the optional extra 'viewer' (k3d): pip install -e '.[viewer]'"
    ) from error

from engine.viewer.overlays import Frame, OverlaySwitches
from engine.viewer.replay import Replay
from engine.viewer.viewer import Viewer

__all__ = ["Frame", "OverlaySwitches", "Replay", "Viewer"]
