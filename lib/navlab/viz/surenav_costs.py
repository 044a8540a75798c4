"""SuReNav Fig. 6: learned relaxation costs on the superpixels (bright = cheap), and training curves."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import colormaps
from matplotlib.colors import Normalize
from matplotlib.ticker import MaxNLocator
from skimage.segmentation import find_boundaries

from navlab.core.labels import SOFT_IDS
from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.estimator_report import CostScenario
from navlab.viz.region_graphs import draw_labels


def draw_relaxation_costs(ax, semantic_map: SemanticMap, graph: RegionGraph, nodes: np.ndarray, psi: np.ndarray,
                          route: np.ndarray | None = None, demo_path: np.ndarray | None = None,
                          title: str | None = None, vmax: float | None = None):
    """The map in the paper's palette with every soft superpixel of the window painted by its Psi
    (``magma_r``: bright = low relaxation cost), superpixel boundaries, the graph plan's region centroids
    (cyan) and the expert's path (black). Returns the colour mapping for a colourbar."""
    draw_labels(ax, semantic_map.labels, semantic_map.frame, title)
    soft = np.isin(graph.node_label[nodes], SOFT_IDS)
    value = np.full(graph.num_nodes, np.nan)
    value[nodes[soft]] = psi[soft]
    raster = np.where(graph.node_raster >= 0, value[np.maximum(graph.node_raster, 0)], np.nan)
    norm = Normalize(0.0, vmax if vmax is not None else float(np.nanmax(value)) if soft.any() else 1.0)
    rgba = colormaps["magma_r"](norm(np.nan_to_num(raster)))
    rgba[..., 3] = np.where(np.isnan(raster), 0.0, 0.9)
    ax.imshow(rgba, extent=semantic_map.frame.extent, interpolation="nearest")
    edges = find_boundaries(graph.superpixels, mode="inner") & (graph.superpixels >= 0)
    overlay = np.zeros((*edges.shape, 4))
    overlay[edges] = (0.3, 0.3, 0.3, 0.35)
    ax.imshow(overlay, extent=semantic_map.frame.extent, interpolation="nearest")
    if demo_path is not None:
        ax.plot(demo_path[:, 0], demo_path[:, 1], color="black", linewidth=1.3, label="expert")
    if route is not None:
        ax.plot(graph.centroid[route, 0], graph.centroid[route, 1], ".-", color="tab:cyan", linewidth=1.2,
                markersize=3, label="graph plan X_G")
    box = graph.centroid[nodes]
    ax.set_xlim(box[:, 0].min() - 5, box[:, 0].max() + 5)
    ax.set_ylim(box[:, 1].max() + 5, box[:, 1].min() - 5)
    ax.legend(loc="lower right", fontsize=7)
    return colormaps["magma_r"], norm


def draw_training_curves(ax_loss, ax_iou, logs: Mapping[str, list[dict]]) -> None:
    """Train / validation loss (Eq. 13) and relaxation IoU per epoch, one colour per run."""
    for k, (name, rows) in enumerate(logs.items()):
        epochs = [r["epoch"] for r in rows]
        colour = f"C{k}"
        ax_loss.plot(epochs, [r["train_loss"] for r in rows], "-", color=colour, label=f"{name} train")
        ax_loss.plot(epochs, [r["val_loss"] for r in rows], "--", color=colour, label=f"{name} val")
        ax_iou.plot(epochs, [r["val_iou"] for r in rows], "o-", color=colour, label=f"{name} val")
        ax_iou.plot(epochs, [r["train_iou"] for r in rows], ":", color=colour, label=f"{name} train")
    for ax, label in ((ax_loss, "loss (Eq. 13)"), (ax_iou, "plan relaxation IoU (val o-, train :)")):
        ax.set_xlabel("epoch")
        ax.set_ylabel(label)
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.legend(fontsize=7)


def draw_training_logs(logs: Mapping[str, list[dict]], path: str | Path) -> None:
    """``draw_training_curves`` of every run in ``logs`` side by side (loss, IoU), saved to ``path``."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4), constrained_layout=True)
    draw_training_curves(axes[0], axes[1], logs)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def draw_learned_costs(scenarios: Sequence[CostScenario], path: str | Path) -> None:
    """Fig. 6: each scenario's learned Psi (``draw_relaxation_costs``) on one shared colour scale, with its
    colour bar, saved to ``path``."""
    fig, axes = plt.subplots(1, len(scenarios), figsize=(6.5 * len(scenarios), 6), constrained_layout=True,
                             squeeze=False)
    soft = [sc.psi[np.isin(sc.graph.node_label[sc.nodes], SOFT_IDS)] for sc in scenarios]
    vmax = max((float(v.max()) for v in soft if len(v)), default=1.0)
    norm = cmap = None
    for k, (ax, sc) in enumerate(zip(axes[0], scenarios, strict=True)):
        cmap, norm = draw_relaxation_costs(ax, sc.view, sc.graph, sc.nodes, sc.psi, sc.route, sc.demo.path,
                                           f"({'abcd'[k]}) {sc.view.name}, semi-static", vmax=vmax)
    if norm is not None:
        fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes[0], shrink=0.7,
                     label="Psi [m] (bright = cheap)")
    fig.savefig(path, dpi=120)
    plt.close(fig)
