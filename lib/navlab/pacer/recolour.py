"""Recoloured terrains: D_synthetic items whose terrains take new colours, alike in the image and the context.

Why (issue 24): PACER meets terrains at deployment that it never trained on, and its texture matcher learns
whatever tells the 8 seen and 14 synthetic textures apart, colour first; on the unseen group (three grey
textures, four rocks) its nearest context patch was right for 0.57 of map pixels, below always naming the
map's commonest terrain (0.65). The paper widens the appearances PACER trains on by replacing terrains with
synthetic textures (Sec. V-C, D_synthetic); this widens them further at no cost in data: each terrain of a
D_synthetic item is, with chance ``probability``, mapped through one random linear colour map (a hue rotation
about the grey axis and a saturation scale, or grey altogether with chance ``grey``), the *same* map on its
pixels and on its context patches. What still ties a context patch to its terrain in the image is then
texture and the colour relation both share, not the colour the training photograph happened to have.
Orderings in D_synthetic are random, so no learned prior ties a colour to a cost.
"""

from __future__ import annotations

import numpy as np

from navlab.core.params.pacer import PacerRecolourParams

GREY = np.full((3, 3), 1.0 / 3.0)  # projects an RGB colour onto the grey axis (its channel mean, in every channel)


def hue_rotation(angle: float) -> np.ndarray:
    """(3, 3): rotation of RGB space by ``angle`` radians about the grey axis (Rodrigues' formula)."""
    k = np.ones(3) / np.sqrt(3.0)
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * cross + (1.0 - np.cos(angle)) * cross @ cross


def colour_map(rng: np.random.Generator, params: PacerRecolourParams) -> np.ndarray:
    """(3, 3) float32 M: colour c becomes M c = grey(c) + s R(θ) (c - grey(c)); a colour's channel mean (its
    grey level) is kept, its chroma turned by θ ~ U(0, 2π) and scaled by s ~ U(saturation), or s = 0 (grey)
    with chance ``params.grey``."""
    grey = rng.uniform() < params.grey
    saturation = 0.0 if grey else rng.uniform(*params.saturation)
    angle = rng.uniform(0.0, 2.0 * np.pi)
    return (GREY + saturation * hue_rotation(angle) @ (np.eye(3) - GREY)).astype(np.float32)


def recolour_terrains(image: np.ndarray, labels: np.ndarray, context: np.ndarray, pairs: np.ndarray,
                      rng: np.random.Generator, params: PacerRecolourParams) -> tuple[np.ndarray, np.ndarray]:
    """(image, context), each terrain of ``labels`` or ``pairs`` recoloured with chance ``params.probability``
    by its own :func:`colour_map`, on its pixels and its context patches alike, clipped to [0, 1].

    image float32 (S, S, 3); labels (S, S) terrain ids (negative: outside the view, left as they are); context
    float32 (3n, 2h, w), pair k in channels 3k..3k+2, its preferred patch on top; pairs (n, 2). Nothing is drawn
    when ``params.probability`` is 0, so such items keep their bytes."""
    if params.probability == 0.0:
        return image, context
    image, context = image.copy(), context.copy()
    n, h = len(pairs), context.shape[1] // 2
    patches = context.reshape(n, 3, 2, h, -1)  # pair, channel, half (0 preferred, 1 other), row, column
    terrains = np.union1d(labels[labels >= 0], np.asarray(pairs).ravel())
    for terrain in terrains:
        if rng.uniform() >= params.probability:
            continue
        matrix = colour_map(rng, params)
        where = labels == terrain
        image[where] = np.clip(image[where] @ matrix.T, 0.0, 1.0)
        for k, half in zip(*np.nonzero(np.asarray(pairs) == terrain)):
            patches[k, :, half] = np.clip(np.einsum("cd,dhw->chw", matrix, patches[k, :, half]), 0.0, 1.0)
    return image, patches.reshape(context.shape)
