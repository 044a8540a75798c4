"""Figures of the SuReNav benchmark: the Fig. 4 safety-efficiency scatter and the Fig. 5 paths."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from navlab.core.labels import HARD_IDS
from navlab.surenav.benchmark import EXPERT, SURENAV, SURENAV_MPNN, SURENAV_RCR, Outcome, method_of
from navlab.surenav.context.benchmark import EXPERT as CONTEXT_EXPERT
from navlab.surenav.episodes import Environment
from navlab.viz.region_graphs import draw_labels

MARKERS = {"milan": "o", "baltimore": "s", "capitol_hill": "^"}
COLOURS = {"D* Lite": "tab:blue", "COA*": "tab:purple", "RCR": "tab:red", SURENAV: "tab:green",
           SURENAV_RCR: "tab:olive", SURENAV_MPNN: "tab:cyan", EXPERT: "black", CONTEXT_EXPERT: "black"}


def draw_safety_efficiency(ax, rows: list[dict]) -> None:
    """Fig. 4: mean SPL against mean total risk, one marker per method and city, 95% CI whiskers.
    Rows without numbers (a method not run) are skipped."""
    for r in rows:
        if r.get("spl") is None:
            continue
        xerr = np.abs(np.array(r["total_risk_ci"]) - r["total_risk"])[:, None]
        yerr = np.abs(np.array(r["spl_ci"]) - r["spl"])[:, None]
        ax.errorbar(r["total_risk"], r["spl"], xerr=xerr, yerr=yerr, marker=MARKERS.get(r["city"], "o"),
                    color=COLOURS.get(r["method"], "gray"), linestyle="none", capsize=2, markersize=6)
    for method, colour in COLOURS.items():
        if any(r["method"] == method and r.get("spl") is not None for r in rows):
            ax.plot([], [], "o", color=colour, label=method)
    for city, marker in MARKERS.items():
        ax.plot([], [], marker, color="gray", label=city, linestyle="none")
    ax.set_xlabel("total risk [risk·m] (lower is safer)")
    ax.set_ylabel("SPL (higher is more efficient)")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def draw_paths(ax, prior_labels: np.ndarray, truth: np.ndarray, frame, paths: dict[str, np.ndarray], start_xy,
               goal_xy, title: str | None = None) -> None:
    """Fig. 5: the true map in the paper's palette, the changed cells outlined, every method's trajectory."""
    draw_labels(ax, truth, frame, title)
    changed = prior_labels != truth
    overlay = np.zeros((*truth.shape, 4))
    overlay[changed & np.isin(truth, HARD_IDS)] = (0.8, 0.0, 0.0, 0.35)
    overlay[changed & ~np.isin(truth, HARD_IDS)] = (0.9, 0.8, 0.0, 0.35)
    ax.imshow(overlay, extent=frame.extent, interpolation="nearest")
    for method, xy in paths.items():
        ax.plot(xy[:, 0], xy[:, 1], color=COLOURS.get(method, "gray"), linewidth=1.6, label=method)
    ax.plot(*start_xy, "o", color="tab:green", markersize=9, markeredgecolor="black")
    ax.plot(*goal_xy, "*", color="gold", markersize=14, markeredgecolor="black")
    ax.legend(fontsize=7, loc="lower right")


def draw_behaviours(candidates: Sequence[Environment], outcomes: Sequence[Outcome], shown: Mapping[str, str],
                    path: str | Path, margin_m: float = 20.0) -> None:
    """Fig. 5: per city, every method's path on the episode ``shown[city]`` (``benchmark.most_contrasting``),
    framed on the paths; saved to ``path``."""
    cities = list(shown)
    fig, axes = plt.subplots(1, len(cities), figsize=(6 * len(cities), 6), constrained_layout=True)
    for ax, city in zip(np.atleast_1d(axes), cities, strict=True):
        env = next(e for e in candidates if e.name == shown[city])
        paths = {method_of(o.method): o.trajectory for o in outcomes if o.environment == env.name}
        frame = env.prior.frame
        draw_paths(ax, env.prior.labels, env.truth, frame, paths, frame.cell_to_world(env.start),
                   frame.cell_to_world(env.goal), f"{city} ({env.prior.name}), episode {env.name}")
        box = np.concatenate(list(paths.values()))
        ax.set_xlim(box[:, 0].min() - margin_m, box[:, 0].max() + margin_m)
        ax.set_ylim(box[:, 1].max() + margin_m, box[:, 1].min() - margin_m)
    fig.savefig(path, dpi=120)
    plt.close(fig)
