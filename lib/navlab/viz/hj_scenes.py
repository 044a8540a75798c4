"""3D scenes of the HJ value functions: the static BRT's zero level set over its room (meshcat, static HTML).

At a fixed speed v the BRT is a set in (x, y, θ); we draw it as a surface with θ as height (so a column
above a point shows for which headings that position is already doomed), over the room's obstacles.
"""

from __future__ import annotations

import numpy as np
from skimage.measure import marching_cubes

from navlab.hj.value_functions import speed_slice
from navlab.maps.rooms import Disc, Rect, Room
from navlab.reach.grid import Grid
from navlab.viz.meshcat_html import add_box, add_cylinder, add_mesh, offline_visualizer


def zero_level_mesh(slice_xyt: np.ndarray, grid: Grid, theta_height: float) -> tuple[np.ndarray, np.ndarray]:
    """Marching cubes of {V = 0} on an (x, y, θ) slice; θ ∈ [-π, π) maps to z ∈ [0, theta_height).

    θ is periodic, so the first θ layer is repeated after the last one to close the surface; the
    region outside the grid is padded as unsafe so the surface closes at the room's walls too.
    """
    vol = np.concatenate([slice_xyt, slice_xyt[:, :, :1]], axis=2)
    vol = np.pad(vol, ((1, 1), (1, 1), (0, 0)), constant_values=min(float(vol.min()), -1e-3))
    dz = theta_height / grid.shape[3]
    verts, faces, _, _ = marching_cubes(vol, level=0.0, spacing=(grid.spacing[0], grid.spacing[1], dz))
    verts[:, 0] += grid.lo[0] - grid.spacing[0]
    verts[:, 1] += grid.lo[1] - grid.spacing[1]
    return verts, faces


def brt_scene_html(room: Room, values: np.ndarray, grid: Grid, v: float, theta_height: float = 2.0) -> str:
    """Static HTML of the room (floor, obstacles) and the BRT zero level set at speed ``v``."""
    vis = offline_visualizer(f"{room.name}: static BRT at v = {v:.2f} m/s")
    add_box(vis["floor"], (0.0, 0.0, -0.02), (room.width, room.height, 0.0), color=0xDDDDDD)
    for i, ob in enumerate(room.obstacles):
        if isinstance(ob, Rect):
            add_box(vis[f"obstacles/{i}"], (ob.x0, ob.y0, 0.0), (ob.x1, ob.y1, theta_height), 0x444444, 0.35)
        elif isinstance(ob, Disc):
            add_cylinder(vis[f"obstacles/{i}"], (ob.cx, ob.cy), ob.r, 0.0, theta_height, 0x444444, 0.35)
    verts, faces = zero_level_mesh(speed_slice(values, grid, v), grid, theta_height)
    add_mesh(vis["brt"], verts, faces, color=0xD62728, opacity=0.8)
    return vis.static_html()



