"""GatedGCN, the local message-passing layer inside SuReNav's GPS layers (Sec. IV-C.2, ref. [23]).

Bresson & Laurent, "Residual Gated Graph ConvNets" (2017), in the form the GraphGPS reference uses
(Rampasek et al. 2022, ``gatedgcn_layer.py``): with node states x and edge states e,

    e_hat_ij = D x_i + E x_j + C e_ij                       (gate logits, also the new edge state)
    x'_i     = A x_i + sum_j sigma(e_hat_ij) ⊙ B x_j / (sum_j sigma(e_hat_ij) + eps)

then BatchNorm, ReLU, dropout and a residual connection on both x' and e_hat. PyG's
``ResGatedGraphConv`` is a different layer (no gate normalisation, no edge-state update, no norm or
residual), hence this one. Messages flow j -> i along ``edge_index[0] -> edge_index[1]``.
"""

from __future__ import annotations

import torch
import torch.nn.functional as F
from torch import Tensor, nn
from torch_geometric.nn import MessagePassing
from torch_geometric.utils import scatter


class GatedGCN(MessagePassing):
    """One GatedGCN layer on (node, edge) states of width ``channels``.

    ``forward`` returns the new node states; the new edge states are left in ``self.edge_out`` for the
    caller (PyG's ``GPSConv`` passes only node features on, so the GPS stack reads them from there).
    """

    def __init__(self, channels: int, dropout: float = 0.0, residual: bool = True, eps: float = 1e-6):
        super().__init__(aggr="add")  # ``aggregate`` below replaces the plain sum
        self.A, self.B, self.C, self.D, self.E = (nn.Linear(channels, channels) for _ in range(5))
        self.bn_node = nn.BatchNorm1d(channels)
        self.bn_edge = nn.BatchNorm1d(channels)
        self.dropout, self.residual, self.eps = dropout, residual, eps
        self.edge_out: Tensor | None = None
        self._gate_logits: Tensor | None = None

    def reset_parameters(self) -> None:
        for layer in (self.A, self.B, self.C, self.D, self.E, self.bn_node, self.bn_edge):
            layer.reset_parameters()

    def forward(self, x: Tensor, edge_index: Tensor, edge_attr: Tensor) -> Tensor:
        x_new = self.propagate(edge_index, Ax=self.A(x), Bx=self.B(x), Dx=self.D(x), Ex=self.E(x),
                               Ce=self.C(edge_attr))
        gate_logits, self._gate_logits = self._gate_logits, None
        x_new = F.dropout(F.relu(self.bn_node(x_new)), self.dropout, self.training)
        e_new = F.dropout(F.relu(self.bn_edge(gate_logits)), self.dropout, self.training)
        if self.residual:
            x_new, e_new = x + x_new, edge_attr + e_new
        self.edge_out = e_new
        return x_new

    def message(self, Dx_i: Tensor, Ex_j: Tensor, Ce: Tensor) -> Tensor:
        """sigma(e_hat_ij), e_hat_ij = D x_i + E x_j + C e_ij; e_hat is kept as the new edge state."""
        self._gate_logits = Dx_i + Ex_j + Ce
        return torch.sigmoid(self._gate_logits)

    def aggregate(self, sigma: Tensor, index: Tensor, Bx_j: Tensor, dim_size: int | None = None) -> Tensor:
        """The gate-normalised sum  sum_j sigma_ij ⊙ B x_j / (sum_j sigma_ij + eps)."""
        num = scatter(sigma * Bx_j, index, dim=0, dim_size=dim_size, reduce="sum")
        den = scatter(sigma, index, dim=0, dim_size=dim_size, reduce="sum")
        return num / (den + self.eps)

    def update(self, aggregated: Tensor, Ax: Tensor) -> Tensor:
        """x'_i = A x_i + the aggregated messages."""
        return Ax + aggregated
