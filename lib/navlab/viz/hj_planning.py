"""Figures of the HJ-search planning experiments (paper Figs. 6 and 7): plans drawn over the room."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from navlab.maps.rooms import Room


def plan_figure(room: Room, runs, goal_xy, title: str = ""):
    """Each (label, SearchResult) as a path with heading ticks; obstacles grey, start dot, goal star."""
    fig, ax = plt.subplots(figsize=(7.0, 4.2), constrained_layout=True)
    xs, ys = np.meshgrid(np.linspace(0, room.width, 481), np.linspace(0, room.height, 271))
    ax.contourf(xs, ys, room.obstacle_distance(xs, ys), levels=[-1e9, 0.0], colors=["0.6"])
    for (label, res), color in zip(runs, ["tab:red", "tab:blue", "tab:green", "tab:orange"], strict=False):
        st = res.states
        text = f"{label}: {res.status}" + (f", cost {res.cost:.2f}" if res.found else "")
        ax.plot(st[:, 0], st[:, 1], "-", color=color, lw=1.5, label=text)
        ax.quiver(st[:, 0], st[:, 1], np.cos(st[:, 3]), np.sin(st[:, 3]), color=color, scale=40, width=0.003)
        ax.plot(st[0, 0], st[0, 1], "o", color="k")
    ax.plot(*goal_xy, "*", color="gold", ms=14, mec="k")
    ax.set_xlim(0, room.width)
    ax.set_ylim(0, room.height)
    ax.set_aspect("equal")
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title(title, fontsize=10)
    return fig
