"""What ImageNet features would cost PACER's training step, against the matcher it trains today (issue 61).

One training step of the texture matcher alone (cosines of every image location with the context's 2n patches,
forward and backward of the matching loss's input), on a batch of the profile's BEV images and contexts, for:

* ``scratch``: the committed recipe's matcher (``pacer.model.TextureMatcher`` with the profile's
  ``match_channels``, dilated, with the grey tower), every weight trained;
* ``pretrained``: ``benchmarks/pacer_texture_towers.py``'s frozen EfficientNet-Lite0 (strides 4 and 8) and a
  trained 1 x 1 projection, the backbone run on every step;
* ``pretrained, cached``: the same with the backbone's features computed once per item and read back (they do not
  train), so a step runs only the projection and the cosines.

Side by side in one run, alternating, median over ``--repeats``; the ratio to ``scratch`` is the figure.

    .venv/bin/python benchmarks/pacer_pretrained_cost.py [--profile default] [--batch 16] [--repeats 7] [--threads 2]
"""

from __future__ import annotations

import argparse
import statistics
import time

import torch

from navlab.core.params import load_params
from navlab.pacer.model import TextureMatcher
from pacer_texture_towers import PretrainedMatcher


def step(matcher: TextureMatcher, image: torch.Tensor, context: torch.Tensor) -> None:
    matcher.zero_grad(set_to_none=True)
    cosines = matcher.cosines(image, *matcher.keys(context))
    cosines.square().mean().backward()


class CachedPretrained(PretrainedMatcher):
    """``PretrainedMatcher`` reading its frozen features back instead of running the backbone: what a training step
    costs if they are computed once per item. Keyed on the input's shape (the images' and the patches' differ)."""

    def __init__(self, inputs: list[torch.Tensor]):
        super().__init__()
        self.cache = {tuple(x.shape): PretrainedMatcher.backbone_features(self, x) for x in inputs}

    def backbone_features(self, x: torch.Tensor) -> torch.Tensor:
        return self.cache[tuple(x.shape)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--batch", type=int, default=16)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(0)
    params = load_params(args.profile).pacer
    side, patch, pairs = params.data.image_size, params.data.patch_size, params.data.n_pairs
    image = torch.rand(args.batch, 3, side, side)
    context = torch.rand(args.batch, 3 * pairs, 2 * patch, patch)
    m = params.model
    scratch = TextureMatcher(tuple(m.match_channels), 3, m.match_dilated, m.match_luminance).train()
    pretrained = PretrainedMatcher().train()
    cached = CachedPretrained([image, pretrained.patches(context)]).train()
    runs = {"scratch": lambda: step(scratch, image, context),
            "pretrained": lambda: step(pretrained, image, context),
            "pretrained, cached": lambda: step(cached, image, context)}
    times: dict[str, list[float]] = {name: [] for name in runs}
    for name, run in runs.items():  # warm-up
        run()
    for _ in range(args.repeats):
        for name, run in runs.items():
            start = time.perf_counter()
            run()
            times[name].append(time.perf_counter() - start)
    base = statistics.median(times["scratch"])
    print(f"{args.profile}: batch {args.batch} of {side} px images, {2 * pairs} patches of {patch} px each, "
          f"{args.threads} thread(s), median of {args.repeats}")
    for name, values in times.items():
        median = statistics.median(values)
        print(f"  {name:20s} {1000 * median:8.1f} ms per step   ratio to scratch {median / base:5.2f}")


if __name__ == "__main__":
    main()
