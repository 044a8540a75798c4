"""The stack's figures: one episode — the map with the blockage and the regions the route relaxed, the terrain
costs the route planned on, the aerial image with the operator's context — and on each the robot's track per
row and the pedestrians' tracks; and one moment of a drive (the stack playground's time slider): where the
robot and the pedestrians are then, and the tracks so far.

Built on ``matplotlib.figure.Figure``, not pyplot, so a playground's redraw shows once (as its image) and
not again as a stray inline figure of the notebook."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from navlab.core.labels import colorize
from navlab.metrics.relaxation import relaxed_regions
from navlab.stack.ablation import NO_HJ, NO_PACER, NO_SURENAV, STACK, Outcome
from navlab.stack.world import StackEpisode
from navlab.viz.pacer import context_strip, save, show_costmap, show_image

__all__ = ["Moment", "episode_figure", "moment_figure", "save"]

ROW_COLOURS = {STACK: "tab:blue", NO_PACER: "tab:orange", NO_SURENAV: "tab:purple", NO_HJ: "tab:red"}
PEDESTRIAN_COLOUR = "tab:pink"


@dataclass(frozen=True)
class Moment:
    """Where everything is at time ``t`` of a drive: the robot (x, y, heading), the pedestrians (N, 2)."""

    t: float
    robot: np.ndarray
    pedestrians: np.ndarray


def _cells_xy(episode: StackEpisode, xy: np.ndarray, zoom: float = 1.0) -> np.ndarray:
    """World metres -> (col, row) image coordinates of a raster ``zoom`` times finer than the map."""
    frame = episode.prior.frame
    return (np.asarray(xy) - np.asarray(frame.origin)) / frame.resolution * zoom - 0.5


def _tracks(ax, episode: StackEpisode, outcomes: Sequence[Outcome], zoom: float = 1.0) -> None:
    """Every row's route (dashed: the route layer's walk) and track, the pedestrians' (over the longest drive
    shown; their planned walk before any), the start (circle) and the goal (star)."""
    for outcome in outcomes:
        route = (outcome.route_cells[:, ::-1] + 0.5) * zoom - 0.5
        ax.plot(route[:, 0], route[:, 1], color=ROW_COLOURS[outcome.row], linewidth=0.8, linestyle="--")
        xy = _cells_xy(episode, outcome.trajectory[:, 1:3], zoom)
        ax.plot(xy[:, 0], xy[:, 1], color=ROW_COLOURS[outcome.row], linewidth=1.4,
                label=f"{outcome.row} ({outcome.outcome})")
    longest = max((o.trajectory[-1, 0] for o in outcomes), default=None)
    times = np.linspace(0.0, longest, 200) if longest is not None else None
    for walker in episode.walkers:
        walked = _cells_xy(episode, walker.path if times is None else walker.track(times), zoom)
        ax.plot(walked[:, 0], walked[:, 1], color="k", linestyle=":", linewidth=1.0)
        ax.plot(*_cells_xy(episode, walker.position(0.0), zoom), "k^", markersize=4)
    start, goal = (np.array(episode.start[::-1]) + 0.5) * zoom - 0.5, (np.array(episode.goal[::-1]) + 0.5) * zoom - 0.5
    ax.plot(*start, "wo", markeredgecolor="k")
    ax.plot(*goal, "w*", markeredgecolor="k", markersize=10)


def _relaxed(episode: StackEpisode, route_cells: np.ndarray) -> np.ndarray:
    """(H, W) bool: the soft superpixels a route walked on (its relaxed set, ``metrics.relaxation``)."""
    return np.isin(episode.superpixels, relaxed_regions(route_cells, episode.truth, episode.superpixels))


def episode_figure(episode: StackEpisode, outcomes: Sequence[Outcome], costs: np.ndarray,
                   costs_name: str = "PACER's costs") -> Figure:
    """Three panels of one episode: labels as they are (the blockage in; the soft regions the route relaxed
    hatched: the stack's, else the first row's; the walkway route grey), the terrain costs (black = preferred), the aerial image with
    the operator's context. No outcome: the episode before a drive (the pedestrians' planned walk)."""
    fig = Figure(figsize=(15, 5.4))
    axes = fig.subplots(1, 3)
    axes[0].imshow(colorize(episode.truth))
    shown = next((o for o in outcomes if o.row == STACK), outcomes[0] if outcomes else None)
    if shown is not None and len(shown.route_cells):
        axes[0].contourf(_relaxed(episode, shown.route_cells), levels=[0.5, 1.5], colors="none", hatches=["//"])
    changed = episode.truth != episode.prior.labels
    if changed.any():
        axes[0].contour(changed, levels=[0.5], colors="red", linewidths=1.5)
    if episode.walkway is not None:  # where a map router would go, and the blockage was put
        axes[0].plot(episode.walkway[:, 1], episode.walkway[:, 0], color="0.4", linewidth=1.0, linestyle="--",
                     label="walkway route")
    _tracks(axes[0], episode, outcomes)
    axes[0].set_title(f"{episode.name}: labels, blockage (red), relaxed regions (hatched)", fontsize=9)
    axes[0].axis("off")
    show_costmap(axes[1], costs, f"{costs_name}, operator: {episode.preference} (black = preferred)")
    _tracks(axes[1], episode, outcomes)
    zoom = episode.aerial.shape[1] / episode.truth.shape[0]
    show_image(axes[2], episode.aerial, "aerial image and the operator's context (preferred patch on top)")
    _tracks(axes[2], episode, outcomes, zoom)
    inset = axes[2].inset_axes([0.0, 0.0, 0.3, 0.3])
    inset.imshow(np.clip(context_strip(episode.context), 0, 1))
    inset.axis("off")
    if outcomes or episode.walkway is not None:
        axes[0].legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.02))
    fig.tight_layout()
    return fig


def moment_figure(episode: StackEpisode, outcome: Outcome, moment: Moment, robot_radius: float,
                  human_radius: float) -> Figure:
    """The map as it is (world metres; the blockage outlined red) with the route layer's route (dashed), the
    robot's whole track faint and its track up to ``moment`` solid, the robot's disc and heading then, and each
    pedestrian's disc then with its track so far."""
    frame = episode.prior.frame
    fig = Figure(figsize=(6.0, 6.0))
    ax = fig.add_axes((0.08, 0.06, 0.9, 0.88))
    ax.imshow(colorize(episode.truth), extent=frame.extent, interpolation="nearest")
    changed = episode.truth != episode.prior.labels
    if changed.any():
        ax.contour(changed, levels=[0.5], colors="red", linewidths=1.2, extent=frame.extent, origin="upper")
    traj, colour = outcome.trajectory, ROW_COLOURS[outcome.row]
    route = frame.cell_to_world(outcome.route_cells)
    ax.plot(route[:, 0], route[:, 1], color=colour, linewidth=0.8, linestyle="--", alpha=0.6)
    ax.plot(traj[:, 1], traj[:, 2], color=colour, linewidth=1.0, alpha=0.35)
    so_far = traj[traj[:, 0] <= moment.t]
    ax.plot([*so_far[:, 1], moment.robot[0]], [*so_far[:, 2], moment.robot[1]], color=colour, linewidth=1.8)
    # the discs at their true size, and a marker of fixed size over each: a 0.3 m disc is a speck on a 50 m map
    ax.add_patch(Circle(moment.robot[:2], robot_radius, facecolor=colour, edgecolor="k", zorder=5))
    ax.plot(*moment.robot[:2], "o", color=colour, markeredgecolor="k", markersize=9, alpha=0.6, zorder=5)
    heading = np.array([np.cos(moment.robot[2]), np.sin(moment.robot[2])])
    ax.annotate("", moment.robot[:2] + 2.0 * heading, moment.robot[:2], zorder=6,
                arrowprops={"arrowstyle": "->", "color": "k", "linewidth": 1.2})
    times = np.linspace(0.0, moment.t, 60)
    for walker, here in zip(episode.walkers, moment.pedestrians, strict=True):
        walked = walker.track(times)
        ax.plot(walked[:, 0], walked[:, 1], color=PEDESTRIAN_COLOUR, linewidth=1.0, linestyle=":")
        ax.add_patch(Circle(here, human_radius, facecolor=PEDESTRIAN_COLOUR, edgecolor="k", zorder=5))
        ax.plot(*here, "o", color=PEDESTRIAN_COLOUR, markeredgecolor="k", markersize=7, alpha=0.6, zorder=5)
    ends = frame.cell_to_world(np.array([episode.start, episode.goal]))
    ax.plot(*ends[0], "wo", markeredgecolor="k")
    ax.plot(*ends[1], "w*", markeredgecolor="k", markersize=12)
    ax.set_xlim(*frame.extent[:2])
    ax.set_ylim(*frame.extent[2:])
    ax.tick_params(labelsize=7)
    ax.set_title(f"{outcome.row}: t = {moment.t:.1f} s of {traj[-1, 0]:.1f} s ({outcome.outcome})", fontsize=9)
    return fig
