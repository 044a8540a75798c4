"""The differentiable graph A* as a plain step-by-step autograd loop (the reference for ``diff_astar``).

Neural A* (Yonetani et al., ICML 2021) on the padded neighbour table, with SuReNav's Eq. (9)-(11):
every step, for all graphs at once, f = (g + Psi) + h over the open set, a masked log-softmax of
-f / tau, the straight-through one-hot of its arg-max added to the closed set, then the selected
node's neighbours relaxed with g' = g_ext + d (Eq. 11). g, the open set and the parents are detached,
as in Neural A*. Autograd records every step, so memory and time grow with B x N x steps; it exists
so that the tests can hold ``diff_astar``'s recorded-trace backward to it (same closed sets, same
gradients).
"""

from __future__ import annotations

import numpy as np
import torch

from navlab.search.diff_astar import DiffAStarResult, GraphBatch, check_psi
from navlab.search.graph_astar import backtrack


def diff_astar_reference(batch: GraphBatch, psi: torch.Tensor, *, temperature: float) -> DiffAStarResult:
    """Same contract as ``diff_astar.diff_astar``."""
    check_psi(batch, psi, temperature)
    b, n = batch.shape
    rows = torch.arange(b, device=psi.device)
    inf = torch.tensor(torch.inf, dtype=psi.dtype, device=psi.device)
    g = torch.full((b, n), torch.inf, dtype=psi.dtype, device=psi.device)
    g[rows, batch.start] = 0.0
    is_open = torch.zeros((b, n), dtype=torch.bool, device=psi.device)
    is_open[rows, batch.start] = True
    is_closed = torch.zeros_like(is_open)
    parent = torch.full((b, n), -1, dtype=torch.int64, device=psi.device)
    searching = torch.ones(b, dtype=torch.bool, device=psi.device)
    closed = torch.zeros_like(psi)
    h = batch.heuristic.to(psi.dtype)
    psi_const = psi.detach()
    while bool(searching.any()):
        searching = searching & is_open.any(dim=1)  # an exhausted open set: the goal is unreachable
        open_now = is_open.clone()  # the masks below are saved for backward; is_open changes in place
        f = (g + psi) + h
        select = torch.where(open_now, f.detach(), inf).argmin(dim=1)  # ties to the lower index, as graph_astar
        logits = torch.where(open_now, -f / temperature, -inf)
        logits = torch.where(searching[:, None], logits, torch.zeros_like(logits))  # no NaN on finished rows
        y = torch.softmax(logits, dim=1)
        hard = torch.nn.functional.one_hot(select, n).to(psi.dtype)
        closed = closed + torch.where(searching[:, None], hard + (y - y.detach()), torch.zeros_like(y))
        live = rows[searching]
        sel = select[searching]
        is_open[live, sel] = False
        is_closed[live, sel] = True
        expand = searching & (select != batch.goal)
        searching = expand
        live, sel = rows[expand], select[expand]
        nbr = batch.neighbours[live, sel]  # (L, K)
        g_new = (g[live, sel] + psi_const[live, sel])[:, None] + batch.edge_length[live, sel].to(psi.dtype)
        nbr0 = nbr.clamp(min=0)
        gr = live[:, None].expand_as(nbr)
        better = (nbr >= 0) & batch.enterable[gr, nbr0] & ~is_closed[gr, nbr0] & \
            (~is_open[gr, nbr0] | (g_new < g[gr, nbr0]))
        gr, nb = gr[better], nbr0[better]
        g[gr, nb] = g_new[better]
        parent[gr, nb] = sel[:, None].expand_as(nbr)[better]
        is_open[gr, nb] = True
    parent_np = parent.cpu().numpy()
    goal_closed = is_closed[rows, batch.goal].cpu().numpy()
    path_hard = torch.zeros_like(psi)
    path_length = np.full(b, np.inf)
    paths = []
    for i, sg in enumerate(batch.graphs):
        if not goal_closed[i]:
            paths.append(None)
            continue
        nodes = backtrack(parent_np[i], batch.starts[i], batch.goals[i])
        path_hard[i, torch.from_numpy(nodes).to(psi.device)] = 1.0
        path_length[i] = np.linalg.norm(np.diff(sg.centroid[nodes], axis=0), axis=1).sum()
        paths.append(nodes)
    cost = torch.from_numpy(path_length).to(psi) + (path_hard * psi).sum(1)
    return DiffAStarResult(closed=closed, path=closed * path_hard, cost=cost, paths=tuple(paths),
                           solved=torch.from_numpy(goal_closed).to(psi.device))
