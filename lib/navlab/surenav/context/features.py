"""A Psi that can express context (issue 25, step 3): the estimator with the rules' context per node.

``surenav_estimator`` reads Eq. 7 alone (one-hot label, start and goal indicators) plus a random-walk
encoding: nothing there says how large a region's patch is, whether a sidewalk runs beside a road or
ends at it, or whether a region borders a new obstacle, and those are what the context demonstrator's
rules decide on. ``node_features = "context"`` appends, per node, what ``regions.region_context``
measures on the believed map (the same quantities the rules read; no demonstration):

- log(1 + area / 100 m²) and log(1 + patch area / 100 m²): the region's size and its patch's;
- by a sidewalk (within 12 m), a crossing point (within 8 m of a crosswalk or a sidewalk's end at a
  road), on the walkway, beside a new obstacle (within 2 m of cells hard now that were not hard in the
  first map the walker saw): 0/1 each.

``"labels"`` keeps the old input exactly (six zero columns are not appended: the same width as
``surenav_estimator``'s). The estimator class, its training loss and the differentiable A* are
``surenav_estimator``'s, unchanged; only the input encoder is wider (``ContextEstimator``), so the
existing stages do not change.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor, nn
from torch_geometric.data import Batch, Data

from navlab.core.labels import NUM_LABELS
from navlab.core.params.surenav_model import EstimatorParams
from navlab.graphs.region_graph import RegionGraph
from navlab.graphs.superpixels import HARD
from navlab.surenav.context.regions import graph_context
from navlab.surenav.model.estimator import RelaxationCostEstimator
from navlab.surenav.model.inputs import estimator_input

CONTEXT_FEATURES = ("log_area", "log_patch", "by_sidewalk", "crossing_point", "on_walkway", "beside_obstacle")
FEATURE_SETS = {"labels": 0, "context": len(CONTEXT_FEATURES)}  # node_features -> extra input columns


def context_features(graph: RegionGraph, new_hard: np.ndarray | None = None) -> np.ndarray:
    """(N, 6) float32 per node of ``graph`` (see the module docstring); ``new_hard``: cells of the
    graph's raster that are a new obstacle."""
    ctx = graph_context(graph, new_hard)
    return np.stack([np.log1p(ctx.area_m2 / 100.0), np.log1p(ctx.patch_m2 / 100.0), ctx.by_sidewalk,
                     ctx.crossing_point, ctx.on_walkway, ctx.beside_obstacle], axis=1).astype(np.float32)


def context_input(graph: RegionGraph, nodes: np.ndarray, walk_steps: int, node_features: str,
                  new_hard: np.ndarray | None = None) -> Data:
    """``model.inputs.estimator_input`` with the context columns appended when ``node_features`` is "context"."""
    if node_features not in FEATURE_SETS:
        raise ValueError(f"node_features = {node_features!r}: choose one of {', '.join(FEATURE_SETS)}")
    data = estimator_input(graph, nodes, walk_steps)
    if node_features == "context":
        extra = torch.from_numpy(context_features(graph, new_hard)[np.asarray(nodes)])
        data.x = torch.cat([data.x, extra], dim=1)
    return data


class ContextEstimator(RelaxationCostEstimator):
    """``RelaxationCostEstimator`` whose node encoder reads ``extra`` more columns (the context features)."""

    def __init__(self, params: EstimatorParams, attention: bool = True, extra: int = 0):
        super().__init__(params, attention)
        self.extra = extra
        self.node_encoder = nn.Linear(NUM_LABELS + 2 + params.walk_steps + extra, params.channels)

    def forward(self, data: Data | Batch) -> Tensor:
        expected = NUM_LABELS + 2 + self.params.walk_steps + self.extra
        if data.x.dim() != 2 or data.x.size(1) != expected:
            raise ValueError(f"node features must be (N, {expected}), got {tuple(data.x.shape)}; build them with "
                             "context_input")
        batch = getattr(data, "batch", None)
        x = self.node_encoder(data.x)
        e = self.edge_encoder(data.edge_attr / self.params.distance_scale_m)
        for k, conv in enumerate(self.local):
            x = self.gps[k](x, data.edge_index, batch, edge_attr=e) if self.gps is not None else conv(x, data.edge_index, e)
            e = conv.edge_out
        psi = self.params.cost_scale_m * F.softplus(self.head(x).squeeze(-1))
        return psi * data.soft.to(psi.dtype)


def architecture(model: ContextEstimator) -> dict:
    return {"model_config": dataclasses.asdict(model.params), "attention": model.attention, "extra": model.extra}


def from_architecture(saved: dict) -> ContextEstimator:
    return ContextEstimator(EstimatorParams(**saved["model_config"]), saved["attention"], saved["extra"])


class EstimatorCost:
    """A ``policy.RelaxationCost`` from a trained ``ContextEstimator``: the first graph it is called with
    fixes the walker's known hard space (as ``walker.RuleCost``); hard cells beyond it are new obstacles."""

    def __init__(self, model: ContextEstimator, node_features: str):
        self.model, self.node_features = model.eval(), node_features
        self.known_hard: np.ndarray | None = None

    def __call__(self, graph: RegionGraph, nodes: np.ndarray, position_xy=None, goal_xy=None) -> np.ndarray:
        hard = graph.superpixels == HARD
        if self.known_hard is None or self.known_hard.shape != hard.shape:
            self.known_hard = hard
        with torch.no_grad():
            data = context_input(graph, nodes, self.model.params.walk_steps, self.node_features,
                                 hard & ~self.known_hard)
            return self.model(data).double().numpy()
