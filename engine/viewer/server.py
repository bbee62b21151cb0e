"""The live page: a small HTTP server on 127.0.0.1 that sends a k3d plot's changes to a browser.

For a browser tab next to a script, or a notebook whose frontend cannot run Jupyter widgets.
The server (the standard library's ``ThreadingHTTPServer`` on a daemon thread) answers:

======================  ================================================================
``GET /``               the page: k3d's JavaScript (``/require.js``, ``/standalone.js``,
                        served from the ``k3d`` pip package's ``static`` folder; no CDN), a
                        loop that asks for changes every ``POLL_INTERVAL_MS``
``GET /changes?since``  msgpack ``{"version", "objects", "removed", "plot"}``: every
                        drawable property that changed after version ``since``
``GET /scene.json``     the scene description: version and ``[{id, name, type,
                        visible}]`` of the drawables
======================  ================================================================

A change log keeps, for every k3d object and property, the serialized value (k3d's own
``to_json``, what its widget sends) and the version at which it last changed.
:meth:`LiveServer.publish` (called by ``Viewer.update``) compares each property's bytes with
the last published ones and bumps the version of those that differ; a page that has seen
version ``v`` receives only what changed after ``v``, so the stage's large mesh goes to the
browser once and each step sends poses and overlays. The page applies the changes the way
k3d's own headless page does (``K3DInstance.load`` for a new object, ``reload`` for changed
properties).

The server binds to 127.0.0.1 unless told otherwise: nothing outside this machine sees it.
"""

from __future__ import annotations

import hashlib
import json
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs, urlparse

import k3d
import msgpack
from k3d.helpers import to_json

from engine.viewer.settings import DEFAULT_HOST, POLL_INTERVAL_MS

__all__ = ["LiveServer", "k3d_static_dir"]

# the plot parameters the page applies, with the k3d setter of each (k3d's own names)
_PLOT_SETTERS = {
    "cameraUpAxis": "setCameraUpAxis",
    "cameraAutoFit": "setCameraAutoFit",
    "camera": "setCamera",
    "gridVisible": "setGridVisible",
    "clearColor": "setClearColor",
    "axesHelper": "setAxesHelper",
}

_PAGE = """<!doctype html>
<html><head><meta charset="utf-8"><title>rigidsim live viewer</title>
<style>html,body{margin:0;padding:0;overflow:hidden;background:#f4f4f4}
#canvasTarget{width:100%;height:100%;position:absolute}</style>
<script src="/require.js"></script><script src="/standalone.js"></script></head>
<body><div id="canvasTarget"></div>
<script>
var SETTERS = SETTERS_JSON;
require(['k3d'], function (lib) {
  var k3d = new lib.K3D(lib.ThreeJsProvider, document.getElementById('canvasTarget'), {});
  window.rigidsimViewer = k3d;
  window.rigidsimVersion = 0;
  var busy = false;
  function apply(message) {
    message.removed.forEach(function (id) { k3d.removeObject(id); });
    var jobs = Object.keys(message.objects).map(function (id) {
      var changes = message.objects[id];
      var current = k3d.getWorld().ObjectsListJson[id] || {};
      var fresh = Object.keys(current).length === 0;
      Object.keys(changes).forEach(function (key) {
        current[key] = changes[key] = k3d.serialize.deserialize(changes[key]);
      });
      return fresh ? k3d.load({objects: [current]}) : k3d.reload(current, changes);
    });
    return Promise.all(jobs).then(function () {
      Object.keys(message.plot).forEach(function (key) {
        if (SETTERS[key]) { k3d[SETTERS[key]](message.plot[key]); }
      });
      window.rigidsimVersion = message.version;
      window.rigidsimLoaded = window.rigidsimLoaded || performance.now();
    });
  }
  function poll() {
    if (busy) { return; }
    busy = true;
    fetch('/changes?since=' + window.rigidsimVersion)
      .then(function (response) { return response.arrayBuffer(); })
      .then(function (buffer) {
        return apply(k3d.msgpack.decode(new Uint8Array(buffer), {codec: k3d.MsgpackCodec}));
      })
      .catch(function (error) { console.warn('rigidsim viewer: ' + error); })
      .finally(function () { busy = false; });
  }
  poll();
  setInterval(poll, POLL_MS);
});
</script></body></html>
"""


def k3d_static_dir() -> Path:
    """The ``static`` folder of the installed ``k3d`` package (its JavaScript bundles)."""
    return Path(k3d.__file__).resolve().parent / "static"


def _fingerprint(value: Any) -> bytes:
    """16-byte digest of a serialized property (what would be sent)."""
    return hashlib.blake2b(msgpack.packb(value, use_bin_type=True), digest_size=16).digest()


class _ChangeLog:
    """Versioned serialized properties of a k3d plot's objects and parameters."""

    def __init__(self) -> None:
        self.version = 0
        # object id -> property -> (version changed, fingerprint, serialized value)
        self.objects: dict[int, dict[str, tuple[int, bytes, Any]]] = {}
        # (object id, property) -> the Python value last serialized: a trait that still holds
        # the very same object was not set again, so it is not serialized again (the viewer
        # always sets new arrays, never edits one in place)
        self.last_values: dict[tuple[int, str], Any] = {}
        self.removed: dict[int, int] = {}  # object id -> version removed
        self.plot: dict[str, tuple[int, bytes, Any]] = {}

    def publish(self, plot: Any) -> None:
        """Record what differs between ``plot`` now and the last published state."""
        self.version += 1
        v = self.version
        alive = set()
        for obj in plot.objects:
            alive.add(obj.id)
            self.removed.pop(obj.id, None)
            known = self.objects.setdefault(obj.id, {})
            for prop in obj._synced_props:  # k3d's list of the properties its widget syncs
                current = obj[prop]
                if prop in known and self.last_values.get((obj.id, prop)) is current:
                    continue
                self.last_values[(obj.id, prop)] = current
                value = to_json(prop, current, obj)
                digest = _fingerprint(value)
                if prop not in known or known[prop][1] != digest:
                    known[prop] = (v, digest, value)
        for object_id in list(self.objects):
            if object_id not in alive:
                del self.objects[object_id]
                self.removed[object_id] = v
                for stale in [k for k in self.last_values if k[0] == object_id]:
                    del self.last_values[stale]
        params = plot.get_plot_params()
        for key in _PLOT_SETTERS:
            digest = _fingerprint(params[key])
            if key not in self.plot or self.plot[key][1] != digest:
                self.plot[key] = (v, digest, params[key])

    def since(self, seen: int) -> dict[str, Any]:
        """Everything that changed after version ``seen`` (all of it for ``seen`` 0)."""
        objects = {}
        for object_id, props in self.objects.items():
            changed = {p: value for p, (v, _, value) in props.items() if v > seen}
            if changed:
                changed["id"], changed["type"] = object_id, props["type"][2]
                objects[str(object_id)] = changed
        return {
            "version": self.version,
            "objects": objects,
            "removed": [i for i, v in self.removed.items() if v > seen],
            "plot": {key: value for key, (v, _, value) in self.plot.items() if v > seen},
        }


class LiveServer:
    """Serve a k3d plot's live page on ``host:port`` (127.0.0.1 and a free port by default).

    Call :meth:`publish` after changing the plot; :meth:`close` stops the server.
    """

    def __init__(self, plot: Any, host: str = DEFAULT_HOST, port: int = 0) -> None:
        if not isinstance(host, str) or not host:
            raise ValueError(f"host must be a non-empty string, got {host!r}")
        if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
            raise ValueError(f"port must be an int in [0, 65535], got {port!r}")
        self._plot = plot
        self._lock = threading.Lock()
        self._log = _ChangeLog()
        self._httpd = ThreadingHTTPServer((host, port), self._handler_class())
        self._httpd.daemon_threads = True
        self._thread = threading.Thread(
            target=self._httpd.serve_forever, name="rigidsim-viewer", daemon=True
        )
        self._thread.start()

    @property
    def url(self) -> str:
        """The page's address, ``http://host:port/``."""
        host, port = self._httpd.server_address[:2]
        return f"http://{host!s}:{port}/"

    def publish(self) -> int:
        """Record the plot's changes for the page; returns the new version."""
        with self._lock:
            self._log.publish(self._plot)
            return self._log.version

    def scene(self) -> dict[str, Any]:
        """The scene description: version and the drawables' id, name, type, visibility."""
        with self._lock:
            objects = [
                {"id": o.id, "name": o.name, "type": o.type, "visible": bool(o.visible)}
                for o in self._plot.objects
            ]
            return {"version": self._log.version, "objects": objects}

    def close(self) -> None:
        """Stop serving and free the port."""
        self._httpd.shutdown()
        self._httpd.server_close()
        self._thread.join(timeout=5.0)

    def _handler_class(self) -> type[BaseHTTPRequestHandler]:
        server = self
        static = k3d_static_dir()
        page = _PAGE.replace("SETTERS_JSON", json.dumps(_PLOT_SETTERS))
        page = page.replace("POLL_MS", str(POLL_INTERVAL_MS))

        class Handler(BaseHTTPRequestHandler):
            def do_GET(self) -> None:  # noqa: N802 - the standard library's name
                url = urlparse(self.path)
                if url.path == "/":
                    self._send(page.encode(), "text/html; charset=utf-8")
                elif url.path in ("/require.js", "/standalone.js"):
                    # cacheable: k3d's bundle asks for its own file again (for its workers)
                    body = (static / url.path[1:]).read_bytes()
                    self._send(body, "text/javascript", cache="max-age=3600")
                elif url.path == "/favicon.ico":
                    self._send(b"", "image/x-icon")
                elif url.path == "/changes":
                    seen = parse_qs(url.query).get("since", ["0"])[0]
                    if not seen.isdigit():
                        self.send_error(400, f"since must be a version number, got {seen!r}")
                        return
                    with server._lock:
                        message = server._log.since(int(seen))
                    body = msgpack.packb(message, use_bin_type=True)
                    self._send(body, "application/octet-stream")
                elif url.path == "/scene.json":
                    self._send(json.dumps(server.scene()).encode(), "application/json")
                else:
                    self.send_error(404, f"no such page: {url.path}")

            def _send(self, body: bytes, content_type: str, cache: str = "no-store") -> None:
                self.send_response(200)
                self.send_header("Content-Type", content_type)
                self.send_header("Content-Length", str(len(body)))
                self.send_header("Cache-Control", cache)
                self.end_headers()
                self.wfile.write(body)

            def log_message(self, format: str, *args: Any) -> None:  # noqa: A002
                """Quiet: a page polls several times a second."""

        return Handler
