"""The relaxation-cost estimator Psi_G (SuReNav Sec. IV-C.2): GatedGCN, GPS stack, masking, equivariance."""

import numpy as np
import pytest
import torch
from torch_geometric.data import Batch, Data

from navlab.core.labels import NUM_LABELS, SOFT_IDS
from navlab.core.params import load_params
from navlab.surenav.model.estimator import build_estimator
from navlab.surenav.model.gated_gcn import GatedGCN
from navlab.surenav.model.inputs import random_walk_encoding


def random_graph(n: int, seed: int, walk_steps: int) -> Data:
    """A random planar-ish graph (k nearest neighbours of random points) with Eq. 7 features + RWSE."""
    gen = np.random.default_rng(seed)
    pts = gen.uniform(0, 100, size=(n, 2))
    d = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    near = np.argsort(d, axis=1)[:, 1:4]
    edges = np.unique(np.sort(np.stack([np.repeat(np.arange(n), 3), near.ravel()], axis=1), axis=1), axis=0)
    labels = gen.integers(0, 7, size=n)  # free + soft labels only (graph nodes are never hard)
    x = np.zeros((n, NUM_LABELS + 2), np.float32)
    x[np.arange(n), labels] = 1
    x[0, NUM_LABELS] = x[n - 1, NUM_LABELS + 1] = 1
    pe = random_walk_encoding(edges, n, walk_steps)
    both = np.concatenate([edges, edges[:, ::-1]]).T
    length = np.linalg.norm(pts[both[0]] - pts[both[1]], axis=1).astype(np.float32)
    return Data(x=torch.from_numpy(np.concatenate([x, pe], 1)), edge_index=torch.from_numpy(both.copy()),
                edge_attr=torch.from_numpy(length[:, None]), soft=torch.from_numpy(np.isin(labels, SOFT_IDS)),
                num_nodes=n)


def permuted(data: Data, perm: np.ndarray) -> Data:
    """The same graph with node i renamed inv[i] (node perm[k] becomes node k); edge order shuffled too."""
    inv = np.argsort(perm)
    p = torch.from_numpy(perm)
    eperm = torch.from_numpy(np.random.default_rng(1).permutation(data.edge_index.size(1)))
    return Data(x=data.x[p], edge_index=torch.from_numpy(inv)[data.edge_index][:, eperm],
                edge_attr=data.edge_attr[eperm], soft=data.soft[p], num_nodes=data.num_nodes)


@pytest.fixture(scope="module")
def model_params():
    return load_params("smoke").surenav.model


@pytest.mark.parametrize("attention", [True, False])
def test_zero_on_free_nodes_positive_on_soft_ones(model_params, attention):
    torch.manual_seed(0)
    net = build_estimator(model_params, attention).eval()
    data = random_graph(60, 0, model_params.walk_steps)
    with torch.no_grad():
        psi = net(Batch.from_data_list([data, random_graph(40, 1, model_params.walk_steps)]))
    soft = torch.cat([data.soft, random_graph(40, 1, model_params.walk_steps).soft])
    assert soft.any() and (~soft).any()
    assert torch.all(psi[~soft] == 0)
    assert torch.all(psi[soft] > 0)


@pytest.mark.parametrize("attention", [True, False])
@pytest.mark.parametrize("train_mode", [False, True])
def test_permuting_the_graph_permutes_the_costs(model_params, attention, train_mode):
    torch.manual_seed(0)
    net = build_estimator(model_params, attention).train(train_mode)
    data = random_graph(50, 2, model_params.walk_steps)
    perm = np.random.default_rng(3).permutation(50)
    with torch.no_grad():
        a = net(Batch.from_data_list([data]))
        b = net(Batch.from_data_list([permuted(data, perm)]))
    assert not torch.allclose(a[data.soft], a[data.soft].mean().expand(int(data.soft.sum())))  # not constant
    torch.testing.assert_close(b, a[torch.from_numpy(perm)], rtol=1e-4, atol=1e-5)


def test_random_walk_encoding_matches_dense_matrix_powers():
    edges = np.array([[0, 1], [1, 2], [2, 0], [2, 3]])
    adj = np.zeros((4, 4))
    adj[edges[:, 0], edges[:, 1]] = adj[edges[:, 1], edges[:, 0]] = 1
    walk = adj / adj.sum(1, keepdims=True)
    want = np.stack([np.diag(np.linalg.matrix_power(walk, k)) for k in range(1, 6)], axis=1)
    np.testing.assert_allclose(random_walk_encoding(edges, 4, 5), want, rtol=1e-6)
    assert want[3, 0] == 0 and want[3, 1] == pytest.approx(1 / 3)  # leaf: back in two steps through node 2


def test_gated_gcn_equals_the_bresson_laurent_formula():
    """x'_i = x_i + ReLU(BN(A x_i + sum_j s_ij B x_j / (sum_j s_ij + eps))), s_ij = sigmoid(D x_i + E x_j + C e_ij),
    e'_ij = e_ij + ReLU(BN(D x_i + E x_j + C e_ij)), written out with dense loops (eval-mode BatchNorm)."""
    torch.manual_seed(0)
    layer = GatedGCN(6).eval()
    for bn in (layer.bn_node, layer.bn_edge):
        bn.running_mean.uniform_(-0.5, 0.5)
        bn.running_var.uniform_(0.5, 2.0)
    x, e = torch.randn(5, 6), torch.randn(7, 6)
    ei = torch.tensor([[0, 1, 2, 3, 4, 0, 2], [1, 0, 1, 2, 3, 3, 4]])  # src -> dst
    with torch.no_grad():
        out, e_out = layer(x, ei, e), layer.edge_out
        bn = lambda m, v: (v - m.running_mean) / torch.sqrt(m.running_var + m.eps) * m.weight + m.bias
        want_e = torch.empty_like(e)
        want = torch.empty_like(x)
        for i in range(5):
            num, den = torch.zeros(6), torch.zeros(6)
            for k in range(ei.size(1)):
                j, d = int(ei[0, k]), int(ei[1, k])
                if d != i:
                    continue
                logit = layer.D(x[i]) + layer.E(x[j]) + layer.C(e[k])
                want_e[k] = e[k] + torch.relu(bn(layer.bn_edge, logit))
                num += torch.sigmoid(logit) * layer.B(x[j])
                den += torch.sigmoid(logit)
            want[i] = x[i] + torch.relu(bn(layer.bn_node, layer.A(x[i]) + num / (den + 1e-6)))
    torch.testing.assert_close(out, want, rtol=1e-5, atol=1e-6)
    torch.testing.assert_close(e_out, want_e, rtol=1e-5, atol=1e-6)


def test_bad_feature_width_is_one_clear_error(model_params):
    net = build_estimator(model_params)
    data = random_graph(10, 0, model_params.walk_steps + 1)
    with pytest.raises(ValueError, match="walk_steps"):
        net(Batch.from_data_list([data]))
