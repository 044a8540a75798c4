"""Superpixel region graphs: label consistency, connectivity, projection round trip, incremental update."""

import itertools

import numpy as np
import pytest
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from navlab.core.labels import NUM_LABELS, label_id
from navlab.graphs.incremental import update_graph
from navlab.graphs.projection import path_to_regions, regions_to_waypoints, trace_cells
from navlab.graphs.region_graph import build_region_graph
from navlab.graphs.superpixels import HARD, label_consistent_slic, traversable_mask
from navlab.search.grid_astar import plan
from synthetic_city import blobs, city


def _graph(m, n=120, tau=None):
    sp = label_consistent_slic(m.labels, n, 1.0)
    return build_region_graph(sp, m.labels, m.frame, m.frame.resolution if tau is None else tau)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_every_superpixel_has_one_label_and_is_connected(seed):
    m = blobs(seed)
    sp = label_consistent_slic(m.labels, 150, 1.0)
    inside = sp != HARD
    assert np.array_equal(inside, traversable_mask(m.labels))
    ids = sp[inside]
    labels_per_id = np.unique(ids.astype(np.int64) * NUM_LABELS + m.labels[inside]) // NUM_LABELS
    assert len(labels_per_id) == len(np.unique(ids))  # one (id, label) pair per id
    for i in np.unique(ids)[:: max(1, len(np.unique(ids)) // 25)]:
        assert ndimage.label(sp == i)[1] == 1


@pytest.mark.parametrize("seed", [0, 3])
def test_graph_components_match_traversable_components(seed):
    m = blobs(seed)
    g = _graph(m)
    n = g.num_nodes
    adj = coo_matrix((np.ones(len(g.edges)), (g.edges[:, 0], g.edges[:, 1])), shape=(n, n))
    n_graph, comp = connected_components(adj, directed=False)
    regions, n_regions = ndimage.label(traversable_mask(m.labels))
    assert n_graph == n_regions
    node_region = np.zeros(n, dtype=int)
    node_region[g.node_raster[regions > 0]] = regions[regions > 0]
    # each graph component lies in exactly one traversable region, and vice versa
    pairs = np.unique(np.stack([comp, node_region], axis=1), axis=0)
    assert len(pairs) == n_graph


def test_features_centroids_and_edges_follow_eq7():
    m = city()
    g = _graph(m).with_endpoints(np.array([5.5, 50.5]), np.array([115.5, 50.5]))
    x = g.features
    assert x.shape == (g.num_nodes, NUM_LABELS + 2)
    assert np.array_equal(x[:, :NUM_LABELS].argmax(1), g.node_label)
    assert x[:, NUM_LABELS].sum() == 1 and x[g.start_node, NUM_LABELS] == 1
    assert x[:, NUM_LABELS + 1].sum() == 1 and x[g.goal_node, NUM_LABELS + 1] == 1
    i = 7
    rows, cols = np.nonzero(g.node_raster == i)
    assert np.allclose(g.centroid[i], [cols.mean() + 0.5, rows.mean() + 0.5])
    a, b = g.edges.T
    assert np.allclose(g.edge_length, np.linalg.norm(g.centroid[a] - g.centroid[b], axis=1))
    assert (g.edge_affinity >= m.frame.resolution).all()
    data = g.to_pyg()
    assert data.x.shape == (g.num_nodes, NUM_LABELS + 2) and data.edge_index.shape == (2, 2 * len(g.edges))


def test_tau_drops_short_boundaries():
    m = city()
    sp = label_consistent_slic(m.labels, 120, 1.0)
    loose, strict = (build_region_graph(sp, m.labels, m.frame, tau) for tau in (1.0, 4.0))
    assert len(strict.edges) < len(loose.edges)
    assert (strict.edge_affinity >= 4.0).all()


def test_start_in_hard_space_is_a_clear_error():
    m = city()
    g = _graph(m)
    with pytest.raises(ValueError, match="start .* hard region"):
        g.with_endpoints(np.array([20.5, 20.5]), np.array([5.5, 50.5]))


def test_path_region_round_trip():
    m = city()
    g = _graph(m)
    cost = np.where(traversable_mask(m.labels), 1.0, np.inf)
    path = m.frame.cell_to_world(plan(cost, (5, 5), (112, 110)).cells)
    seq = path_to_regions(g, path)
    assert len(seq) > 5 and np.all(seq[1:] != seq[:-1])
    neighbours = g.neighbours()
    assert all(b in neighbours[a] for a, b in itertools.pairwise(seq))  # consecutive = adjacent
    waypoints = regions_to_waypoints(g, seq)
    assert len(waypoints) == 2 * len(seq) - 1
    assert np.array_equal(g.node_at(waypoints[0::2]), seq)  # anchors lie in their own regions
    back = g.node_at(waypoints)
    assert np.array_equal(back[np.r_[True, back[1:] != back[:-1]]], seq)  # portals sit on shared boundaries


def test_trace_cells_is_4_connected_and_hard_paths_are_refused():
    m = city()
    cells = trace_cells(np.array([[0.5, 0.5], [30.2, 17.9]]), m.frame)
    assert (np.abs(np.diff(cells, axis=0)).sum(axis=1) == 1).all()
    with pytest.raises(ValueError, match="hard region"):
        path_to_regions(_graph(m), np.array([[5.5, 5.5], [25.5, 25.5]]))


def test_incremental_update_keeps_untouched_regions():
    m = city()
    g = _graph(m)
    new = m.labels.copy()
    changed = np.zeros(new.shape, dtype=bool)
    changed[40:52, 44:56] = True
    new[changed] = label_id("building")
    new[45:48, 44:56] = label_id("grass")
    g2 = update_graph(g, new, changed, compactness=1.0, tau=1.0)
    touched = np.unique(g.superpixels[changed & (g.superpixels != HARD)])
    kept = np.setdiff1d(g.region_ids, touched)
    assert len(kept) > 0.8 * g.num_nodes
    outside = ~np.isin(g.superpixels, touched) & ~changed
    assert np.array_equal(g2.superpixels[outside], g.superpixels[outside])  # ids and cells unchanged
    i_old, i_new = np.searchsorted(g.region_ids, kept), np.searchsorted(g2.region_ids, kept)
    assert np.array_equal(g2.region_ids[i_new], kept)
    assert np.allclose(g2.centroid[i_new], g.centroid[i_old]) and np.array_equal(g2.node_label[i_new], g.node_label[i_old])
    # the re-segmented part is label consistent, new ids are fresh, hard cells belong to no node
    fresh = g2.superpixels[np.isin(g.superpixels, touched) & (g2.superpixels != HARD)]
    assert fresh.size and (np.unique(fresh) > g.region_ids.max()).all()
    assert (g2.superpixels[new == label_id("building")] == HARD).all()
    ids = g2.superpixels[g2.superpixels != HARD]
    labs = new[g2.superpixels != HARD]
    assert len(np.unique(ids.astype(np.int64) * NUM_LABELS + labs)) == g2.num_nodes
    # and it equals a from-scratch graph on the same raster
    rebuilt = build_region_graph(g2.superpixels, new, m.frame, 1.0)
    assert np.array_equal(rebuilt.edges, g2.edges)
