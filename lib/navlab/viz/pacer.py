"""PACER figures in the paper's style: preference contexts as patch pairs, costmaps dark = cheap, A* paths.

The notebooks compute (``navlab.pacer.experiments``) and call one function here per figure; no figure is
assembled in a notebook cell.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np

from navlab.pacer.recognition import true_terrains_name

# One colour per method, the same in every paths figure.
METHOD_COLOURS = {"PACER": "tab:blue", "PACER (uninformative context)": "tab:cyan", "STERLING-style": "tab:orange",
                  "Classifier": "tab:purple", "Ground truth": "white", "Window oracle (ceiling)": "tab:green",
                  "Context-limited oracle": "tab:olive", "Uniform costmap (chance)": "tab:gray",
                  true_terrains_name("PACER"): "tab:red"}
# A context's path, by the k-th preference of a figure.
CONTEXT_COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple")


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


def bev_contexts_figure(costed: Sequence[tuple[str, dict, np.ndarray]]):
    """Fig. 3 style: per (preference, BEV item, predicted costmap) a row of the image, the context (preferred
    patch on top), PACER's costmap and the target, both masked to the field of view."""
    fig, axes = plt.subplots(len(costed), 4, figsize=(11, 2.75 * len(costed)), squeeze=False)
    for row, (name, item, cost) in zip(axes, costed):
        show_image(row[0], item["image"], "BEV image")
        row[1].imshow(context_strip(item["context"]))
        row[1].set_title(f"{name} context (top ≻ bottom)", fontsize=9)
        row[1].axis("off")
        fov = np.asarray(item["fov_mask"])
        show_costmap(row[2], np.where(fov, cost, np.nan), "PACER costmap")
        show_costmap(row[3], np.where(fov, np.asarray(item["costmap"]), np.nan), "target costmap")
    return fig


def context_paths_figure(amap, runs: Sequence, title: str):
    """Figs. 1, 4 and 5 style: the aerial map with one A* path per context, then per context its patch
    pairs and the costmap it produced with that path (``runs``: ``experiments.ContextRun``)."""
    widths = [3] + [1.2, 3] * len(runs)
    fig, axes = plt.subplots(1, len(widths), figsize=(sum(widths) * 1.3, 4), gridspec_kw={"width_ratios": widths})
    drawn = []
    for k, run in enumerate(runs):
        colour = CONTEXT_COLOURS[k % len(CONTEXT_COLOURS)]
        label = f"{run.preference} context"
        if run.preference == "random":  # the random orderings numbered among themselves: 1, 2, ...
            label += f" {sum(r.preference == 'random' for r in runs[:k + 1])}"
        drawn.append((run.path, colour, label))
        axes[1 + 2 * k].imshow(context_strip(run.context))
        axes[1 + 2 * k].set_title(label, fontsize=9)
        axes[1 + 2 * k].axis("off")
        show_costmap(axes[2 + 2 * k], run.cost, f"costmap ({label})", [(run.path, colour)])
    show_paths(axes[0], amap.image, drawn, amap.start, amap.goal, title)
    return fig


def method_paths_figure(maps: Sequence, paths: Mapping[str, Sequence[np.ndarray]], title: str, shown: int = 3):
    """Every method's path (``NavigationResult.paths``) on each of the first ``shown`` maps."""
    shown = min(shown, len(maps))
    fig, axes = plt.subplots(1, shown, figsize=(5 * shown, 5), squeeze=False)
    for k in range(shown):
        drawn = [(cells[k], METHOD_COLOURS.get(name, "tab:brown"), name) for name, cells in paths.items()
                 if len(cells) > k]
        show_paths(axes[0, k], maps[k].image, drawn, maps[k].start, maps[k].goal, f"{title} {k}")
    return fig


def agreement_figure(agreement: Mapping[tuple, object], models: Sequence[str], contexts: Sequence[str]):
    """Held-out pair agreement (``experiments.context_following_rows``' second value) per model and set,
    one panel per context draw, with the bootstrap intervals; 0.5 is chance."""
    labels = [(env, pref) for env in ("seen", "unseen") for pref in ("realistic", "inverted")]
    width = 0.8 / max(len(models), 1)
    fig, axes = plt.subplots(1, len(contexts), figsize=(5.5 * len(contexts), 3.8), sharey=True, squeeze=False)
    for ax, context in zip(axes[0], contexts):
        for k, name in enumerate(models):
            found = [agreement[name, env, pref, context] for env, pref in labels]
            errors = np.array([[a.fraction - a.ci[0], a.ci[1] - a.fraction] if a.ci else [0, 0] for a in found]).T
            ax.bar(np.arange(len(labels)) + width * k, [a.fraction for a in found], width=width, yerr=errors,
                   label=name)
        ax.axhline(0.5, color="gray", linestyle=":")
        ax.set_xticks(np.arange(len(labels)) + width * (len(models) - 1) / 2, [f"{e}/{p}" for e, p in labels],
                      fontsize=8)
        ax.set_title(f"{context} contexts: pairs ordered as the context says", fontsize=9)
    axes[0, 0].legend(fontsize=8)
    return fig


def save(fig, path) -> None:
    """PNG at a fixed dpi (figures are regenerated, not versioned), then closed: a notebook shows the saved
    file beside its table (``viz.report.show``), once."""
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
