"""Region-adjacency graph construction: navlab (np.unique on shifted label pairs) against scikit-image's RAG.

Both build the 4-connected adjacency of the same label-consistent SLIC superpixels of a random blob
map; the script checks they find the same edges and prints times and the ratio.
Usage: python benchmarks/region_graph.py [--size 500] [--nodes 1500] [--repeats 3]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import ndimage
from skimage.graph import RAG

from navlab.core.grid import RasterFrame
from navlab.core.labels import NUM_LABELS
from navlab.core.seeding import rng
from navlab.graphs.region_graph import build_region_graph
from navlab.graphs.superpixels import label_consistent_slic


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=500)
    parser.add_argument("--nodes", type=int, default=1500)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    fields = ndimage.gaussian_filter(rng(0, "benchmark", "region_graph").standard_normal(
        (NUM_LABELS, args.size, args.size)), sigma=(0, 8, 8))
    labels = np.argmax(fields, axis=0).astype(np.uint8)
    frame = RasterFrame(labels.shape, 1.0)
    superpixels = label_consistent_slic(labels, args.nodes, 1.0)
    t_ours = t_ref = 0.0
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        graph = build_region_graph(superpixels, labels, frame, tau=0.0)
        t1 = time.perf_counter()
        reference = RAG(superpixels + 1, connectivity=1)  # its label 0 is background-like; shift ids
        t2 = time.perf_counter()
        t_ours, t_ref = t_ours + t1 - t0, t_ref + t2 - t1
    ref_edges = {(min(a, b) - 1, max(a, b) - 1) for a, b in reference.edges() if a > 0 and b > 0}
    ours = {tuple(int(v) for v in graph.region_ids[e]) for e in graph.edges}
    assert ours == ref_edges, f"edge sets differ: {len(ours ^ ref_edges)} edges"
    print(f"{graph.num_nodes} nodes, {len(ours)} edges on a {args.size}^2 map; same edges as skimage RAG")
    print(f"navlab build_region_graph {t_ours / args.repeats:.3f} s (with centroids, portals), "
          f"skimage RAG {t_ref / args.repeats:.3f} s (adjacency only); ratio ours/reference "
          f"{t_ours / t_ref:.3f}")


if __name__ == "__main__":
    main()
