"""Matplotlib drawings of semantic maps, superpixel region graphs and demonstrations (SuReNav Figs. 5-6 style)."""

from __future__ import annotations

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.patches import Patch
from skimage.segmentation import find_boundaries

from navlab.core.labels import LABELS, colorize
from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap


def draw_labels(ax, labels: np.ndarray, frame, title: str | None = None, legend: bool = False) -> None:
    """The label raster in the paper's palette, in metres."""
    ax.imshow(colorize(labels), extent=frame.extent, interpolation="nearest")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if title:
        ax.set_title(title)
    if legend:
        present = set(np.unique(labels).tolist())
        handles = [Patch(color=np.array(lab.rgb) / 255, label=lab.name) for lab in LABELS if lab.id in present]
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)


def draw_region_graph(ax, semantic_map: SemanticMap, graph: RegionGraph, title: str | None = None) -> None:
    """Superpixel boundaries over the map, with the region-adjacency edges between centroids."""
    draw_labels(ax, semantic_map.labels, semantic_map.frame, title)
    edges = find_boundaries(graph.superpixels, mode="inner") & (graph.superpixels >= 0)
    overlay = np.zeros((*edges.shape, 4))
    overlay[edges] = (0.2, 0.2, 0.2, 0.6)
    ax.imshow(overlay, extent=semantic_map.frame.extent, interpolation="nearest")
    segments = graph.centroid[graph.edges]
    ax.add_collection(LineCollection(segments, colors="tab:blue", linewidths=0.4, alpha=0.7))
    ax.plot(graph.centroid[:, 0], graph.centroid[:, 1], ".", color="tab:blue", markersize=1.5)


def draw_demonstration(ax, labels: np.ndarray, frame, superpixels: np.ndarray, demo, title: str | None = None,
                       prefix_of=None) -> None:
    """A demonstration on the map it was drawn on, its relaxed superpixels hatched in red."""
    draw_labels(ax, labels, frame, title)
    relaxed = np.isin(superpixels, demo.relaxed_superpixels)
    overlay = np.zeros((*labels.shape, 4))
    overlay[relaxed] = (0.85, 0.1, 0.1, 0.45)
    ax.imshow(overlay, extent=frame.extent, interpolation="nearest")
    if prefix_of is not None:
        ax.plot(prefix_of.path[:, 0], prefix_of.path[:, 1], "--", color="0.3", linewidth=1, label="static drawing")
    ax.plot(demo.path[:, 0], demo.path[:, 1], color="black", linewidth=1.5, label=demo.kind.replace("_", "-"))
    ax.plot(*demo.start, "o", color="tab:green", label="start")
    ax.plot(*demo.goal, "*", color="tab:red", markersize=10, label="goal")
    ax.legend(loc="lower right", fontsize=7)
