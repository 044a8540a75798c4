"""meshcat scenes as static HTML: the same scene writes the same bytes (committed under reports/hj/)."""

from __future__ import annotations

import re

import numpy as np

from navlab.viz.meshcat_html import add_box, add_mesh, offline_visualizer


def _scene() -> str:
    vis = offline_visualizer("test")
    add_box(vis["room/wall"], (0, 0, 0), (1, 0.1, 0.5), 0x888888)
    add_box(vis["room/pillar"], (2, 2, 0), (2.2, 2.2, 1.0), 0x444444, opacity=0.5)
    add_mesh(vis["brt"], np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]]), 0xFF7F0E)
    return vis.static_html()


def test_a_scene_writes_the_same_bytes_twice_and_its_objects_keep_distinct_uuids():
    first, second = _scene(), _scene()
    assert first == second  # meshcat's own uuids are uuid1: the clock and the host
    window = offline_visualizer("test").window
    vis = offline_visualizer("test")
    vis.window = window
    for name in ("a", "b"):
        add_box(vis[name], (0, 0, 0), (1, 1, 1), 0x000000)
    packed = b"".join(window.commands.values())
    uuids = set(re.findall(rb"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}", packed))
    assert len(uuids) == 6  # per box: its object, geometry and material
