"""navlab.pacer.recolour: D_synthetic's recoloured terrains, one colour map per terrain in image and context."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.core.params.pacer import PacerRecolourParams
from navlab.core.seeding import rng
from navlab.pacer.context import stack_context
from navlab.pacer.datasets import RECIPES, PacerDataset
from navlab.pacer.recolour import colour_map, hue_rotation, recolour_terrains
from navlab.pacer.terrain import load_terrain_bank
from pacer_support import with_pacer_data

ALWAYS = PacerRecolourParams(probability=1.0, grey=0.3, saturation=(0.3, 1.4))


@pytest.fixture(scope="module")
def bank(smoke_data, smoke_params):
    return load_terrain_bank(smoke_data, smoke_params.pacer.data)


@given(st.floats(0.0, 2 * np.pi), st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
@settings(max_examples=50, deadline=None)
def test_hue_rotation_is_a_rotation_that_keeps_the_grey_axis(angle, r, g, b):
    rotation = hue_rotation(angle)
    np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(rotation) == pytest.approx(1.0)
    np.testing.assert_allclose(rotation @ np.ones(3), np.ones(3), atol=1e-12)
    colour = np.array([r, g, b])
    assert np.linalg.norm(rotation @ colour) == pytest.approx(np.linalg.norm(colour), abs=1e-12)


def test_colour_maps_keep_grey_levels_and_scale_chroma_within_bounds():
    """M c keeps c's channel mean; its chroma (c minus that mean) is scaled by s in the saturation range, or
    is 0 for a grey map, whose three channels then agree."""
    colour = np.array([0.7, 0.2, 0.4], dtype=np.float32)
    chroma = np.linalg.norm(colour - colour.mean())
    seen_grey = seen_colour = 0
    for k in range(200):
        matrix = colour_map(rng(0, "test", k), ALWAYS)
        out = matrix @ colour
        assert out.mean() == pytest.approx(colour.mean(), abs=1e-6)
        scale = np.linalg.norm(out - out.mean()) / chroma
        if scale < 1e-6:
            seen_grey += 1
            np.testing.assert_allclose(out, out.mean(), atol=1e-6)
        else:
            seen_colour += 1
            assert 0.3 - 1e-5 <= scale <= 1.4 + 1e-5
    assert 30 <= seen_grey <= 90 and seen_colour > 100  # grey with chance 0.3 of 200 draws


def test_each_terrain_gets_one_map_in_the_image_and_in_its_context_patches():
    """Terrain t's pixels and every context patch of t (preferred or other) go through the same map, so a
    uniform colour stays equal across image and context; other terrains keep theirs when not drawn."""
    colours = {3: [0.6, 0.3, 0.2], 5: [0.2, 0.5, 0.3], 8: [0.3, 0.3, 0.7]}
    labels = np.full((8, 8), -1)
    labels[:4], labels[4:, :4], labels[4:, 4:] = 3, 5, 8
    image = np.zeros((8, 8, 3), dtype=np.float32)
    for t, c in colours.items():
        image[labels == t] = c
    pairs = np.array([[3, 5], [8, 3], [5, 8]])
    patch = {t: np.broadcast_to(np.float32(c), (4, 4, 3)) for t, c in colours.items()}
    context = stack_context(np.stack([patch[a] for a, _ in pairs]), np.stack([patch[b] for _, b in pairs]))
    out_image, out_context = recolour_terrains(image, labels, context, pairs, rng(1), ALWAYS)
    changed = 0
    for k, (a, b) in enumerate(pairs):
        for terrain, rows in ((a, slice(0, 4)), (b, slice(4, 8))):
            in_image = out_image[labels == terrain]
            in_patch = out_context[3 * k : 3 * k + 3, rows].reshape(3, -1).T
            np.testing.assert_allclose(in_patch, np.broadcast_to(in_image[0], in_patch.shape), atol=1e-6)
            np.testing.assert_allclose(in_image, np.broadcast_to(in_image[0], in_image.shape), atol=1e-6)
            changed += not np.allclose(in_image[0], colours[terrain], atol=1e-3)
    assert changed > 0
    assert out_image.min() >= 0.0 and out_image.max() <= 1.0
    assert np.allclose(image[labels == 3], np.float32(colours[3]), atol=0)  # the input is left as it was


def test_probability_zero_draws_nothing_and_keeps_synthetic_items_byte_identical(bank, smoke_params):
    """With the chance 0 a D_synthetic item is the item the pipeline drew before recolouring existed; with
    chance 1 it differs only in image and context, and real / shuffled items never change."""
    off = with_pacer_data(smoke_params, recolour=dataclasses.replace(ALWAYS, probability=0.0)).pacer.data
    on = with_pacer_data(smoke_params, recolour=ALWAYS).pacer.data
    for name in ("real", "shuffled", "synthetic"):
        plain = PacerDataset(bank, off, RECIPES[name], "train", 3, 0).item(2)
        coloured = PacerDataset(bank, on, RECIPES[name], "train", 3, 0).item(2)
        for key in plain:
            same = np.array_equal(plain[key], coloured[key])
            assert same if (name != "synthetic" or key not in ("image", "context")) else not same, (name, key)
    generator = rng(7)
    state = generator.bit_generator.state
    image, context = np.zeros((4, 4, 3), np.float32), np.zeros((3, 8, 4), np.float32)
    recolour_terrains(image, np.zeros((4, 4), int), context, np.array([[0, 1]]), generator,
                      dataclasses.replace(ALWAYS, probability=0.0))
    assert generator.bit_generator.state == state


def test_the_tables_say_when_d_synthetic_is_recoloured(smoke_params):
    """The protocol note names the recolouring (an addition to the paper's D_synthetic) only where it is on."""
    from navlab.pacer.experiments import protocol_note

    evaluation = smoke_params.pacer.evaluation
    on = with_pacer_data(smoke_params, recolour=ALWAYS).pacer.data
    off = with_pacer_data(smoke_params, recolour=dataclasses.replace(ALWAYS, probability=0.0)).pacer.data
    assert "recolouring of ours" in protocol_note(on, evaluation, "smoke")
    assert "with chance 1," in protocol_note(on, evaluation, "smoke")
    assert "recolour" not in protocol_note(off, evaluation, "smoke")
