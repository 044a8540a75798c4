"""Using a costmap: predicted costs over a large map, A* paths on them, and agreement with an ordering.

PACER's aerial-map experiments (Sec. VI-A) give the robot its local BEV at each pose; we cover a large
rendered map with overlapping BEV-sized windows instead, each window contributing only inside its
field-of-view trapezoid (the only pixels the network was trained on), and plan once on the stitched
map. The *window oracle* costs every window exactly as its training target and is stitched the same
way: what a perfect model would score under this protocol. The planner sees cost per metre 1 + cost_scale · c for predicted cost c ∈ [0, 1].
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import torch
from torch.nn import functional as F

from navlab.pacer.aerial import EDGE_MARGIN
from navlab.pacer.preferences import IGNORE, target_costmap
from navlab.search.grid_astar import GridPath, plan


def stitch_windows(window_costs: Callable[[list[tuple[int, int]]], torch.Tensor], shape: tuple[int, int],
                   fov_mask: np.ndarray, *, overlap: int = 2, batch: int = 32) -> torch.Tensor:
    """(H,W) costs of a large map of ``shape`` from BEV-sized windows at stride window/overlap.

    The map is thought of as reflect-padded by one window so border pixels fall inside some window's
    trapezoid too; ``window_costs(corners)`` returns the (N, window, window) costs of the padded map's
    windows with those top-left corners. Each pixel averages the windows whose field of view covers it.
    """
    window = fov_mask.shape[0]
    stride = max(1, window // overlap)
    h, w = shape
    padded = (h + 2 * window, w + 2 * window)
    weight = torch.as_tensor(fov_mask, dtype=torch.float32)
    corners = [(r, c) for r in range(0, padded[0] - window + 1, stride)
               for c in range(0, padded[1] - window + 1, stride)]
    total, hits = torch.zeros(padded), torch.zeros(padded)
    for start in range(0, len(corners), batch):
        chunk = corners[start:start + batch]
        for (r, c), cost in zip(chunk, window_costs(chunk)):
            total[r:r + window, c:c + window] += cost * weight
            hits[r:r + window, c:c + window] += weight
    inner = (slice(window, window + h), slice(window, window + w))
    return total[inner] / hits[inner].clamp_min(1e-6)


def window_cutter(image: torch.Tensor, fov_mask: np.ndarray) -> Callable[[list[tuple[int, int]]], torch.Tensor]:
    """corners -> (N, 3, window, window): the BEV-sized windows of the (3,H,W) ``image`` reflect-padded by
    one window (the padded map ``stitch_windows`` thinks of), zero outside the field of view, as in training."""
    window = fov_mask.shape[0]
    padded = F.pad(torch.as_tensor(image, dtype=torch.float32)[None], (window,) * 4, mode="reflect")[0]
    weight = torch.as_tensor(fov_mask, dtype=torch.float32)
    return lambda corners: torch.stack([padded[:, r:r + window, c:c + window] * weight for r, c in corners])


@torch.no_grad()
def costmap_over_map(model: torch.nn.Module, image: torch.Tensor, context: torch.Tensor, fov_mask: np.ndarray,
                     *, overlap: int = 2, batch: int = 32, device: str | torch.device = "cpu") -> torch.Tensor:
    """(H,W) PACER costs of a large (3,H,W) map: the network on every window (zero outside its field of
    view, as in training), stitched by :func:`stitch_windows`."""
    model.eval()
    image = torch.as_tensor(image, dtype=torch.float32)
    cut = window_cutter(image, fov_mask)
    ctx = torch.as_tensor(context, dtype=torch.float32)[None].to(device)

    def costs(corners):
        return torch.sigmoid(model(cut(corners).to(device), ctx.expand(len(corners), -1, -1, -1))).cpu()

    return stitch_windows(costs, tuple(image.shape[1:]), fov_mask, overlap=overlap, batch=batch)


def oracle_window_costs(labels: np.ndarray, fov_mask: np.ndarray, ordering: np.ndarray,
                        target: str = "in_view") -> np.ndarray:
    """The training target of one BEV window (Sec. V-A) under the environment's ``ordering``: each pixel
    costed (l-1)/(L-1) by its rank l among the terrains in the window's field of view (``target``
    in_view) or in the whole ordering (context: what the operator's context was drawn over)."""
    ordering = np.asarray(ordering, dtype=np.int64)
    if target == "in_view":
        ordering = ordering[np.isin(ordering, np.unique(labels[fov_mask]))]
    return target_costmap(np.where(fov_mask, labels, IGNORE), ordering)


def window_oracle_costmap(labels: np.ndarray, ordering: np.ndarray, fov_mask: np.ndarray, *,
                          overlap: int = 2, target: str = "in_view") -> torch.Tensor:
    """(H,W) costs of a map whose every window is costed exactly as its training target (``target``:
    ``pacer.data.train_target``), stitched like PACER's: the ceiling of the window protocol (a perfect
    PACER model scores this)."""
    window = fov_mask.shape[0]
    padded = np.pad(np.asarray(labels, dtype=np.int64), window, mode="reflect")

    def costs(corners):
        return torch.from_numpy(np.stack([oracle_window_costs(padded[r:r + window, c:c + window], fov_mask,
                                                              ordering, target) for r, c in corners]))

    return stitch_windows(costs, labels.shape, fov_mask, overlap=overlap)


def plan_on_costmap(costmap: np.ndarray, start, goal, cost_scale: float) -> GridPath:
    """Optimal 8-connected A* path where a cell costs 1 + cost_scale · costmap per metre."""
    return plan(1.0 + cost_scale * np.asarray(costmap, dtype=np.float64), start, goal)


def crossing_queries(size: int, count: int, gen: np.random.Generator) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """``count`` (start, goal) cells near opposite edges of a square map (left-right or top-bottom, either
    way), placed like the aerial maps' own query, so one map yields several crossings to score."""
    near, far = round(EDGE_MARGIN * size), size - 1 - round(EDGE_MARGIN * size)
    queries = []
    for _ in range(count):
        a, b = (int(v) for v in gen.integers(round(0.15 * size), round(0.85 * size), size=2))
        ends = [(a, near), (b, far)] if gen.uniform() < 0.5 else [(near, a), (far, b)]
        if gen.uniform() < 0.5:
            ends.reverse()
        queries.append((ends[0], ends[1]))
    return queries


def context_pair_agreement(predicted: np.ndarray, labels: np.ndarray, mask: np.ndarray,
                           pairs: np.ndarray) -> tuple[int, int]:
    """(agreeing, compared) context pairs: pair (a ≻ b) agrees when terrain a's mean predicted cost in view
    is lower than b's. Pairs whose terrains are not both in view (or a = b) are not compared."""
    predicted, labels = np.asarray(predicted), np.asarray(labels)
    mask = np.asarray(mask, dtype=bool)
    agree = compared = 0
    for a, b in np.asarray(pairs, dtype=np.int64).reshape(-1, 2):
        in_a, in_b = mask & (labels == a), mask & (labels == b)
        if a == b or not in_a.any() or not in_b.any():
            continue
        compared += 1
        agree += int(predicted[in_a].mean() < predicted[in_b].mean())
    return agree, compared
