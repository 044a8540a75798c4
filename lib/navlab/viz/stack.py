"""The stack's figure: one episode — the map with the blockage and the regions the route relaxed, PACER's
terrain costs, the aerial image with the operator's context — and on each the robot's track per row and the
pedestrians' tracks."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np

from navlab.core.labels import SOFT_IDS, colorize
from navlab.stack.ablation import NO_HJ, NO_PACER, NO_SURENAV, STACK, Outcome
from navlab.stack.world import StackEpisode
from navlab.viz.pacer import context_strip, save, show_costmap, show_image

__all__ = ["episode_figure", "save"]

ROW_COLOURS = {STACK: "tab:blue", NO_PACER: "tab:orange", NO_SURENAV: "tab:purple", NO_HJ: "tab:red"}


def _cells_xy(episode: StackEpisode, xy: np.ndarray, zoom: float = 1.0) -> np.ndarray:
    """World metres -> (col, row) image coordinates of a raster ``zoom`` times finer than the map."""
    frame = episode.prior.frame
    return (np.asarray(xy) - np.asarray(frame.origin)) / frame.resolution * zoom - 0.5


def _tracks(ax, episode: StackEpisode, outcomes: Sequence[Outcome], zoom: float = 1.0) -> None:
    for outcome in outcomes:
        xy = _cells_xy(episode, outcome.trajectory[:, 1:3], zoom)
        ax.plot(xy[:, 0], xy[:, 1], color=ROW_COLOURS[outcome.row], linewidth=1.4,
                label=f"{outcome.row} ({outcome.outcome})")
    stack = next(o for o in outcomes if o.row == STACK)
    for walker in episode.walkers:
        walked = _cells_xy(episode, np.array([walker.position(t) for t in stack.trajectory[:, 0]]), zoom)
        ax.plot(walked[:, 0], walked[:, 1], color="k", linestyle=":", linewidth=1.0)
        ax.plot(*walked[0], "k^", markersize=4)
    start, goal = (np.array(episode.start[::-1]) + 0.5) * zoom - 0.5, (np.array(episode.goal[::-1]) + 0.5) * zoom - 0.5
    ax.plot(*start, "wo", markeredgecolor="k")
    ax.plot(*goal, "w*", markeredgecolor="k", markersize=10)


def episode_figure(episode: StackEpisode, outcomes: Sequence[Outcome], pacer_costs: np.ndarray):
    """Three panels of one episode: labels as they are (the blockage in; the soft regions the stack's route
    relaxed hatched), PACER's costs (black = preferred), the aerial image with the operator's context."""
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.4))
    stack = next(o for o in outcomes if o.row == STACK)
    axes[0].imshow(colorize(episode.truth))
    walked = episode.superpixels[stack.route_cells[:, 0], stack.route_cells[:, 1]]
    soft_walked = walked[np.isin(episode.truth[stack.route_cells[:, 0], stack.route_cells[:, 1]], SOFT_IDS)]
    relaxed = np.isin(episode.superpixels, soft_walked[soft_walked >= 0])
    axes[0].contourf(relaxed, levels=[0.5, 1.5], colors="none", hatches=["//"])
    changed = episode.truth != episode.prior.labels
    axes[0].contour(changed, levels=[0.5], colors="red", linewidths=1.5)
    _tracks(axes[0], episode, outcomes)
    axes[0].set_title(f"{episode.name}: labels, blockage (red), relaxed regions (hatched)", fontsize=9)
    axes[0].axis("off")
    show_costmap(axes[1], pacer_costs, f"PACER's costs, operator: {episode.preference} (black = preferred)")
    _tracks(axes[1], episode, outcomes)
    zoom = episode.aerial.shape[1] / episode.truth.shape[0]
    show_image(axes[2], episode.aerial, "aerial image and the operator's context (preferred patch on top)")
    _tracks(axes[2], episode, outcomes, zoom)
    inset = axes[2].inset_axes([0.0, 0.0, 0.3, 0.3])
    inset.imshow(np.clip(context_strip(episode.context), 0, 1))
    inset.axis("off")
    axes[0].legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.02))
    fig.tight_layout()
    return fig
