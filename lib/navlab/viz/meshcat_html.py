"""meshcat scenes exported as self-contained static HTML, without starting a server.

``meshcat.Visualizer()`` normally spawns a ZeroMQ/websocket server and ``vis.static_html()`` asks that
server for the scene. Here the visualizer is given an ``OfflineWindow`` instead: it records the same
msgpack-encoded commands the server would have kept (the latest one per path and kind) and renders them
into the same page the server builds (meshcat's bundled ``main.min.js`` inlined, one ``fetch(data:…)``
per command). So ``vis.static_html()`` works offline and the file opens in any browser; its objects' uuids
are derived from their paths, so a committed scene changes only when the scene does.
"""

from __future__ import annotations

import uuid
from pathlib import Path

import numpy as np
import umsgpack
from meshcat import Visualizer
from meshcat import geometry as g
from meshcat import transformations as tf
from meshcat.servers.zmqserver import VIEWER_ROOT, create_command

_PAGE = """<!DOCTYPE html>
<html>
  <head><meta charset=utf-8><title>{title}</title></head>
  <body>
    <div id="meshcat-pane"></div>
    <script>{mainminjs}</script>
    <script>
      var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
      {commands}
    </script>
    <style>body {{margin: 0;}} #meshcat-pane {{width: 100vw; height: 100vh; overflow: hidden;}}</style>
  </body>
</html>
"""


class OfflineWindow:
    """Stands in for meshcat's ViewerWindow: keeps the scene's commands instead of sending them."""

    def __init__(self, title: str = "navlab"):
        self.title = title
        self.commands: dict[tuple[str, str, str], bytes] = {}

    def send(self, command) -> None:
        data = _named(command.lower())
        key = (data["type"], data["path"], str(data.get("property", "")))
        if data["type"] == "delete":
            self.commands = {k: v for k, v in self.commands.items() if not k[1].startswith(data["path"])}
            return
        self.commands.pop(key, None)  # re-setting a path replaces it, like the server's scene tree
        self.commands[key] = umsgpack.packb(data)

    def get_scene(self) -> str:
        mainminjs = (Path(VIEWER_ROOT) / "main.min.js").read_text()
        commands = "".join(create_command(c) for c in self.commands.values())
        return _PAGE.format(title=self.title, mainminjs=mainminjs, commands=commands)


def _named(data: dict) -> dict:
    """``data`` with meshcat's uuids (``uuid.uuid1``: the clock and the host) replaced by ones derived from the
    command's path and each uuid's place in it, so one scene writes the same bytes on every run and machine."""
    found: dict[str, str] = {}

    def collect(node) -> None:
        if isinstance(node, dict):
            if isinstance(node.get("uuid"), str) and node["uuid"] not in found:
                found[node["uuid"]] = str(uuid.uuid5(uuid.NAMESPACE_URL, f"{data.get('path', '')}#{len(found)}"))
            for value in node.values():
                collect(value)
        elif isinstance(node, list):
            for value in node:
                collect(value)

    def rename(node):
        if isinstance(node, dict):
            return {k: rename(v) for k, v in node.items()}
        if isinstance(node, list):
            return [rename(v) for v in node]
        return found.get(node, node) if isinstance(node, str) else node

    collect(data)
    return rename(data) if found else data


def offline_visualizer(title: str = "navlab") -> Visualizer:
    return Visualizer(window=OfflineWindow(title))


def add_mesh(vis: Visualizer, vertices: np.ndarray, faces: np.ndarray, color: int, opacity: float = 1.0):
    vis.set_object(g.TriangularMeshGeometry(vertices, faces),
                   g.MeshLambertMaterial(color=color, opacity=opacity, transparent=opacity < 1.0))


def add_box(vis: Visualizer, lo: tuple[float, float, float], hi: tuple[float, float, float], color: int,
            opacity: float = 1.0):
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    vis.set_object(g.Box(hi - lo), g.MeshLambertMaterial(color=color, opacity=opacity, transparent=opacity < 1.0))
    vis.set_transform(tf.translation_matrix((lo + hi) / 2))


def add_cylinder(vis: Visualizer, centre: tuple[float, float], radius: float, z0: float, z1: float, color: int,
                 opacity: float = 1.0):
    """A vertical cylinder (meshcat's cylinders run along y; rotate them to z)."""
    vis.set_object(g.Cylinder(z1 - z0, radius),
                   g.MeshLambertMaterial(color=color, opacity=opacity, transparent=opacity < 1.0))
    vis.set_transform(tf.translation_matrix((centre[0], centre[1], (z0 + z1) / 2))
                      @ tf.rotation_matrix(np.pi / 2, (1, 0, 0)))
