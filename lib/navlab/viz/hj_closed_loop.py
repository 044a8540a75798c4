"""Figures and replays of the HJ-search closed-loop runs: Fig. 8 (where FI-BRT and FS-BRT start their
detour before a head-on human), Fig. 10 (OBS vs BRT planning snapshots in the Dense Room), and a patrol
among humans as an animated GIF (matplotlib + pillow) and a meshcat scene exported as static HTML.

The human-robot BRT is drawn "under the car": the human positions, in the car's frame at its current
speed, from which the human can force a collision within the BRT's horizon ({V(x_rel, y_rel, v) < 0},
``reach.lookup.HumanBRTLookup``). A human inside that region is what the FS-BRT pruner forbids.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.animation import FuncAnimation, PillowWriter
from matplotlib.patches import Circle
from meshcat import geometry as g
from meshcat import transformations as tf
from meshcat.animation import Animation

from navlab.core.io import atomic_path
from navlab.hj.receding_horizon import Run
from navlab.maps.rooms import Disc, Rect, Room
from navlab.reach.lookup import HumanBRTLookup
from navlab.search.dubins_lattice import LatticeSpec, densify
from navlab.viz.meshcat_html import add_box, add_cylinder, offline_visualizer

COLORS = {"FI-BRT": "tab:blue", "FS-BRT": "tab:orange", "OBS": "tab:red", "Dist + OBS": "tab:red",
          "Dist + BRT": "tab:purple", "TTR + OBS": "tab:orange", "TTR + BRT": "tab:blue"}


def _room_axes(ax, room: Room) -> None:
    xs, ys = np.meshgrid(np.linspace(0, room.width, 481), np.linspace(0, room.height, 271))
    blocked = np.where(room.obstacle_distance(xs, ys) < 0.0, 0.6, 1.0)
    ax.imshow(blocked, cmap="gray", vmin=0.0, vmax=1.0, origin="lower", extent=(0, room.width, 0, room.height))
    ax.set_xlim(0, room.width)
    ax.set_ylim(0, room.height)
    ax.set_aspect("equal")


def detour_figure(room: Room, runs: dict[str, Run], detours: dict[str, dict | None], goal, title: str = ""):
    """Fig. 8: the car's path per method, the human's, and where each detour started (distance to the human)."""
    fig, ax = plt.subplots(figsize=(7.0, 4.2), constrained_layout=True)
    _room_axes(ax, room)
    for label, run in runs.items():
        traj, color = np.asarray(run.trajectory), COLORS.get(label, "k")
        ax.plot(traj[:, 1], traj[:, 2], "-", color=color, lw=1.5, label=label)
        d = detours.get(label)
        if d is not None:
            ax.plot(*d["xy"], "o", color=color, ms=7, mec="k")
            ax.annotate(f"{d['distance_to_human_m']:.1f} m", d["xy"], textcoords="offset points", xytext=(4, 6),
                        fontsize=8, color=color)
    human = np.asarray(next(iter(runs.values())).humans)[:, 0]
    ax.plot(human[:, 0], human[:, 1], "--", color="k", lw=1.0, label="human")
    ax.plot(*goal, "*", color="gold", ms=14, mec="k")
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title(title, fontsize=10)
    return fig


def snapshots_figure(room: Room, spec: LatticeSpec, runs: dict[str, Run], times: list[float], goal, title=""):
    """Fig. 10: per method (rows) and time (columns) the path so far and the plan the car had at that time."""
    fig, axes = plt.subplots(len(runs), len(times), figsize=(3.2 * len(times), 2.1 * len(runs)),
                             constrained_layout=True, squeeze=False)
    for row, (label, run) in zip(axes, runs.items(), strict=True):
        traj = np.asarray(run.trajectory)
        for ax, t in zip(row, times, strict=True):
            _room_axes(ax, room)
            past = traj[traj[:, 0] <= t]
            ax.plot(past[:, 1], past[:, 2], "-", color="k", lw=1.0)
            kept = [(pt, c) for pt, c in run.plans if pt <= t]
            if kept and len(past):
                pt, commands = kept[-1]
                state = traj[np.argmin(np.abs(traj[:, 0] - pt)), 1:]
                plan = densify(spec, state, commands)
                ax.plot(plan[:, 0], plan[:, 1], "-", color=COLORS.get(label, "tab:blue"), lw=1.5)
            if len(past):
                ax.plot(past[-1, 1], past[-1, 2], "o", color="k", ms=4)
            ax.plot(*goal, "*", color="gold", ms=10, mec="k")
            ax.set_title(f"{label}, t = {t:.1f} s", fontsize=8)
            ax.set_xticks([])
            ax.set_yticks([])
    fig.suptitle(title, fontsize=10)
    return fig


def brt_region(lookup: HumanBRTLookup, speed: float, n: int = 61) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Human positions (car frame, car at the origin facing +x at ``speed``) with V < 0: a (n, n) mask and
    its axes."""
    half = float(lookup.grid.hi[0])
    ax = np.linspace(-half, half, n)
    x, y = np.meshgrid(ax, ax, indexing="ij")
    robot = np.zeros((x.size, 4))
    robot[:, 2] = speed
    values = lookup(robot, np.stack([x.ravel(), y.ravel()], 1)).reshape(n, n)
    return values < 0.0, ax, ax


def _frames(run: Run, fps: float, control_hz: float) -> np.ndarray:
    return np.arange(0, len(run.trajectory), max(1, round(control_hz / fps)))


def patrol_gif(path: str | Path, room: Room, run: Run, lookup: HumanBRTLookup, robot_radius: float,
               human_radius: float, control_hz: float, sample_hz: float = 1.0, fps: float = 5.0,
               title: str = "") -> Path:
    """The patrol as an animated GIF: car, humans, and the BRT region under the car at its speed;
    ``sample_hz`` frames per simulated second played at ``fps`` (fps / sample_hz times real time)."""
    traj, humans = np.asarray(run.trajectory), np.asarray(run.humans)
    frames = _frames(run, sample_hz, control_hz)
    speeds = np.unique(np.round(traj[:, 3] * 4) / 4)  # regions precomputed per 0.25 m/s
    regions = {v: brt_region(lookup, float(v)) for v in speeds}
    fig, ax = plt.subplots(figsize=(5.6, 3.4), dpi=80, constrained_layout=True)
    _room_axes(ax, room)
    ax.plot(traj[:, 1], traj[:, 2], "-", color="0.8", lw=0.8)
    car = Circle((0, 0), robot_radius, color="tab:blue", zorder=3)
    ax.add_patch(car)
    heading, = ax.plot([], [], "-", color="k", lw=1.5, zorder=4)
    people = [Circle((0, 0), human_radius, color="tab:red", zorder=3) for _ in range(humans.shape[1])]
    for p in people:
        ax.add_patch(p)
    region = ax.scatter([], [], s=4, color="tab:orange", alpha=0.5, zorder=2)
    stamp = ax.text(0.02, 0.95, "", transform=ax.transAxes, fontsize=8, va="top")
    ax.set_title(title, fontsize=9)

    def draw(i):
        t, x, y, v, th = traj[i]
        car.center = (x, y)
        heading.set_data([x, x + 0.4 * np.cos(th)], [y, y + 0.4 * np.sin(th)])
        for p, h in zip(people, humans[i], strict=True):
            p.center = tuple(h)
        mask, ax_x, ax_y = regions[np.round(v * 4) / 4]
        ix, iy = np.nonzero(mask)
        c, s = np.cos(th), np.sin(th)
        region.set_offsets(np.c_[x + c * ax_x[ix] - s * ax_y[iy], y + s * ax_x[ix] + c * ax_y[iy]])
        stamp.set_text(f"t = {t:5.1f} s   v = {v:.2f} m/s")
        return car, heading, region, stamp, *people

    anim = FuncAnimation(fig, draw, frames=frames, blit=False)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path, ".gif") as tmp:
        anim.save(tmp, writer=PillowWriter(fps=fps))
    plt.close(fig)
    return path


def _region_mesh(mask: np.ndarray, ax_x: np.ndarray, ax_y: np.ndarray, z: float):
    """Flat quads (two triangles each) over the mask's cells: vertices (V, 3), faces (F, 3)."""
    hx, hy = (ax_x[1] - ax_x[0]) / 2, (ax_y[1] - ax_y[0]) / 2
    ix, iy = np.nonzero(mask)
    cx, cy = ax_x[ix], ax_y[iy]
    corners = np.stack([np.c_[cx - hx, cy - hy], np.c_[cx + hx, cy - hy], np.c_[cx + hx, cy + hy],
                        np.c_[cx - hx, cy + hy]], 1)  # (K, 4, 2)
    verts = np.concatenate([corners.reshape(-1, 2), np.full((corners.size // 2, 1), z)], 1)
    base = 4 * np.arange(len(cx))[:, None]
    faces = np.concatenate([base + [0, 1, 2], base + [0, 2, 3]])
    return verts.astype(np.float32), faces.astype(np.uint32)


def patrol_scene_html(room: Room, run: Run, lookup: HumanBRTLookup, robot_radius: float, human_radius: float,
                      control_hz: float, fps: float = 5.0) -> str:
    """The patrol as a meshcat animation in one static HTML page (press play in the Animations panel)."""
    traj, humans = np.asarray(run.trajectory), np.asarray(run.humans)
    vis = offline_visualizer(f"{room.name}: patrol replay")
    add_box(vis["floor"], (0.0, 0.0, -0.02), (room.width, room.height, 0.0), color=0xDDDDDD)
    for i, ob in enumerate(room.obstacles):
        if isinstance(ob, Rect):
            add_box(vis[f"obstacles/{i}"], (ob.x0, ob.y0, 0.0), (ob.x1, ob.y1, 0.5), 0x444444)
        elif isinstance(ob, Disc):
            add_cylinder(vis[f"obstacles/{i}"], (ob.cx, ob.cy), ob.r, 0.0, 0.5, 0x444444)
    levels = np.unique(np.round(traj[:, 3] * 4) / 4)
    car = vis["car"]
    car["body"].set_object(g.Cylinder(0.23, robot_radius), g.MeshLambertMaterial(color=0x1F77B4))
    car["body"].set_transform(tf.translation_matrix((0, 0, 0.115)) @ tf.rotation_matrix(np.pi / 2, (1, 0, 0)))
    car["nose"].set_object(g.Box((0.2, 0.06, 0.06)), g.MeshLambertMaterial(color=0x000000))
    car["nose"].set_transform(tf.translation_matrix((robot_radius, 0, 0.23)))
    for v in levels:
        verts, faces = _region_mesh(*brt_region(lookup, float(v)), z=0.01)
        if len(faces):
            car[f"brt/{v:.2f}"].set_object(g.TriangularMeshGeometry(verts, faces),
                                           g.MeshBasicMaterial(color=0xFF7F0E, opacity=0.45, transparent=True))
    for k in range(humans.shape[1]):
        add_cylinder(vis[f"humans/{k}"], (0.0, 0.0), human_radius, 0.0, 1.7, 0xD62728)
    anim = Animation(default_framerate=fps)
    for f, i in enumerate(_frames(run, fps, control_hz)):
        _, x, y, v, th = traj[i]
        with anim.at_frame(vis, f) as frame:
            frame["car"].set_transform(tf.translation_matrix((x, y, 0.0)) @ tf.rotation_matrix(th, (0, 0, 1)))
            for lv in levels:
                frame[f"car/brt/{lv:.2f}"].set_property("visible", "boolean", bool(lv == np.round(v * 4) / 4))
            for k, h in enumerate(humans[i]):
                frame[f"humans/{k}"].set_transform(tf.translation_matrix((h[0], h[1], 0.85))
                                                   @ tf.rotation_matrix(np.pi / 2, (1, 0, 0)))
    vis.set_animation(anim, play=False)
    return vis.static_html()
