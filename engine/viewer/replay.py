"""Replays: frames recorded from a run, played back with a time slider in one HTML file.

A :class:`Replay` holds the scene's parts (meshes, once) and the recorded
:class:`~engine.viewer.overlays.Frame` s (poses, sleeping tints and overlays per frame).
:meth:`Replay.to_html` writes k3d's self-contained snapshot: k3d's JavaScript, read from
the ``k3d`` pip package and inlined (compressed) into the page, the scene as k3d time series,
and a small control bar of ours (play/pause, a slider over the frames, world time and contact
count). The file needs no server and no network: open it from disk, or embed it in a page with
``<iframe src="replay.html">``; orbit with the mouse (left drag), zoom with the wheel.

The page exposes its scene description for tests and curious students:
``window.rigidsimViewer`` is the k3d instance (``getWorld().ObjectsListJson`` lists the
drawables by name), ``window.rigidsimReplay`` the frame times and contact counts, and
``window.rigidsimShowFrame(i)`` moves the slider to frame ``i``.
"""

from __future__ import annotations

import html
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from engine.viewer.drawing import SceneDrawing
from engine.viewer.overlays import Frame
from engine.viewer.world_view import Part

__all__ = ["Replay"]

# The control bar, run by k3d's snapshot page once the scene is loaded (``K3DInstance`` is the
# loaded instance there). ``REPLAY`` is replaced by the frames' times and contact counts.
_CONTROLS_JS = """
(function (k3d) {
  var replay = REPLAY;
  window.rigidsimViewer = k3d;
  window.rigidsimReplay = replay;
  var bar = document.createElement('div');
  bar.id = 'rigidsim-controls';
  bar.style.cssText = 'position:fixed;left:0;right:0;bottom:0;padding:6px 10px;' +
    'background:rgba(32,32,32,0.85);color:#fff;font:13px sans-serif;display:flex;' +
    'align-items:center;gap:10px;z-index:10';
  var play = document.createElement('button');
  play.textContent = 'play';
  play.style.cssText = 'width:56px';
  var slider = document.createElement('input');
  slider.type = 'range'; slider.min = 0; slider.max = replay.times.length - 1; slider.value = 0;
  slider.style.cssText = 'flex:1';
  slider.setAttribute('aria-label', 'replay frame');
  var label = document.createElement('span');
  label.style.cssText = 'min-width:190px;font-variant-numeric:tabular-nums';
  bar.appendChild(play); bar.appendChild(slider); bar.appendChild(label);
  document.body.appendChild(bar);
  var timer = null;
  function show(i) {
    i = Math.max(0, Math.min(replay.times.length - 1, i | 0));
    slider.value = i;
    window.rigidsimFrame = i;
    label.textContent = 't = ' + replay.times[i].toFixed(3) + ' s, ' +
      replay.contacts[i] + ' contact points';
    return k3d.setTime(replay.times[i]);
  }
  window.rigidsimShowFrame = show;
  slider.addEventListener('input', function () { stop(); show(+slider.value); });
  function stop() {
    if (timer !== null) { clearInterval(timer); timer = null; }
    play.textContent = 'play';
  }
  play.addEventListener('click', function () {
    if (timer !== null) { stop(); return; }
    if (+slider.value >= replay.times.length - 1) { show(0); }
    play.textContent = 'pause';
    timer = setInterval(function () {
      var next = +slider.value + 1;
      if (next >= replay.times.length) { stop(); return; }
      show(next);
    }, 1000 * replay.frame_dt);
  });
  show(0);
  window.rigidsimReady = true;
})(K3DInstance);
"""


@dataclass
class Replay:
    """A recorded run: the parts drawn and one :class:`Frame` per recorded instant.

    Attributes
    ----------
    parts : list of Part
        The meshes, in their nodes' frames.
    names : dict[int, str]
        Object id -> the name shown for it (its handle).
    frames : list of Frame
        In recording order; times must not decrease.
    navmesh : tuple of arrays or None
        The navmesh overlay's mesh, if it was switched on.
    camera : (9,) float or None
        k3d camera ``[eye xyz, target xyz, up xyz]``, world frame; None fits the scene.
    """

    parts: list[Part]
    names: dict[int, str]
    frames: list[Frame] = field(default_factory=list)
    navmesh: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    camera: list[float] | None = None

    def times(self) -> list[float]:
        """World times of the frames, s, counted from the first frame."""
        if not self.frames:
            return []
        return [frame.time - self.frames[0].time for frame in self.frames]

    def drawing(self, height: int = 480) -> SceneDrawing:
        """The k3d plot with every drawable animated over the frames."""
        times = self.times()
        if any(b < a for a, b in zip(times, times[1:], strict=False)):
            raise ValueError(f"replay frame times must not decrease, got {times}")
        drawing = SceneDrawing(self.parts, self.names, self.navmesh, height=height)
        drawing.animate(self.frames)
        if self.camera is not None:
            drawing.plot.camera_auto_fit = False
            drawing.plot.camera = list(self.camera)
        return drawing

    def to_html(self) -> str:
        """The self-contained HTML page of the replay (k3d inlined; no server, no network)."""
        drawing = self.drawing()
        times = self.times()
        frame_dt = float(np.median(np.diff(times))) if len(times) > 1 else 1.0 / 60.0
        replay = {
            "times": [round(t, 6) for t in times],
            "contacts": [frame.n_contacts for frame in self.frames],
            "frame_dt": frame_dt,
        }
        controls = _CONTROLS_JS.replace("REPLAY", json.dumps(replay))
        page = drawing.plot.get_snapshot(additional_js_code=controls)
        return page.replace("<title>K3D snapshot viewer", "<title>rigidsim replay", 1)

    def save(self, path: str | Path) -> Path:
        """Write :meth:`to_html` to ``path`` (parent folders are created); return the path."""
        path = Path(path)
        if path.suffix.lower() not in (".html", ".htm"):
            raise ValueError(f"a replay is written as .html, got path={str(path)!r}")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(self.to_html(), encoding="utf-8")
        return path

    def _repr_html_(self) -> str:
        """Inline display in Jupyter: the page in an ``iframe srcdoc`` (no server needed)."""
        source = html.escape(self.to_html(), quote=True)
        return (
            f'<iframe srcdoc="{source}" style="width:100%;height:520px;border:1px solid #ccc" '
            'title="rigidsim replay"></iframe>'
        )
