"""`params check` for SuReNav: the relaxation-cost estimator (GPS and its MPNN-only ablation) at
the profile's size on a three-node region graph.

Each ``*_problems(params, notes)`` returns one line per problem, naming the params key, and may append what it
measured to ``notes``; the manifest (``track.py``) lists them, ``navlab.pipeline.profile_check`` runs them on
every profile.
"""

from __future__ import annotations

import numpy as np

from navlab.core.params import Params


def model_problems(params: Params, notes: list[str]) -> list[str]:
    """The SuReNav estimator (GPS and the MPNN-only ablation) at the profile's size, on the input
    estimator_input builds from a three-node region graph: its own checks, Psi per node, its size.
    On the CPU, not ``meta``: the attention path calls torch.nonzero, which needs real values; three nodes
    take milliseconds."""
    import torch

    from navlab.surenav.model.estimator import RelaxationCostEstimator
    from navlab.surenav.model.inputs import estimator_input

    m, counts = params.surenav.model, []
    data = estimator_input(_three_node_graph(), walk_steps=m.walk_steps)
    for attention in (True, False):
        try:
            model = RelaxationCostEstimator(m, attention=attention).eval()
            with torch.no_grad():
                psi = model(data)
        except (RuntimeError, ValueError) as err:
            line = str(err).splitlines()[0]
            return [line if line.startswith("surenav.") else f"surenav.model: {line}"]
        if psi.shape != (data.num_nodes,):
            return [f"surenav.model: Psi of shape {tuple(psi.shape)} for {data.num_nodes} nodes; expected one per node"]
        counts.append(sum(p.numel() for p in model.parameters()))
    notes.append(f"surenav estimator {counts[0]:,} parameters (MPNN-only ablation {counts[1]:,}), "
                 f"batch {params.surenav.train.batch_size} on {params.surenav.train.device}")
    return []


def _three_node_graph():
    """A free node between two soft ones, start and goal at the ends: the smallest graph with both kinds."""
    from navlab.core.grid import RasterFrame
    from navlab.core.labels import FREE_IDS, SOFT_IDS
    from navlab.graphs.region_graph import RegionGraph

    xy = np.array([[0.5, 0.5], [1.5, 0.5], [2.5, 0.5]])
    edges = np.array([[0, 1], [1, 2]])
    return RegionGraph(superpixels=np.arange(3, dtype=np.int32)[None], frame=RasterFrame((1, 3), 1.0),
                       region_ids=np.arange(3), node_label=np.array([SOFT_IDS[0], FREE_IDS[0], SOFT_IDS[0]]),
                       centroid=xy, anchor=xy, area=np.ones(3), edges=edges, edge_length=np.ones(2),
                       edge_affinity=np.ones(2), portal=np.array([[1.0, 0.5], [2.0, 0.5]]), start_node=0, goal_node=2)
