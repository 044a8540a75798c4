"""One evaluation's frozen ImageNet features, computed once and shared by every model that reads them.

Why: Tables I-IV cost each aerial map with every PACER model (three seeds of three phases, under two
preferences): about 1,200 costmaps, each the network on the same few hundred BEV windows of its map. Each
model's texture matcher starts with the same frozen EfficientNet-Lite0 layers
(``pacer.pretrained.ImageNetFeatures``: ImageNet's weights, eval mode, never trained), so on a given window
batch they give the same features for every model; only the trained layers after them differ. Profiled,
the networks' forward passes were 87% of notebook 03's navigation rows.

``FeatureMemo`` keys a batch on its bytes (and the frozen layers' own weights), so a hit returns exactly the
tensor the layers computed for that same input: the costmaps are bit for bit those of a model without it
(tested). It holds the most recent ``max_bytes`` of features and lives as long as the run that made it.
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict

import torch
from torch import nn

from navlab.pacer.model import PacerNet
from navlab.pacer.pretrained import ImageNetFeatures


def _digest(*tensors: torch.Tensor) -> bytes:
    h = hashlib.blake2b(digest_size=20)
    for t in tensors:
        t = t.detach().contiguous().cpu()
        h.update(f"{t.dtype}{tuple(t.shape)}".encode())
        h.update(t.numpy().tobytes())
    return h.digest()


class FeatureMemo:
    """Features by (weights, input) digest, least recently used dropped beyond ``max_bytes``."""

    def __init__(self, max_bytes: int = 1 << 30):
        if max_bytes <= 0:
            raise ValueError(f"max_bytes {max_bytes}: give a positive size in bytes (e.g. 1 << 30)")
        self.max_bytes = max_bytes
        self._items: OrderedDict[bytes, torch.Tensor] = OrderedDict()
        self._bytes = 0
        self.hits = self.misses = 0

    def get(self, key: bytes, compute) -> torch.Tensor:
        if key in self._items:
            self._items.move_to_end(key)
            self.hits += 1
            return self._items[key]
        self.misses += 1
        value = compute()
        size = value.numel() * value.element_size()
        if size <= self.max_bytes:
            self._items[key] = value
            self._bytes += size
            while self._bytes > self.max_bytes:
                _, dropped = self._items.popitem(last=False)
                self._bytes -= dropped.numel() * dropped.element_size()
        return value


class MemoisedFeatures(nn.Module):
    """An ``ImageNetFeatures`` whose outputs go through a shared ``FeatureMemo`` (inference only: the layers
    are frozen and take no gradient, so nothing is lost by reusing their output)."""

    def __init__(self, inner: ImageNetFeatures, memo: FeatureMemo):
        super().__init__()
        self.inner, self.memo = inner, memo
        self._weights = _digest(*inner.state_dict().values())

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return self.memo.get(self._weights + _digest(x), lambda: self.inner(x))


def share_features(model: PacerNet, memo: FeatureMemo) -> PacerNet:
    """``model`` with its matcher's frozen ImageNet layers reading through ``memo`` (a model without them,
    such as the paper's architecture or the from-scratch matcher, is returned as it is)."""
    matcher = getattr(model, "matcher", None)
    if matcher is not None and isinstance(matcher.features, ImageNetFeatures):
        matcher.features = MemoisedFeatures(matcher.features, memo)
    return model
