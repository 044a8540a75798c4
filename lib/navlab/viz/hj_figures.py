"""Matplotlib figures in the style of the HJ-search paper: heuristic contours (Fig. 2), BRT slices (Fig. 3), the
human-robot BRT in the robot's frame."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle, Rectangle

from navlab.hj.guidance import euclidean_time
from navlab.hj.value_functions import FIG2_ROBOTS, Fig2, Fig3, speed_slice
from navlab.maps.rooms import Disc, Rect, Room


def draw_room(ax, room: Room, color: str = "0.3") -> None:
    """Walls and obstacles in room coordinates (x right, y up as in the paper's plots)."""
    ax.add_patch(Rectangle((0, 0), room.width, room.height, fill=False, lw=2, ec=color))
    for ob in room.obstacles:
        if isinstance(ob, Rect):
            ax.add_patch(Rectangle((ob.x0, ob.y0), ob.x1 - ob.x0, ob.y1 - ob.y0, color=color))
        elif isinstance(ob, Disc):
            ax.add_patch(Circle((ob.cx, ob.cy), ob.r, color=color))
    ax.set_xlim(-0.1, room.width + 0.1)
    ax.set_ylim(-0.1, room.height + 0.1)
    ax.set_aspect("equal")


def heuristic_fields(room: Room, goal, robots: list[tuple[float, float, float, float]], ttr, map_ttr,
                     geodesic: tuple[np.ndarray, object], robot_radius: float, v_max: float) -> dict:
    """Fig. 2's four heuristics over the room's free positions, as ``heuristic_contours`` takes them: the two
    TTRs at each robot's speed and heading (one field per robot), map Dist (``geodesic``: the field and frame of
    ``hj.guidance.geodesic_time_field``, whose cell centres are the plotted positions) and general Dist."""
    geo, frame = geodesic
    rows, cols = geo.shape
    X, Y = np.meshgrid(frame.origin[0] + (np.arange(cols) + 0.5) * frame.resolution,
                       frame.origin[1] + (np.arange(rows) + 0.5) * frame.resolution, indexing="xy")
    free = room.signed_distance(X, Y, robot_radius) > 0

    def at(lookup, v, theta):
        states = np.stack([X.ravel(), Y.ravel(), np.full(X.size, v), np.full(X.size, theta)], -1)
        return np.where(free, lookup(states).reshape(X.shape), np.nan)

    return {
        "map TTR": [(X, Y, at(map_ttr, v, th)) for (_, _, v, th) in robots],
        "general TTR": [(X, Y, at(lambda s: ttr(s, goal), v, th)) for (_, _, v, th) in robots],
        "map Dist": (X, Y, np.where(free, geo, np.nan)),
        "general Dist": (X, Y, np.where(free, euclidean_time(np.stack([X, Y], -1), goal, v_max), np.nan)),
    }


def heuristic_contours(room: Room, fields: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]],
                       robots: list[tuple[float, float, float, float]], goal, values: dict[tuple[int, str], float],
                       levels: np.ndarray):
    """Fig. 2: one column per heuristic, one row per robot state.

    ``fields[name] = (X, Y, H)`` or a list of them per row (H over positions for that row's v, θ);
    ``values[(row, name)]`` is the heuristic at the robot, printed in the panel title.
    """
    fig, axes = plt.subplots(len(robots), len(fields), figsize=(4.2 * len(fields), 2.8 * len(robots)),
                             squeeze=False, constrained_layout=True)
    for r, (x, y, v, th) in enumerate(robots):
        for c, (name, field) in enumerate(fields.items()):
            ax = axes[r, c]
            X, Y, H = field[r] if isinstance(field, list) else field
            cs = ax.contourf(X, Y, np.ma.masked_invalid(H), levels=levels, cmap="viridis", extend="max")
            ax.contour(X, Y, np.ma.masked_invalid(H), levels=levels, colors="k", linewidths=0.3)
            draw_room(ax, room)
            ax.plot(*goal, marker="*", ms=14, color="gold", mec="k")
            ax.arrow(x, y, 0.5 * np.cos(th), 0.5 * np.sin(th), width=0.06, color="red")
            ax.set_title(f"{name}: {values[(r, name)]:.2f} s (v={v:.1f} m/s, θ={np.degrees(th):.0f}°)", fontsize=9)
    fig.colorbar(cs, ax=axes, label="heuristic (s)", shrink=0.8)
    return fig


def brt_slices(room: Room, values: np.ndarray, grid, speeds, theta: float):
    """Fig. 3: the static BRT {V < 0} at heading ``theta`` for several speeds (it grows with speed)."""
    th_idx = round((theta - grid.lo[3]) / grid.spacing[3]) % grid.shape[3]
    X, Y = np.meshgrid(grid.axis(0), grid.axis(1), indexing="ij")
    fig, axes = plt.subplots(1, len(speeds) + 1, figsize=(3.6 * (len(speeds) + 1), 2.6), constrained_layout=True)
    colors = plt.cm.plasma(np.linspace(0.1, 0.85, len(speeds)))
    for ax, v, color in zip(axes, speeds, colors):
        V = speed_slice(values, grid, v)[:, :, th_idx]
        ax.contourf(X, Y, V, levels=[V.min() - 1, 0.0], colors=[color], alpha=0.6)
        draw_room(ax, room)
        ax.arrow(0.4, 0.4, 0.4 * np.cos(theta), 0.4 * np.sin(theta), width=0.05, color="k")
        ax.set_title(f"v = {v:.2f} m/s: {100 * (V < 0).mean():.0f}% unsafe", fontsize=9)
    ax = axes[-1]
    for v, color in zip(speeds, colors):
        ax.contour(X, Y, speed_slice(values, grid, v)[:, :, th_idx], levels=[0.0], colors=[color])
    draw_room(ax, room)
    ax.set_title(f"zero level sets, θ = {np.degrees(theta):.0f}°", fontsize=9)
    return fig


def human_brt_figure(human, v_max: float, horizon_s: float):
    """The human-robot BRT's zero level set in the robot's frame (x ahead, y left) at three robot speeds from 0
    to ``v_max``: where the pursuing human can force a collision within the horizon (``human``: a
    ``reach.lookup.HumanBRTLookup``; its speed axis starts at v_min, below 0 for the reversing car)."""
    values, grid = np.asarray(human.stored.values), human.grid
    PX, PY = np.meshgrid(grid.axis(0), grid.axis(1), indexing="ij")
    fig, ax = plt.subplots(figsize=(4.5, 4.2), constrained_layout=True)
    for v, color in zip(np.linspace(0, v_max, 3), ["tab:blue", "tab:orange", "tab:red"]):
        iv = round((v - grid.lo[2]) / grid.spacing[2])
        ax.contour(PX, PY, values[:, :, iv], levels=[0.0], colors=[color])
        ax.plot([], [], color=color, label=f"v = {grid.axis(2)[iv]:.2f} m/s")
    ax.arrow(0, 0, 0.4, 0, width=0.05, color="k")
    ax.set_aspect("equal")
    ax.legend(fontsize=8)
    ax.set_xlabel("human ahead (m)")
    ax.set_ylabel("human left (m)")
    ax.set_title(f"human-robot BRT, horizon {horizon_s} s", fontsize=9)
    return fig


def _save(fig, path: str | Path) -> None:
    fig.savefig(path, dpi=120)
    plt.close(fig)


def draw_fig2(fig2: Fig2, robot_radius: float, v_max: float, horizon_s: float, path: str | Path) -> None:
    """Fig. 2 of ``hj.value_functions.fig2`` as a PNG at ``path``: the four heuristics contoured over the room
    at each robot's speed and heading, 25 levels from 0 to max(12 s, the TTR horizon)."""
    fields = heuristic_fields(fig2.room, fig2.goal, list(FIG2_ROBOTS), fig2.ttr, fig2.map_ttr, fig2.geodesic,
                              robot_radius, v_max)
    _save(heuristic_contours(fig2.room, fields, list(FIG2_ROBOTS), fig2.goal, fig2.values,
                             np.linspace(0, max(12.0, horizon_s), 25)), path)


def draw_fig3(fig3: Fig3, path: str | Path) -> None:
    """Fig. 3 of ``hj.value_functions.fig3`` as a PNG at ``path``: the static BRT's slices at heading 0."""
    _save(brt_slices(fig3.room, np.asarray(fig3.brt.stored.values), fig3.brt.grid, fig3.speeds, theta=0.0), path)


def draw_human_brt(human, v_max: float, horizon_s: float, path: str | Path) -> None:
    """``human_brt_figure`` as a PNG at ``path``."""
    _save(human_brt_figure(human, v_max, horizon_s), path)
