"""PACER figures in the paper's style: preference contexts as patch pairs, costmaps dark = cheap, A* paths."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def context_strip(context, gap: int = 2) -> np.ndarray:
    """(2h, n·(w+gap), 3) image of a (3n,2h,w) context: pair i in column i, preferred patch on top."""
    context = np.asarray(context, dtype=np.float32)
    n, two_h, w = context.shape[0] // 3, context.shape[1], context.shape[2]
    out = np.ones((two_h, n * (w + gap) - gap, 3), dtype=np.float32)
    for i in range(n):
        out[:, i * (w + gap):i * (w + gap) + w] = context[3 * i:3 * i + 3].transpose(1, 2, 0)
    return out


def show_image(ax, image, title: str = "") -> None:
    """A (3,H,W) image in [0, 1]."""
    ax.imshow(np.clip(np.asarray(image).transpose(1, 2, 0), 0, 1))
    ax.set_title(title, fontsize=9)
    ax.axis("off")


def show_costmap(ax, costmap, title: str = "", paths: Sequence[tuple[np.ndarray, str]] = ()):
    """Costs in [0, 1], black = low (as in Fig. 1), with optional (cells, colour) paths on top; framed, so a
    flat all-high costmap reads as a white map, not as a blank panel. Returns the image (for a colour bar)."""
    image = ax.imshow(np.asarray(costmap), cmap="gray", vmin=0.0, vmax=1.0)
    for cells, colour in paths:
        if cells is not None:
            ax.plot(cells[:, 1], cells[:, 0], color=colour, linewidth=1.5)
    ax.set_title(title, fontsize=9)
    ax.set_xticks([])
    ax.set_yticks([])
    return image


def show_paths(ax, image, paths: Sequence[tuple[np.ndarray, str, str]], start=None, goal=None, title: str = "") -> None:
    """An aerial image with (cells, colour, label) paths, start (circle) and goal (star)."""
    show_image(ax, image, title)
    for cells, colour, label in paths:
        if cells is not None:
            ax.plot(cells[:, 1], cells[:, 0], color=colour, linewidth=1.5, label=label)
    if start is not None:
        ax.plot(start[1], start[0], "o", color="white", markeredgecolor="black")
    if goal is not None:
        ax.plot(goal[1], goal[0], "*", color="yellow", markeredgecolor="black", markersize=12)
    if paths:
        ax.legend(fontsize=7, loc="lower left")


def save(fig, path) -> None:
    """PNG at a fixed dpi (figures are regenerated, not versioned).

    The figure stays open so that a notebook shows it under the cell; the inline backend closes it then.
    """
    fig.savefig(path, dpi=120, bbox_inches="tight")
