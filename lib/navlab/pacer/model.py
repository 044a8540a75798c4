"""The PACER costmap network R̂(I, Ĥ) (Mao et al., RA-L 2025, Sec. IV-B).

Two encoders and one decoder: a U-Net encoder F_BEV over the bird's-eye image, a preference-context
encoder F_pref over the (n·c)×2h×w context tensor, and a U-Net decoder D that turns the fused
bottleneck into one cost logit per pixel (sigmoid → cost in [0, 1]).

Two fusions, chosen in params.yaml (`pacer.model.fusion`):

- ``concat_mlp`` is the released code's: average-pool the bottleneck, concatenate the context
  embedding, two linear layers, broadcast back over the bottleneck grid. With ``context_encoder:
  resnet50`` and the paper's widths this is the ~573M-parameter network (``paper`` profile).
- ``film`` (feature-wise linear modulation, Perez et al., AAAI 2018) scales and shifts the bottleneck
  and every decoder stage by the context embedding; it keeps the bottleneck's spatial layout, which is
  what lets a small CPU-sized model (``default``) tie costs to where each terrain is.

FiLM alone must *bind* the context to the image indirectly: the context encoder has to learn which
terrain each patch shows and turn that into channel gains that happen to address the image encoder's
channels for the same terrain, a binding learned terrain by terrain (it does not carry over to terrains
never trained on, and the small models learn it only slowly). With ``match_channels`` set (the small
profiles), a :class:`TextureMatcher` adds the binding explicitly: one texture tower, shared by the image
and the context patches, compares every image location with every context patch, and the decoder
receives, per location, how strongly it resembles the *preferred* patches versus the *other* ones. This
is a function of the context by construction (swapping the halves of every pair flips its sign) and of
appearance only, so it holds for any terrain the texture features tell apart. ``paper`` keeps the
released code's concat-MLP fusion without it.
"""

from __future__ import annotations

import itertools
import math

import torch
from torch import nn
from torch.nn import functional as F

from navlab.core.params.pacer import PacerModelParams
from navlab.pacer.pretrained import ImageNetFeatures


def conv_block(c_in: int, c_out: int) -> nn.Sequential:
    """Two 3×3 convolutions, each with batch norm and ReLU (the U-Net unit)."""
    return nn.Sequential(
        nn.Conv2d(c_in, c_out, 3, padding=1), nn.BatchNorm2d(c_out), nn.ReLU(inplace=True),
        nn.Conv2d(c_out, c_out, 3, padding=1), nn.BatchNorm2d(c_out), nn.ReLU(inplace=True),
    )


class ContextCNN(nn.Module):
    """F_pref for small models: one conv tower (conv blocks with pooling, global average) applied to the
    preferred half and to the other half of the context, the two features concatenated, one linear layer.

    Why two halves: a global average over the whole stacked (2h, w) context is nearly blind to *which*
    patch of a pair is on top (convolutions are translation-equivariant; only padding and the seam tell
    the halves apart), so a context and its inversion embed almost alike and the network falls back on
    the ordering it saw most (phase 1's realistic one). Pooling each half separately makes "preferred"
    and "other" distinct inputs of the head by construction.
    """

    def __init__(self, c_in: int, channels: tuple[int, ...], dim: int):
        super().__init__()
        layers, c = [], c_in
        for width in channels:
            layers += [conv_block(c, width), nn.MaxPool2d(2)]
            c = width
        self.features = nn.Sequential(*layers)
        self.head = nn.Linear(2 * c, dim)

    def forward(self, context: torch.Tensor) -> torch.Tensor:
        h = context.shape[2] // 2
        halves = torch.cat([context[:, :, :h], context[:, :, h:]])  # (2B, 3n, h, w): preferred, then other
        pooled = self.features(halves).mean(dim=(2, 3))
        return self.head(torch.cat(pooled.chunk(2), dim=1))


class Bottleneck(nn.Module):
    """ResNet bottleneck block (1×1, 3×3, 1×1 with expansion 4) of He et al., CVPR 2016."""

    def __init__(self, c_in: int, width: int, stride: int):
        super().__init__()
        c_out = 4 * width
        self.body = nn.Sequential(
            nn.Conv2d(c_in, width, 1, bias=False), nn.BatchNorm2d(width), nn.ReLU(inplace=True),
            nn.Conv2d(width, width, 3, stride=stride, padding=1, bias=False), nn.BatchNorm2d(width),
            nn.ReLU(inplace=True), nn.Conv2d(width, c_out, 1, bias=False), nn.BatchNorm2d(c_out),
        )
        self.shortcut = nn.Identity() if stride == 1 and c_in == c_out else nn.Sequential(
            nn.Conv2d(c_in, c_out, 1, stride=stride, bias=False), nn.BatchNorm2d(c_out))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return F.relu(self.body(x) + self.shortcut(x))


class ContextResNet50(nn.Module):
    """F_pref of the released code: ResNet-50 with a 3×3 stride-1 stem and no max-pool (small patches)."""

    def __init__(self, c_in: int, dim: int):
        super().__init__()
        layers = [nn.Conv2d(c_in, 64, 3, padding=1, bias=False), nn.BatchNorm2d(64), nn.ReLU(inplace=True)]
        c = 64
        for width, blocks, stride in ((64, 3, 1), (128, 4, 2), (256, 6, 2), (512, 3, 2)):
            for i in range(blocks):
                layers.append(Bottleneck(c, width, stride if i == 0 else 1))
                c = 4 * width
        self.features = nn.Sequential(*layers)
        self.head = nn.Identity() if dim == c else nn.Linear(c, dim)

    def forward(self, context: torch.Tensor) -> torch.Tensor:
        return self.head(self.features(context).mean(dim=(2, 3)))


class FiLM(nn.Module):
    """x ↦ (1 + γ(z)) · x + β(z): the context embedding z scales and shifts each channel."""

    def __init__(self, dim: int, channels: int):
        super().__init__()
        self.affine = nn.Linear(dim, 2 * channels)
        nn.init.zeros_(self.affine.weight)
        nn.init.zeros_(self.affine.bias)

    def forward(self, x: torch.Tensor, z: torch.Tensor) -> torch.Tensor:
        gamma, beta = self.affine(z)[:, :, None, None].chunk(2, dim=1)
        return (1 + gamma) * x + beta


class TextureMatcher(nn.Module):
    """Per-location preference evidence from appearance: (image, context) → (B, 2, H/s, W/s) maps.

    One tower of 3×3 convolutions (ReLU, no batch norm so that images and patches are featured alike in
    training and evaluation) maps the image to features and each context patch to the mean of its
    features. ``dilated`` (the small profiles): stage k's convolutions are dilated 2^k and nothing is
    pooled, so features stay at stride s = 1 with a receptive field of 1 + 4·(2^K - 1) px; a sidewalk or
    strip 1-3 px wide keeps features of its own (with a 2×2 pool per stage, stride ``s = 2 ** len(channels)``
    and a 3×3 local mean, a strip's features were mostly its neighbours': on the evaluation maps, whose
    pixels lie within 4 px of another terrain for about half of them, the nearest patch was right for 0.63 of
    those against 0.94 inside regions; benchmarks/pacer_texture_towers.py). Both are projected, centred on
    the mean of the context's 2n patch features (what the context's terrains share says nothing about which
    one a location is: uncentred ReLU features all point one way, cosines near 1 whatever the terrain) and
    L2-normalised. With ``luminance`` a second tower of the same shape sees the image and patches in grey (their
    channel mean), its features concatenated to the colour tower's: the colour tower separates terrains of
    different colour, the grey one terrains that share a colour and differ in texture, which a tower that sees
    colour never learns to (benchmarks/README.md, "a tower blind to colour").
    Every location attends over the 2n patches by cosine similarity (softmax with a learned
    temperature); the maps are

    * ``S = Σ_j a_j r_j``, r_j = -(the place patch j's terrain holds in the order the context's pairs
      imply, :meth:`patch_ranks`): -1 where the location looks like the context's most preferred terrain,
      +1 where it looks like its least preferred one, between for a terrain ranked between (with pairs over
      six distinct terrains, r = -1 for a preferred patch and +1 for the other one);
    * ``M = max_j cos``: how well the location matches any context patch at all.

    Both are invariant to the order of the pairs and S changes sign when every pair is swapped.
    """

    def __init__(self, channels: tuple[int, ...], colour_channels: int = 3, dilated: bool = False,
                 luminance: bool = False, features: str = "scratch"):
        super().__init__()
        if features not in ("scratch", "imagenet"):
            raise ValueError(f"pacer.model.match_features = {features!r}: allowed values are imagenet, scratch")
        self.imagenet = features == "imagenet"
        if self.imagenet and colour_channels != 3:
            raise ValueError(f"ImageNet features take RGB images, not {colour_channels} channels; use "
                             "pacer.model.match_features: scratch")
        if self.imagenet:
            self.features = ImageNetFeatures()
            width = ImageNetFeatures.channels
            self.project = nn.Conv2d(width, width, 1)
            with torch.no_grad():  # identity at the start: the untrained matcher compares ImageNet's features
                self.project.weight.copy_(torch.eye(width)[:, :, None, None])
                self.project.bias.zero_()
            dilated, luminance = False, False  # stride 4; the 3 x 3 local mean of ``cosines`` as a pooled tower's
        else:
            self.features = self._tower(channels, colour_channels, dilated)
            self.project = nn.Conv2d(channels[-1], channels[-1], 1)
        # a second tower fed the image in grey: trained where colour separates nearly every terrain, a colour
        # tower never learns the texture statistics that tell same-coloured terrains apart, a colour-blind one
        # must (benchmarks/README.md, "a tower blind to colour")
        self.grey_features = self._tower(channels, 1, dilated) if luminance else None
        self.grey_project = nn.Conv2d(channels[-1], channels[-1], 1) if luminance else None
        self.dilated = dilated
        self.log_temperature = nn.Parameter(torch.tensor(2.3))  # e^2.3 ≈ 10: cosines 0.1 apart → e:1 weights
        # two patches show the same terrain with weight sigmoid(e^k (cos - c)); c = 0.7, e^k = 10 at the start:
        # a trained matcher's same-terrain patch pairs sit at cosine 0.93 (median), others below 0.76 (95%)
        self.same_threshold = nn.Parameter(torch.tensor(0.7))
        self.log_same_sharpness = nn.Parameter(torch.tensor(2.3))
        self.colour_channels = colour_channels

    @staticmethod
    def _tower(channels: tuple[int, ...], c_in: int, dilated: bool) -> nn.Sequential:
        layers, c = [], c_in
        for stage, width in enumerate(channels):
            d = 2**stage if dilated else 1
            layers += [nn.Conv2d(c, width, 3, padding=d, dilation=d), nn.ReLU(inplace=True),
                       nn.Conv2d(width, width, 3, padding=d, dilation=d), nn.ReLU(inplace=True)]
            layers += [] if dilated else [nn.AvgPool2d(2)]
            c = width
        return nn.Sequential(*layers)

    def embed(self, x: torch.Tensor) -> torch.Tensor:
        """Features (B, d, ...): the projected ImageNet features; or the colour tower's, then (with
        ``luminance``) the grey tower's."""
        if self.imagenet:
            return self.project(self.features(x))
        colour = self.project(self.features(x - 0.5))
        if self.grey_features is None:
            return colour
        grey = self.grey_project(self.grey_features(x.mean(dim=1, keepdim=True) - 0.5))
        return torch.cat([colour, grey], dim=1)

    def unit(self, features: torch.Tensor, centre: torch.Tensor) -> torch.Tensor:
        """``features`` (B, d, ...) centred on ``centre`` (broadcast) and made unit length over both towers at
        once: one cosine over the concatenated features (normalising each tower apart and averaging the two
        cosines recognised less, unseen maps 0.641 against 0.726 at 2,000 steps; benchmarks/README.md)."""
        return F.normalize(features - centre, dim=1)

    def patches(self, context: torch.Tensor) -> torch.Tensor:
        """The context's 2n patches one by one, (B * 2n, c, h, w): each item's n preferred patches, then its n
        others; context (B, cn, 2h, w), pair i's preferred patch above its other."""
        b, c = context.shape[0], self.colour_channels
        h, n = context.shape[2] // 2, context.shape[1] // c
        return torch.cat([context[:, :, :h], context[:, :, h:]], dim=1).reshape(b * 2 * n, c, h, -1)

    def keys(self, context: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """(B, 2n, d) unit patch features (the n preferred patches, then the n others), centred on their
        mean, and that centre (B, d); context (B, cn, 2h, w)."""
        keys = self.embed(self.patches(context)).mean(dim=(2, 3)).unflatten(0, (context.shape[0], -1))
        centre = keys.mean(dim=1)
        return self.unit(keys.transpose(1, 2), centre[:, :, None]).transpose(1, 2), centre

    def cosines(self, image: torch.Tensor, keys: torch.Tensor, centre: torch.Tensor) -> torch.Tensor:
        """(B, 2n, H/s, W/s): every image location's cosine with each context patch."""
        feats = self.embed(image)
        if not self.dilated:  # a pooled tower's cells average over about one patch of support
            feats = F.avg_pool2d(feats, 3, stride=1, padding=1, count_include_pad=False)
        feats = self.unit(feats, centre[:, :, None, None])
        return torch.einsum("bkd,bdhw->bkhw", keys, feats)

    def patch_ranks(self, keys: torch.Tensor) -> torch.Tensor:
        """(B, 2n) in [-1, 1]: each patch's terrain's place in the order the context implies (issue 24's
        order inference; +1 most preferred). Patches are soft-identified by their cosine (``same``); a
        terrain beats another if a pair says so of patches like them, closed under transitivity
        (a > b, b > c ⇒ a > c); the place is (wins - losses) / (wins + losses) over the distinct terrains
        (each patch weighted by 1 / its terrain's patch count), a Copeland score of the implied order. For a
        chain a > b > c > d it is 1, 1/3, -1/3, -1 (a role-weighted sum gives b and c both 0); terrains the
        context leaves unordered keep their own pairs' places, and the decoder's learned prior orders them."""
        k = keys.shape[1]
        n = k // 2
        eye = torch.eye(k, dtype=keys.dtype, device=keys.device)
        sharp = self.log_same_sharpness.exp()
        same = torch.sigmoid(sharp * (keys @ keys.transpose(1, 2) - self.same_threshold)) * (1 - eye) + eye
        said = torch.zeros(k, k, dtype=keys.dtype, device=keys.device)
        said[torch.arange(n), torch.arange(n) + n] = 1.0  # pair i: preferred patch i beats patch n + i
        beats = (same @ said @ same).clamp(max=1.0)
        for _ in range(max(1, math.ceil(math.log2(k)))):  # paths of up to k steps
            beats = torch.maximum(beats, (beats @ beats).clamp(max=1.0))
        weight = 1.0 / same.sum(dim=2)  # (B, k)
        wins = (beats * weight[:, None, :]).sum(dim=2)
        losses = (beats * weight[:, :, None]).sum(dim=1)
        return (wins - losses) / (wins + losses).clamp_min(1e-6)

    def match(self, image: torch.Tensor, context: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """The (B, 2, H/s, W/s) maps S and M, and the cosines they derive from (B, 2n, H/s, W/s), which the
        matching loss (``pacer.loss.matching_loss``) trains directly."""
        keys, centre = self.keys(context)
        cosine = self.cosines(image, keys, centre)
        attention = torch.softmax(cosine * self.log_temperature.exp(), dim=1)
        role = -self.patch_ranks(keys)[:, :, None, None]
        maps = torch.cat([(attention * role).sum(dim=1, keepdim=True), cosine.amax(dim=1, keepdim=True)], dim=1)
        return maps, cosine

    def forward(self, image: torch.Tensor, context: torch.Tensor) -> torch.Tensor:
        return self.match(image, context)[0]


class UpBlock(nn.Module):
    """Transposed convolution ×2, concatenation with the encoder skip, conv block."""

    def __init__(self, c_in: int, c_out: int):
        super().__init__()
        self.up = nn.ConvTranspose2d(c_in, c_out, 2, stride=2)
        self.conv = conv_block(2 * c_out, c_out)

    def forward(self, x: torch.Tensor, skip: torch.Tensor) -> torch.Tensor:
        return self.conv(torch.cat([self.up(x), skip], dim=1))


class PacerNet(nn.Module):
    """R̂(I, Ĥ): BEV image (B,3,H,W) and context (B,3n,2h,w) → cost logits (B,H,W)."""

    def __init__(self, cfg: PacerModelParams, context_pairs: int = 3, colour_channels: int = 3,
                 patch_size: int | None = None):
        super().__init__()
        self.cfg = cfg
        widths = tuple(cfg.image_channels)
        if not widths:
            raise ValueError("pacer.model.image_channels is empty: give the U-Net encoder at least one width, "
                             "e.g. [16, 32, 64]")
        self.colour_channels = colour_channels
        self.patch_size = patch_size  # the context patches' side it was trained on (None: any square side)
        self.down = nn.ModuleList(conv_block(c, w) for c, w in zip((colour_channels, *widths[:-1]), widths))
        self.bottleneck = conv_block(widths[-1], cfg.bottleneck_channels)
        c_ctx = colour_channels * context_pairs
        self.context_pairs, self.context_channels = context_pairs, c_ctx
        self.context_encoder = (ContextResNet50(c_ctx, cfg.context_dim) if cfg.context_encoder == "resnet50"
                                else ContextCNN(c_ctx, tuple(cfg.context_channels), cfg.context_dim))
        ups = (cfg.bottleneck_channels, *widths[::-1])
        self.up = nn.ModuleList(UpBlock(c, w) for c, w in itertools.pairwise(ups))
        if cfg.fusion == "film":
            self.film = nn.ModuleList(FiLM(cfg.context_dim, c) for c in ups)
        else:
            b = cfg.bottleneck_channels
            self.fuse = nn.Sequential(nn.Linear(b + cfg.context_dim, b + cfg.context_dim // 2),
                                      nn.Linear(b + cfg.context_dim // 2, b))
        self.matcher = (TextureMatcher(tuple(cfg.match_channels), colour_channels, cfg.match_dilated,
                                       cfg.match_luminance, cfg.match_features) if cfg.match_channels else None)
        if self.matcher is not None:  # the match maps enter the bottleneck and every decoder stage
            self.match_in = nn.ModuleList(nn.Conv2d(2, c, 1) for c in ups)
            # and S reaches the cost logit directly, with a learned gain: "looks like a less preferred
            # patch" means "costs more" from the first step, and the decoder learns corrections around it
            self.match_gain = nn.Parameter(torch.tensor(1.0))
        self.out = nn.Conv2d(widths[0], 1, 1)

    @property
    def stride(self) -> int:
        """Image height and width must be multiples of this (one max-pool per encoder stage)."""
        return 2 ** len(self.down)

    def check_context(self, context: torch.Tensor) -> None:
        """A context is (B, 3n, 2h, h): n pairs of square h×h patches stacked vertically (Sec. IV-A), h the
        patch side the model was trained on."""
        if context.ndim != 4 or context.shape[1] != self.context_channels:
            raise ValueError(f"context of shape {tuple(context.shape)}: this model takes (B, {self.context_channels}, "
                             f"2h, h), {self.context_pairs} preference pairs (pacer.data.n_pairs); build the context "
                             "with the n_pairs the model was trained with")
        if context.shape[2] != 2 * context.shape[3]:
            raise ValueError(f"context of shape {tuple(context.shape)}: each pair is two square patches stacked "
                             "(height = 2 x width = 2 x pacer.data.patch_size); check the patch size")
        if self.patch_size is not None and context.shape[3] != self.patch_size:
            raise ValueError(f"context of shape {tuple(context.shape)}: this model was trained on "
                             f"{self.patch_size}-px patches (pacer.data.patch_size); cut the context's patches at "
                             f"{self.patch_size} px, or train a model for {context.shape[3]}-px patches")

    def check_inputs(self, image: torch.Tensor, context: torch.Tensor) -> None:
        """One clear ValueError for inputs the model was not built for, before any layer runs: an image that is
        not (B, 3, H, W) with H and W multiples of ``stride``, a context that ``check_context`` refuses, a
        context batch other than the image's (torch would broadcast one context over every image silently),
        and values that are not finite (a NaN image would give a NaN costmap)."""
        if image.ndim != 4 or image.shape[1] != self.colour_channels:
            raise ValueError(f"image of shape {tuple(image.shape)}: this model takes (B, {self.colour_channels}, H, W) "
                             "BEV images")
        h, w = image.shape[-2:]
        if h % self.stride or w % self.stride:
            raise ValueError(f"image size {h}x{w}: height and width must be multiples of {self.stride} "
                             f"(2 ** len(pacer.model.image_channels)); change the BEV size in params.yaml")
        self.check_context(context)
        if context.shape[0] != image.shape[0]:
            raise ValueError(f"{image.shape[0]} image(s) but {context.shape[0]} context(s): give one context per "
                             "image (repeat a shared context with context.expand(len(image), -1, -1, -1))")
        for name, x in (("image", image), ("context", context)):
            if not x.is_meta and not torch.isfinite(x).all():  # meta: ``params check``'s shape-only dry run
                raise ValueError(f"the {name} holds NaN or infinite values; check how it was loaded (pixels are "
                                 "floats in [0, 1])")

    def forward(self, image: torch.Tensor, context: torch.Tensor) -> torch.Tensor:
        return self.scored(image, context)[0]

    def scored(self, image: torch.Tensor, context: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor | None]:
        """Cost logits (B, H, W) and the matcher's cosines (B, 2n, H/s, W/s; None without a matcher)."""
        self.check_inputs(image, context)
        z = self.context_encoder(context)
        skips, x = [], image
        for block in self.down:
            x = block(x)
            skips.append(x)
            x = F.max_pool2d(x, 2)
        x = self.bottleneck(x)
        if self.cfg.fusion == "film":
            x = self.film[0](x, z)
        else:
            pooled = x.mean(dim=(2, 3))
            x = self.fuse(torch.cat([pooled, z], dim=1))[:, :, None, None].expand_as(x)
        match, cosine = self.matcher.match(image, context) if self.matcher is not None else (None, None)
        x = self._add_match(x, match, 0)
        for i, (block, skip) in enumerate(zip(self.up, reversed(skips))):
            x = block(x, skip)
            if self.cfg.fusion == "film":
                x = self.film[i + 1](x, z)
            x = self._add_match(x, match, i + 1)
        logits = self.out(x)[:, 0]
        if match is not None:
            evidence = F.interpolate(match[:, :1], size=logits.shape[-2:], mode="bilinear", align_corners=False)
            logits = logits + self.match_gain * evidence[:, 0]
        return logits, cosine

    def _add_match(self, x: torch.Tensor, match: torch.Tensor | None, stage: int) -> torch.Tensor:
        if match is None:
            return x
        if match.shape[-2] > x.shape[-2]:  # a full-resolution match map: the mean over each stage's cell
            match = F.adaptive_avg_pool2d(match, x.shape[-2:])
        elif match.shape[-2:] != x.shape[-2:]:
            match = F.interpolate(match, size=x.shape[-2:], mode="bilinear", align_corners=False)
        return x + self.match_in[stage](match)

    @torch.no_grad()
    def costmap(self, image: torch.Tensor, context: torch.Tensor) -> torch.Tensor:
        """Costs in [0, 1] (eval mode, no gradients): what a planner reads."""
        return torch.sigmoid(self(image, context))


def build_model(cfg: PacerModelParams, *, context_pairs: int = 3, patch_size: int | None = None,
                device: str | torch.device = "cpu") -> PacerNet:
    """A freshly initialised network on ``device`` (initialisation draws from torch's global seed)."""
    return PacerNet(cfg, context_pairs=context_pairs, patch_size=patch_size).to(device)


def count_parameters(model: nn.Module) -> int:
    return sum(p.numel() for p in model.parameters())
