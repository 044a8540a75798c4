"""Differentiable graph A*, forward + backward: navlab's sparse trace backward vs a GraphMP-style dense loop.

Both run the same batched search (Neural A* selection with SuReNav's entry cost Psi, Eq. 9-11) on the
same real superpixel graphs of the default dataset (``data/``: one train map per graph, the map's
first static demonstration as the query, Psi random on soft nodes and 0 on free ones), and back-
propagate the same closed-set loss. The reference is the loop GraphMP writes: every step a masked
softmax over all N nodes and a dense (B, N, N) x (B, N) product W v_sel for the neighbours and their
costs (Eq. 2-3), autograd recording every step. The script checks the two give the same closed sets
and gradients and prints the times and the ratio.
Usage: python benchmarks/diff_astar.py [--data data] [--graphs 16] [--nodes 1000 3000] [--repeats 3] [--threads 1]
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np
import torch

from navlab.core.grid import RasterFrame
from navlab.core.labels import SOFT_IDS
from navlab.core.params import load_params
from navlab.core.seeding import rng
from navlab.graphs.region_graph import RegionGraph, superpixel_graph
from navlab.maps.dataset import load_maps
from navlab.maps.semantic_map import SemanticMap
from navlab.search.diff_astar import GraphBatch, batch_graphs, diff_astar
from navlab.surenav.experts.store import load_demos


def window_graph(m: SemanticMap, centre: np.ndarray, side: int, target: float, settings) -> RegionGraph:
    """The superpixel graph of a ``side``-cell square window of the map around ``centre`` (world x, y)."""
    rows, cols = m.labels.shape
    side = min(side, rows, cols)
    rc = m.frame.world_to_cell(centre)
    r0, c0 = (int(np.clip(v - side // 2, 0, size - side)) for v, size in zip(rc, (rows, cols), strict=True))
    frame = RasterFrame((side, side), m.frame.resolution, (m.frame.origin[0] + c0 * m.frame.resolution,
                                                           m.frame.origin[1] + r0 * m.frame.resolution))
    return superpixel_graph(m.labels[r0:r0 + side, c0:c0 + side], frame,
                            dataclasses.replace(settings, target_nodes=max(1, round(target))))


def real_graphs(data: str, count: int, nodes: int) -> list[RegionGraph]:
    """``count`` train maps' superpixel graphs of about ``nodes`` nodes, endpoints from a demonstration.

    Label-consistent SLIC also splits superpixels at label edges, so a whole 500 m tile has 600-1,300
    nodes at any target. Each graph is therefore cut from a window around the map's first static
    demonstration: the window shrinks (or, at the whole tile or at the smallest window that still holds
    both endpoints, the SLIC target changes) until the graph has ``nodes`` nodes within 10%."""
    settings = load_params("default").surenav.graph
    maps, demos = load_maps(data, "train")[:count], load_demos(data, "train")[:count]
    if len(maps) < count:
        raise SystemExit(f"{data} holds {len(maps)} train maps, {count} asked; build the default dataset "
                         "(`python -m navlab data build`) or pass --graphs")
    out = []
    for m, md in zip(maps, demos, strict=True):
        demo = md.static[0]
        centre, full = (demo.start + demo.goal) / 2, min(m.labels.shape)
        least = min(full, int(np.ceil(np.abs(demo.goal - demo.start).max() / m.frame.resolution)) + 8)
        side, target = full, nodes / 2
        for _ in range(6):
            graph = window_graph(m, centre, side, target, settings)
            ratio = nodes / graph.num_nodes
            if abs(ratio - 1) < 0.1:
                break
            if least <= side * np.sqrt(ratio) <= full:
                side = int(side * np.sqrt(ratio))
            else:
                side, target = (full if ratio > 1 else least), target * ratio
        out.append(graph.with_endpoints(demo.start, demo.goal))
    return out


def graphmp_dense_closed_set(batch: GraphBatch, psi: torch.Tensor, temperature: float) -> torch.Tensor:
    """GraphMP's loop: dense W (B, N, N), one N x N product per step; g, open set, parents detached."""
    b, n = batch.shape
    rows = torch.arange(b)
    weight = torch.zeros(b, n, n, dtype=psi.dtype)  # W[b, j, i]: length of edge i -> j, 0 if not adjacent
    valid = batch.neighbours >= 0
    tail = torch.arange(n)[None, :, None].expand_as(batch.neighbours)
    bidx = rows[:, None, None].expand_as(batch.neighbours)
    weight[bidx[valid], batch.neighbours[valid], tail[valid]] = batch.edge_length[valid].to(psi.dtype)
    h = batch.heuristic.to(psi.dtype)
    inf = torch.tensor(torch.inf, dtype=psi.dtype)
    g = torch.full((b, n), torch.inf, dtype=psi.dtype)
    g[rows, batch.start] = 0.0
    is_open = torch.zeros(b, n, dtype=torch.bool)
    is_open[rows, batch.start] = True
    is_closed = torch.zeros_like(is_open)
    searching = torch.ones(b, dtype=torch.bool)
    closed = torch.zeros_like(psi)
    while bool(searching.any()):
        searching = searching & is_open.any(1)
        f = (g + psi) + h
        select = torch.where(is_open, f.detach(), inf).argmin(1)
        logits = torch.where(searching[:, None], torch.where(is_open, -f / temperature, -inf), 0.0)
        y = torch.softmax(logits, 1)
        v_sel = torch.nn.functional.one_hot(select, n).to(psi.dtype) * searching[:, None]
        closed = closed + v_sel + (y - y.detach()) * searching[:, None]
        is_open = is_open & (v_sel == 0)
        is_closed = is_closed | (v_sel > 0)
        searching = searching & (select != batch.goal)
        v_sel = v_sel * searching[:, None]
        w_v = torch.bmm(weight, v_sel[:, :, None])[:, :, 0]  # Eq. (2)-(3): the dense product
        g_new = ((g + psi.detach())[rows, select])[:, None] + w_v  # Eq. (11)
        better = (w_v > 0) & batch.enterable & ~is_closed & (~is_open | (g_new < g))
        g = torch.where(better, g_new, g)
        is_open = is_open | better
    return closed


def timed(fn, repeats):
    best, out = np.inf, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default="data")
    parser.add_argument("--graphs", type=int, default=16)
    parser.add_argument("--nodes", type=int, nargs="+", default=[1000, 3000])
    parser.add_argument("--temperature", type=float, default=1.0)
    parser.add_argument("--psi-max", type=float, default=30.0, help="Psi ~ U(0, psi-max) on soft nodes")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1, help="torch CPU threads (both methods)")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    print(f"torch {torch.__version__}, {torch.get_num_threads()} thread(s), CPU, float32")
    for nodes in args.nodes:
        graphs = real_graphs(args.data, args.graphs, nodes)
        sizes = np.array([g.num_nodes for g in graphs])
        batch = batch_graphs(graphs, dtype=torch.float32)
        gen = rng(0, "benchmark", "diff_astar", nodes)
        soft = np.zeros(batch.shape, dtype=bool)
        for i, g in enumerate(graphs):
            soft[i, :g.num_nodes] = np.isin(g.node_label, SOFT_IDS)
        psi = torch.tensor(gen.uniform(0.0, args.psi_max, batch.shape) * soft, dtype=torch.float32)
        v = torch.tensor(gen.normal(size=batch.shape), dtype=torch.float32)  # dL/dc of a closed-set loss

        def ours(batch=batch, psi=psi, v=v):
            p = psi.clone().requires_grad_(True)
            closed = diff_astar(batch, p, temperature=args.temperature).closed
            return closed.detach(), torch.autograd.grad((closed * v).sum(), p)[0]

        def reference(batch=batch, psi=psi, v=v):
            p = psi.clone().requires_grad_(True)
            closed = graphmp_dense_closed_set(batch, p, args.temperature)
            return closed.detach(), torch.autograd.grad((closed * v).sum(), p)[0]

        ours()  # compiles the search's kernels: the timing is of the search, not of numba
        t_ours, (c_ours, g_ours) = timed(ours, args.repeats)
        t_ref, (c_ref, g_ref) = timed(reference, max(1, args.repeats // 3))
        same_closed = torch.equal(c_ours, c_ref)
        scale = float(g_ref.abs().max())
        grad_err = float((g_ours - g_ref).abs().max()) / scale
        print(f"{args.graphs} graphs, {sizes.min()}-{sizes.max()} nodes (mean {sizes.mean():.0f}), padded N = "
              f"{batch.shape[1]}, K = {batch.neighbours.shape[2]}; expansions per graph {int(c_ours.sum(1).min())}-"
              f"{int(c_ours.sum(1).max())}")
        print(f"  closed sets equal: {same_closed}; gradients max |diff| / max |grad| = {grad_err:.1e}")
        print(f"  forward+backward: navlab diff_astar {t_ours * 1e3:.1f} ms, GraphMP-style dense loop "
              f"{t_ref * 1e3:.1f} ms, ratio reference/ours {t_ref / t_ours:.1f}x")
        assert same_closed and grad_err < 1e-4, "navlab and the dense reference disagree"


if __name__ == "__main__":
    main()
