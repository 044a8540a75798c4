"""The stack's terrain layer: what each map cell costs the operator, in [0, 1] (0 the most preferred).

PACER (the method): the trained phase-3 network reads the episode's aerial image and the operator's
preference context (Sec. IV; ``pacer.evaluate.costmap_over_map``), and its costs at PACER's ground scale are
averaged over each map cell. Label costs (the ablation's simpler counterpart): a fixed table from the
semantic labels alone, the realistic order of the terrain each label is painted with (rank costs
(l - 1) / (L - 1), PACER's training targets), which cannot follow an operator who orders terrains otherwise.
"""

from __future__ import annotations

import numpy as np
import torch

from navlab.core.params import Params
from navlab.pacer.bev import fov_mask
from navlab.pacer.evaluate import costmap_over_map
from navlab.pacer.preferences import order_terrains, rank_costs
from navlab.pacer.terrain import TerrainBank
from navlab.stack.world import StackEpisode


def _per_cell(costs: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    zoom = costs.shape[0] // shape[0]
    return costs.reshape(shape[0], zoom, shape[1], zoom).mean(axis=(1, 3))


def pacer_costs(model: torch.nn.Module, episode: StackEpisode, params: Params) -> np.ndarray:
    """(H, W) PACER's cost of each map cell for the episode's operator context."""
    D = params.pacer.data
    costs = costmap_over_map(model, torch.from_numpy(episode.aerial), torch.from_numpy(episode.context),
                             fov_mask(D.image_size, D.camera.near_width), device=params.pacer.train.device)
    return _per_cell(costs.cpu().numpy().astype(np.float64), episode.truth.shape)


def label_costs(episode: StackEpisode, bank: TerrainBank) -> np.ndarray:
    """(H, W) the fixed label table's cost of each cell: its terrain's rank in the realistic order."""
    present = np.unique(episode.terrain)
    ordering = order_terrains(present, "realistic", bank, np.random.default_rng(0))  # realistic: no draw
    table = np.zeros(len(bank), dtype=np.float64)
    table[ordering] = rank_costs(ordering)
    return table[episode.terrain]
