"""The relaxation-cost estimator Psi_G : V -> R+ of SuReNav (Sec. IV-C.2, Eq. 8).

Encoded node states V^k and edge states E^k pass through K GPS layers (Rampasek et al. 2022):
V^{k+1}, E^{k+1} = GPS^k(V^k, E^k, A), each the sum of a local MPNN (GatedGCN, Bresson & Laurent) and
global multi-head attention, as torch_geometric's ``GPSConv``. A node-wise shared MLP with softplus
gives Psi; nodes in R_free are zero-masked (Psi is a *relaxation* cost, and free space needs none).

``attention=False`` is the ablation the issue asks for: the same stack with GatedGCN alone (no global
attention), so the difference measures what the long-range part adds.
"""

from __future__ import annotations

import dataclasses

import torch
import torch.nn.functional as F
from torch import Tensor, nn
from torch_geometric.data import Batch, Data
from torch_geometric.nn import GPSConv

from navlab.core.labels import NUM_LABELS
from navlab.core.params.surenav_model import EstimatorParams
from navlab.surenav.model.gated_gcn import GatedGCN


class RelaxationCostEstimator(nn.Module):
    def __init__(self, params: EstimatorParams, attention: bool = True):
        super().__init__()
        if params.channels % params.heads:
            raise ValueError(f"surenav.model.channels = {params.channels} must be a multiple of heads = "
                             f"{params.heads}; change one of them in params.yaml")
        c = params.channels
        self.params, self.attention = params, attention
        self.node_encoder = nn.Linear(NUM_LABELS + 2 + params.walk_steps, c)
        self.edge_encoder = nn.Linear(1, c)
        self.local = nn.ModuleList(GatedGCN(c, params.dropout) for _ in range(params.layers))
        self.gps = nn.ModuleList(GPSConv(c, conv, heads=params.heads, dropout=params.dropout)
                                 for conv in self.local) if attention else None
        self.head = nn.Sequential(nn.Linear(c, c), nn.ReLU(), nn.Linear(c, 1))

    def forward(self, data: Data | Batch) -> Tensor:
        """Psi per node (num_nodes,), metres: cost_scale_m * softplus(MLP(V^K)) on soft nodes, exactly 0 on free ones."""
        expected = NUM_LABELS + 2 + self.params.walk_steps
        if data.x.dim() != 2 or data.x.size(1) != expected:
            raise ValueError(f"node features must be (N, {expected}) (Eq. 7 + {self.params.walk_steps} random-walk "
                             f"steps), got {tuple(data.x.shape)}; build them with estimator_input(walk_steps="
                             f"{self.params.walk_steps})")
        batch = getattr(data, "batch", None)
        x = self.node_encoder(data.x)
        e = self.edge_encoder(data.edge_attr / self.params.distance_scale_m)
        for k, conv in enumerate(self.local):
            if self.gps is not None:
                x = self.gps[k](x, data.edge_index, batch, edge_attr=e)  # Eq. (8): GPS^k
            else:
                x = conv(x, data.edge_index, e)
            e = conv.edge_out  # the GatedGCN's new edge states E^{k+1}
        psi = self.params.cost_scale_m * F.softplus(self.head(x).squeeze(-1))
        return psi * data.soft.to(psi.dtype)


def build_estimator(params: EstimatorParams, attention: bool = True, device: str | torch.device = "cpu"
                    ) -> RelaxationCostEstimator:
    return RelaxationCostEstimator(params, attention).to(device)


def architecture(model: RelaxationCostEstimator) -> dict:
    """What ``from_architecture`` needs to rebuild ``model`` (stored beside its weights)."""
    return {"model_config": dataclasses.asdict(model.params), "attention": model.attention}


def from_architecture(saved: dict) -> RelaxationCostEstimator:
    return RelaxationCostEstimator(EstimatorParams(**saved["model_config"]), saved["attention"])
