"""navlab.pacer.recognition: the matcher's cosines are the network's own, and the recognition rate counts
what it says (hand-built cases), on real smoke maps as on synthetic arrays."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from navlab.pacer.aerial import AerialMap, aerial_maps
from navlab.pacer.model import build_model
from navlab.pacer.recognition import (
    RECOGNITION_COLUMNS,
    patch_cosines,
    recognition,
    recognition_rows,
    true_terrain_method,
)
from navlab.pacer.terrain import load_terrain_bank


@pytest.fixture(scope="module")
def model(smoke_params):
    pacer = smoke_params.pacer
    torch.manual_seed(0)
    return build_model(pacer.model, context_pairs=pacer.data.n_pairs).eval()


def test_cosines_give_back_the_network_s_preference_map(model, smoke_params):
    """S = sum_j softmax_j(T cos_j) r_j (r = -(the patch's implied place)): recomputed from ``patch_cosines`` it
    equals the matcher's own first map, so the diagnostic reads what the costmap reads."""
    n, p = smoke_params.pacer.data.n_pairs, smoke_params.pacer.data.patch_size
    gen = torch.Generator().manual_seed(3)
    image, context = torch.rand(3, 32, 32, generator=gen), torch.rand(3 * n, 2 * p, p, generator=gen)
    cos = patch_cosines(model.matcher, image, context)
    attention = torch.softmax(cos * model.matcher.log_temperature.exp(), dim=0)
    with torch.no_grad():
        roles = -model.matcher.patch_ranks(model.matcher.keys(context[None])[0])[0][:, None, None]
    with torch.no_grad():
        s = model.matcher(image[None], context[None])[0, 0]
    assert cos.shape == (2 * n, *s.shape)
    torch.testing.assert_close((attention * roles).sum(dim=0), s, rtol=1e-5, atol=1e-6)


def test_recognition_counts_named_cells_only():
    # 8 x 8 labels, 2 x 2 cells (stride 4): left column terrain 5, right column 7, one cell of terrain 3
    labels = np.full((8, 8), 5)
    labels[:, 4:] = 7
    labels[4:, 4:] = 3  # not in the context: left out of both shares
    patch_terrains = np.array([5, 7, 9, 5])
    cos = np.zeros((4, 2, 2))
    cos[0, 0, 0] = 1  # terrain 5 cell -> a patch of 5: right
    cos[2, 0, 1] = 1  # terrain 7 cell -> the patch of 9: wrong
    cos[3, 1, 0] = 1  # terrain 5 cell -> the other patch of 5: right
    cos[1, 1, 1] = 1  # terrain 3 cell: not named
    rate, baseline = recognition(cos, labels, patch_terrains)
    assert rate == pytest.approx(2 / 3)
    assert baseline == pytest.approx(2 / 3)  # named cells 5, 7, 5: the commonest covers two of three
    assert recognition(cos, np.full((8, 8), 3), patch_terrains) is None


def test_a_perfect_matcher_scores_one():
    labels = np.repeat(np.repeat(np.array([[1, 2], [2, 4]]), 4, axis=0), 4, axis=1)
    patch_terrains = np.array([1, 2, 4, 1])
    cos = (patch_terrains[:, None, None] == labels[2::4, 2::4][None]).astype(float)
    assert recognition(cos, labels, patch_terrains) == (1.0, 0.5)


def test_rows_on_smoke_maps(model, smoke_params, smoke_data):
    pacer = smoke_params.pacer
    bank = load_terrain_bank(smoke_data, pacer.data)
    maps = {env: aerial_maps(smoke_params, smoke_data, env, bank) for env in ("seen", "unseen")}
    rows = recognition_rows({"untrained": model, "no matcher": torch.nn.Identity()}, maps, bank, pacer.data,
                            pacer.seed)
    assert [r["set"] for r in rows] == ["seen maps", "unseen maps"]  # the model without a matcher has no row
    for r in rows:
        assert set(RECOGNITION_COLUMNS) <= set(r) and r["maps"] == len(maps[r["set"].split()[0]])
        assert 0 <= r["recognition"] <= 1 and 0 < r["commonest_terrain"] <= 1
        assert r["recognition_ci"][0] <= r["recognition"] <= r["recognition_ci"][1]
        assert r["above_commonest"] == pytest.approx(r["recognition"] - r["commonest_terrain"])


def test_true_terrain_costs_follow_the_matchers_own_order_inference(model, smoke_params):
    """Every pixel of a terrain costs (1 - place) / 2 of its patches (one cost per terrain, in [0, 1]); a terrain
    the context does not show costs 0.5; swapping the halves of every pair mirrors every cost about 0.5 (the
    places change sign); a model without a matcher gives a row of None."""
    n, p = smoke_params.pacer.data.n_pairs, smoke_params.pacer.data.patch_size
    context = torch.rand(3 * n, 2 * p, p, generator=torch.Generator().manual_seed(5)).numpy()
    pairs = np.array([[1, 2], [2, 3], [4, 5]])[:n]
    labels = np.repeat(np.arange(1, 7), 4).reshape(4, 6)  # terrain 6 is in no pair
    amap = AerialMap(np.zeros((3, 4, 6), np.float32), labels, np.arange(1, 7), (0, 0), (3, 5))
    method = true_terrain_method(model.matcher)
    cost = method(amap, None, context, pairs)
    swapped = np.concatenate([context[:, p:], context[:, :p]], axis=1)
    mirrored = method(amap, None, swapped, pairs[:, ::-1])
    with torch.no_grad():
        places = model.matcher.patch_ranks(model.matcher.keys(torch.as_tensor(context)[None])[0])[0].numpy()
    patch_terrains = np.concatenate([pairs[:, 0], pairs[:, 1]])
    for t in range(1, 6):
        np.testing.assert_allclose(cost[labels == t], np.mean((1 - places[patch_terrains == t]) / 2), atol=1e-6)
    np.testing.assert_allclose(cost[labels == 6], 0.5)
    np.testing.assert_allclose(mirrored, 1 - cost, atol=1e-5)
    assert true_terrain_method(None)(amap, None, context, pairs) is None
