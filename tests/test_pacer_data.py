"""navlab.pacer data half: terrain banks, BEV rendering, preference contexts, datasets; PACER metrics."""

from __future__ import annotations

import dataclasses

import cv2
import numpy as np
import pytest
import torch

from navlab.core.grid import RasterFrame
from navlab.core.params import ParamsError
from navlab.core.seeding import rng
from navlab.maps.dataset import load_maps
from navlab.maps.semantic_map import SemanticMap
from navlab.metrics.cost_tiers import cost_tier_proportions
from navlab.pacer.aerial import aerial_map, aerial_maps, semantic_map_regions
from navlab.pacer.bev import fov_mask
from navlab.pacer.context import preference_context, preference_pairs, stack_context, superset_terrains
from navlab.pacer.datasets import PacerDataset, Recipe, evaluation_dataset, max_terrains, pacer_dataset
from navlab.pacer.margin_ranking import margin_ranking_error
from navlab.pacer.preferences import IGNORE, environment_tiers, order_terrains, rank_costs, target_costmap
from navlab.pacer.terrain import load_terrain_bank
from pacer_support import with_pacer_data


@pytest.fixture(scope="module")
def bank(smoke_data, smoke_params):
    return load_terrain_bank(smoke_data, smoke_params.pacer.data)


def _items(dataset, count):
    return [dataset.item(i) for i in range(count)]


# --- terrain banks ------------------------------------------------------------------------------------

def test_bank_split_is_disjoint_and_documented(bank, smoke_params):
    data = smoke_params.pacer.data
    seen, unseen, synthetic = (set(bank.ids(g).tolist()) for g in ("seen", "unseen", "synthetic"))
    assert seen and unseen and len(synthetic) == 14
    assert not (seen & unseen or seen & synthetic or unseen & synthetic)
    assert len(seen | unseen | synthetic) == len(bank)
    assert [bank.names[i] for i in sorted(seen)] == list(data.seen)
    # realistic ranks follow params; synthetic terrains have none
    ranked = np.argsort(np.where(bank.realistic_rank >= 0, bank.realistic_rank, 99))[: len(seen | unseen)]
    assert [bank.names[i] for i in ranked] == list(data.realistic_ordering)
    assert (bank.realistic_rank[list(synthetic)] == -1).all()


def test_bank_parts_are_disjoint_strips_and_loading_is_deterministic(bank, smoke_data, smoke_params):
    again = load_terrain_bank(smoke_data, smoke_params.pacer.data)
    for t in range(len(bank)):
        for image, context, image2 in zip(bank.image_parts[t], bank.context_parts[t], again.image_parts[t], strict=True):
            width = image[0].shape[1] + context[0].shape[1]
            assert context[0].shape[1] == max(1, round(width * smoke_params.pacer.data.context_fraction))
            assert image[0].dtype == np.float32 and image[0].shape[2] == 3
            assert image[0].tobytes() == image2[0].tobytes()


def test_inconsistent_split_is_one_clear_error(smoke_data, smoke_params):
    data = smoke_params.pacer.data
    broken = dataclasses.replace(data, realistic_ordering=data.realistic_ordering[1:])
    with pytest.raises(ParamsError, match="realistic_ordering"):
        load_terrain_bank(smoke_data, broken)
    crowded = dataclasses.replace(data, layout=dataclasses.replace(data.layout, regions=(2, 8)))
    with pytest.raises(ParamsError, match="pacer.data.seen: 8 classes, but a BEV image can show 9 terrains"):
        load_terrain_bank(smoke_data, crowded)
    backwards = dataclasses.replace(data, footprint_texels=(200.0, 100.0))
    with pytest.raises(ParamsError, match=r"footprint_texels = \[200.0, 100.0\]"):
        load_terrain_bank(smoke_data, backwards)


# --- preferences: ordering -> costs ------------------------------------------------------------------

def test_rank_costs_are_l_minus_one_over_l_minus_one():
    assert rank_costs(np.array([7])).tolist() == [0.0]
    assert rank_costs(np.array([3, 9])).tolist() == [0.0, 1.0]
    np.testing.assert_allclose(rank_costs(np.array([5, 1, 2, 0])), [0, 1 / 3, 2 / 3, 1])
    with pytest.raises(ValueError, match="empty"):
        rank_costs(np.array([], dtype=np.int64))


def test_target_costmap_maps_each_label_by_its_rank():
    labels = np.array([[4, 4, 2], [9, IGNORE, 2]])
    costs = target_costmap(labels, np.array([2, 9, 4, IGNORE]))  # padding is ignored
    np.testing.assert_allclose(costs, [[1.0, 1.0, 0.0], [0.5, 0.0, 0.0]])
    assert target_costmap(np.array([[3, IGNORE]]), np.array([3])).tolist() == [[0.0, 0.0]]  # L = 1
    with pytest.raises(ValueError, match="does not rank"):
        target_costmap(labels, np.array([2, 9]))
    with pytest.raises(ValueError, match="repeats"):
        target_costmap(labels, np.array([2, 9, 4, 2]))


def test_tiers_come_from_each_environments_own_ordering():
    # a two-terrain environment has one low and one high terrain, whatever their global ranks
    two = environment_tiers(np.array([9, 4]), 12)
    assert two[9] == 0 and two[4] == 2 and (np.delete(two, [4, 9]) == -1).all()
    assert environment_tiers(np.array([3, 1, 7]), 8)[[3, 1, 7]].tolist() == [0, 1, 2]
    for count in range(1, 9):  # thirds of the ranks; inverting the ordering swaps low and high
        ordering = rng(count, "tiers").permutation(20)[:count]
        tiers, inverted = environment_tiers(ordering, 20), environment_tiers(ordering[::-1], 20)
        assert (np.diff(tiers[ordering]) >= 0).all() and tiers[ordering[0]] == 0
        assert (tiers[ordering] + inverted[ordering] == 2).all() or count == 1
        costs = rank_costs(ordering)
        assert (tiers[ordering][costs < 1 / 3 - 1e-9] == 0).all() and (tiers[ordering][costs > 2 / 3 + 1e-9] == 2).all()
    with pytest.raises(ValueError, match="distinct terrain ids"):
        environment_tiers(np.array([2, 2]), 5)


# --- preference contexts -------------------------------------------------------------------------------

def test_context_tensor_puts_the_preferred_patch_on_top():
    n, h, w = 3, 4, 5
    preferred = rng(0, "top").uniform(size=(n, h, w, 3)).astype(np.float32)
    other = rng(0, "bottom").uniform(size=(n, h, w, 3)).astype(np.float32)
    context = stack_context(preferred, other)
    assert context.shape == (3 * n, 2 * h, w) and context.dtype == np.float32
    for i in range(n):
        np.testing.assert_array_equal(context[3 * i : 3 * i + 3, :h].transpose(1, 2, 0), preferred[i])
        np.testing.assert_array_equal(context[3 * i : 3 * i + 3, h:].transpose(1, 2, 0), other[i])


def test_preference_pairs_follow_the_ordering():
    ordering = np.array([12, 3, 7, 5])
    position = {t: i for i, t in enumerate(ordering)}
    for seed in range(20):
        pairs = preference_pairs(ordering, 3, rng(seed, "pairs"))
        assert pairs.shape == (3, 2)
        assert all(position[a] < position[b] for a, b in pairs)
        assert len({tuple(p) for p in pairs}) == 3  # without replacement while there are enough pairs
    assert (preference_pairs(np.array([4, 8]), 3, rng(0)) == [4, 8]).all()  # L = 2: one pair, repeated
    assert (preference_pairs(np.array([6]), 3, rng(0)) == 6).all()  # L = 1: no preference to express


def test_superset_contexts_name_every_terrain_in_view_when_n_allows():
    candidates = np.arange(10)
    for seed in range(30):
        gen = rng(seed, "superset")
        in_view = gen.choice(10, size=int(gen.integers(1, 5)), replace=False)
        terrains = superset_terrains(in_view, candidates, 2, gen)
        assert set(in_view) <= set(terrains.tolist()) and len(terrains) == len(in_view) + 2
        ordering = gen.permutation(terrains)
        position = {int(t): i for i, t in enumerate(ordering)}
        pairs = preference_pairs(ordering, 3, gen, cover=in_view)
        assert all(position[a] < position[b] for a, b in pairs)
        assert set(in_view.tolist()) <= set(pairs.ravel().tolist())  # 1-4 terrains in view fit in 3 pairs
    many = np.arange(8)  # 8 to cover with 3 pairs: 6 of them are named, none twice in the covering pairs
    assert len(set(preference_pairs(many, 3, rng(0), cover=many).ravel().tolist())) == 6
    with pytest.raises(ValueError, match="does not rank"):
        preference_pairs(np.array([1, 2]), 3, rng(0), cover=np.array([5]))


def test_context_patches_come_from_the_real_bank(bank, smoke_params):
    data = smoke_params.pacer.data
    ordering = bank.ids("seen")[:3]
    context, pairs = preference_context(bank, ordering, rng(1, "ctx"), data)
    h = data.patch_size
    assert context.shape == (3 * data.n_pairs, 2 * h, h)
    assert 0.0 <= context.min() and context.max() <= 1.0 and context.std() > 0.01
    assert set(pairs.ravel().tolist()) <= set(ordering.tolist())


ENCODED_WIDTH = 192


def _encoded_data_dir(tmp_path, params):
    """A data dir whose every photograph (192 px wide, the least the bank takes) stores its column index in the
    red channel (and its own number in blue: the bank refuses one photograph in two classes)."""
    columns = np.arange(ENCODED_WIDTH, dtype=np.uint8)
    photo = np.zeros((64, ENCODED_WIDTH, 3), np.uint8)
    photo[:, :, 2] = columns[None, :]  # OpenCV writes BGR: channel 2 is red
    photo[:, :, 1] = 128
    for group in ("seen", "unseen", "synthetic"):
        for sources in getattr(params.pacer.data, group).values():
            for source in sources:
                photo[0, 0, 0] += 1
                path = tmp_path / "raw" / "terrain" / source
                path.parent.mkdir(parents=True, exist_ok=True)
                assert cv2.imwrite(str(path.with_suffix(".png")), photo)
                path.with_suffix(".png").rename(path)
    return tmp_path


def test_context_patches_never_come_from_the_pixels_images_are_drawn_from(tmp_path, smoke_params):
    data = smoke_params.pacer.data
    flat = dataclasses.replace(data, photometric=dataclasses.replace(  # colours encode photograph columns here
        data.photometric, brightness=0.0, gradient=0.0, shadows=0, noise_std=0.0),
        recolour=dataclasses.replace(data.recolour, probability=0.0))
    bank = load_terrain_bank(_encoded_data_dir(tmp_path, smoke_params), flat)
    cut = ENCODED_WIDTH - round(ENCODED_WIDTH * data.context_fraction)  # first context column
    for name in ("real", "synthetic"):
        recipe = Recipe(name, name, "seen", "realistic" if name == "real" else "random", synthetic=name == "synthetic")
        dataset = PacerDataset(bank, flat, recipe, "train", 8, seed=0)
        for item in _items(dataset, 8):
            red_image = item["image"][0][item["fov_mask"]]
            assert red_image.max() <= (cut - 1) / 255 + 1e-6  # image pixels: image-part columns only
            assert item["context"][0::3].min() >= cut / 255 - 1e-6  # context: context-part columns only


# --- rendering: field of view, determinism ------------------------------------------------------------

@pytest.mark.parametrize("size,near", [(64, 0.45), (33, 0.2), (16, 1.0)])
def test_fov_mask_is_a_centred_trapezoid(size, near):
    mask = fov_mask(size, near)
    widths = mask.sum(axis=1)
    assert widths[0] == size and abs(widths[-1] - near * size) <= 2
    assert (np.diff(widths) <= 0).all()  # narrows towards the robot
    slopes = np.diff(widths.astype(float))
    assert np.ptp(slopes) <= 2  # straight legs
    for row in mask:
        cols = np.flatnonzero(row)
        assert (np.diff(cols) == 1).all()  # one interval per row
        assert abs(cols[0] + cols[-1] - (size - 1)) <= 1  # centred


def test_items_are_zero_outside_the_field_of_view(bank, smoke_params):
    dataset = pacer_dataset(smoke_params, None, "real", bank=bank)
    for item in _items(dataset, 6):
        outside = ~item["fov_mask"]
        assert outside.any() and (item["image"][:, outside] == 0).all()
        assert (item["costmap"][outside] == 0).all() and (item["labels"][outside] == IGNORE).all()
        assert (item["labels"][item["fov_mask"]] >= 0).all()
        assert (item["fov_mask"] == fov_mask(smoke_params.pacer.data.image_size,
                                             smoke_params.pacer.data.camera.near_width)).all()


def test_items_have_the_documented_layout_and_collate(bank, smoke_params):
    data = smoke_params.pacer.data
    dataset = pacer_dataset(smoke_params, None, "shuffled", bank=bank)
    batch = next(iter(torch.utils.data.DataLoader(dataset, batch_size=4)))
    s, n, h = data.image_size, data.n_pairs, data.patch_size
    expected = {"image": ((4, 3, s, s), torch.float32), "context": ((4, 3 * n, 2 * h, h), torch.float32),
                "costmap": ((4, s, s), torch.float32), "fov_mask": ((4, s, s), torch.bool),
                "labels": ((4, s, s), torch.int64), "ordering": ((4, max_terrains(data)), torch.int64),
                "pairs": ((4, n, 2), torch.int64)}
    assert {k: (tuple(v.shape), v.dtype) for k, v in batch.items()} == expected
    assert 0 <= batch["image"].min() and batch["image"].max() <= 1
    assert 0 <= batch["costmap"].min() and batch["costmap"].max() <= 1


def test_items_and_maps_are_deterministic_per_seed_and_index(bank, smoke_params, smoke_data):
    data = smoke_params.pacer.data
    first = PacerDataset(bank, data, Recipe("real", "real", "seen", "realistic"), "train", 4, seed=0)
    same = PacerDataset(bank, data, Recipe("real", "real", "seen", "realistic"), "train", 4, seed=0)
    other_seed = PacerDataset(bank, data, Recipe("real", "real", "seen", "realistic"), "train", 4, seed=1)
    for i in range(4):
        a, b, c = first.item(i), same.item(i), other_seed.item(i)
        assert all(a[k].tobytes() == b[k].tobytes() for k in a)
        assert a["image"].tobytes() != c["image"].tobytes()
    assert first.item(0)["image"].tobytes() != first.item(1)["image"].tobytes()
    val = pacer_dataset(smoke_params, None, "real", "val", bank=bank)
    assert val.item(0)["image"].tobytes() != first.item(0)["image"].tobytes()  # splits differ
    first.set_epoch(3)  # augmentation: a fresh draw per epoch, itself reproducible
    assert first.item(0)["image"].tobytes() != same.item(0)["image"].tobytes()
    assert first.item(0)["image"].tobytes() == first.item(0)["image"].tobytes()
    maps, again = (aerial_maps(smoke_params, smoke_data, "unseen", bank=bank) for _ in range(2))
    assert all(m.image.tobytes() == n.image.tobytes() and m.start == n.start for m, n in zip(maps, again, strict=True))


# --- orderings per dataset -------------------------------------------------------------------------------

def _in_view(params):
    """``params`` with targets over the terrains in view only, for the tests of what a window shows."""
    return with_pacer_data(params, train_target="in_view")


@pytest.mark.parametrize("target", ["in_view", "context"])
def test_realistic_orderings_sort_by_rank_and_costs_follow(bank, smoke_params, target):
    dataset = pacer_dataset(with_pacer_data(smoke_params, train_target=target), None, "real", bank=bank)
    for item in _items(dataset, 10):
        ordering = item["ordering"][item["ordering"] >= 0]
        shown = set(np.unique(item["labels"][item["fov_mask"]]).tolist())
        assert set(ordering.tolist()) == shown if target == "in_view" else set(ordering.tolist()) >= shown
        assert (np.diff(bank.realistic_rank[ordering]) > 0).all()
        np.testing.assert_array_equal(item["costmap"], target_costmap(item["labels"], ordering))


def test_shuffled_orderings_are_permutations_not_only_reversals(bank, smoke_params):
    dataset = pacer_dataset(_in_view(smoke_params), None, "shuffled", bank=bank)
    kinds = set()
    for item in _items(dataset, 40):
        ordering = item["ordering"][item["ordering"] >= 0]
        present = np.unique(item["labels"][item["fov_mask"]])
        assert sorted(ordering.tolist()) == present.tolist()
        realistic = order_terrains(present, "realistic", bank, rng(0))
        if len(ordering) >= 3:
            kinds.add("realistic" if (ordering == realistic).all() else
                      "reversed" if (ordering == realistic[::-1]).all() else "other")
    assert "other" in kinds and len(kinds) >= 2


def test_synthetic_items_show_a_synthetic_terrain(bank, smoke_params):
    synthetic = set(bank.ids("synthetic").tolist())
    dataset = pacer_dataset(_in_view(smoke_params), None, "synthetic", bank=bank)
    for item in _items(dataset, 12):
        shown = set(np.unique(item["labels"][item["fov_mask"]]).tolist())
        assert shown & synthetic
        assert set(item["ordering"][item["ordering"] >= 0].tolist()) == shown


def test_inverted_evaluation_reverses_costs_on_the_same_images(bank, smoke_params):
    params = _in_view(smoke_params)  # the same terrains ranked both ways (context targets add drawn extras)
    realistic = evaluation_dataset(params, None, "unseen", "realistic", bank=bank)
    inverted = evaluation_dataset(params, None, "unseen", "inverted", bank=bank)
    blind = evaluation_dataset(params, None, "unseen", "realistic", informative=False, bank=bank)
    unseen, seen = set(bank.ids("unseen").tolist()), set(bank.ids("seen").tolist())
    for a, b, c in zip(_items(realistic, 6), _items(inverted, 6), _items(blind, 6), strict=True):
        assert a["image"].tobytes() == b["image"].tobytes() == c["image"].tobytes()
        assert set(np.unique(a["labels"][a["fov_mask"]]).tolist()) <= unseen
        fov = a["fov_mask"]
        np.testing.assert_allclose(a["costmap"][fov] + b["costmap"][fov], 1.0 if len(np.unique(a["labels"][fov])) > 1 else 0.0)
        np.testing.assert_array_equal(a["costmap"], c["costmap"])
        assert set(a["pairs"].ravel().tolist()) <= unseen  # informative: the image's own group
        assert set(c["pairs"].ravel().tolist()) <= seen  # uninformative: only the other group
        rank = bank.realistic_rank
        assert (rank[a["pairs"][:, 0]] < rank[a["pairs"][:, 1]]).all() or len(np.unique(a["pairs"])) == 1
        assert (rank[b["pairs"][:, 0]] > rank[b["pairs"][:, 1]]).all() or len(np.unique(b["pairs"])) == 1
        assert (rank[c["pairs"][:, 0]] < rank[c["pairs"][:, 1]]).all()


@pytest.mark.parametrize("layout", ["procedural", "surenav"])
def test_aerial_maps_cover_one_group_with_endpoints_on_opposite_edges(bank, smoke_params, smoke_data, layout):
    params = _with_aerial_layout(smoke_params, layout)
    size = params.pacer.data.aerial.size
    for group in ("seen", "unseen"):
        for m in aerial_maps(params, smoke_data, group, bank=bank):
            assert m.image.shape == (3, size, size) and m.labels.shape == (size, size)
            assert set(np.unique(m.labels).tolist()) == set(m.terrains.tolist()) <= set(bank.ids(group).tolist())
            assert len(m.terrains) >= 2
            (r0, c0), (r1, c1) = m.start, m.goal
            assert max(abs(r0 - r1), abs(c0 - c1)) >= 0.8 * size


def _with_aerial_layout(params, layout):
    return with_pacer_data(params, aerial=dataclasses.replace(params.pacer.data.aerial, layout=layout))


def test_surenav_aerial_maps_give_each_semantic_label_one_terrain(bank, smoke_params, smoke_data):
    params = _with_aerial_layout(smoke_params, "surenav")
    semantic_maps = load_maps(smoke_data, "test")
    size = params.pacer.data.aerial.size
    for index in range(3):
        window = semantic_map_regions(semantic_maps, size, rng(params.pacer.seed, "pacer-aerial", "seen", index),
                                      params.pacer.data.layout.street_zoom)
        m = aerial_map(bank, params.pacer.data, "seen", index, params.pacer.seed, semantic_maps)
        for region in np.unique(window):  # a region (one semantic label) is painted with exactly one terrain
            assert len(np.unique(m.labels[window == region])) == 1
    with pytest.raises(ValueError, match="needs the SuReNav maps"):
        aerial_map(bank, params.pacer.data, "seen", 0, params.pacer.seed)


@pytest.mark.parametrize("zoom", [1, 2, 3])
def test_street_zoom_draws_each_map_pixel_as_a_zoom_block(zoom):
    """At zoom z a window shows ceil(size / z) map pixels, each as a z x z block: on a map whose labels count
    up row by row, the blocks' corners number the map's pixels in order."""
    counting = SemanticMap("counting", np.arange(9, dtype=np.uint8).reshape(3, 3), RasterFrame((3, 3), 1.0))
    size = 3 * zoom - (zoom > 1)  # the whole map; above zoom 1 its last blocks cropped by one pixel
    regions = semantic_map_regions([counting], size, np.random.default_rng(zoom), zoom)
    cut = 3
    assert regions.shape == (size, size)
    blocks = np.repeat(np.repeat(regions[::zoom, ::zoom], zoom, 0), zoom, 1)[:size, :size]
    np.testing.assert_array_equal(regions, blocks)
    np.testing.assert_array_equal(regions[::zoom, ::zoom], np.arange(cut * cut).reshape(cut, cut))


def test_street_windows_come_from_surenav_training_geography_one_terrain_per_label(bank, smoke_params, smoke_data):
    data = smoke_params.pacer.data
    params = with_pacer_data(smoke_params, layout=dataclasses.replace(data.layout, street_windows=1.0))
    for split, maps in (("train", "train"), ("val", "val"), ("test", "val")):  # never the evaluation tiles
        dataset = pacer_dataset(params, smoke_data, "real", split, bank)
        assert [m.name for m in dataset.street_maps] == [m.name for m in load_maps(smoke_data, maps)]
    dataset = pacer_dataset(params, smoke_data, "real", "train", bank)
    for index in range(8):
        keys = ("pacer", "real", "train", index)
        gen = rng(params.pacer.seed, *keys)
        gen.uniform()  # the street-window draw
        window = semantic_map_regions(dataset.street_maps, data.image_size, gen, data.layout.street_zoom)
        item = dataset.item(index)
        fov = item["fov_mask"]
        assert 1 <= len(np.unique(item["labels"][fov])) <= data.layout.regions[1] + 1
        assert set(item["ordering"][item["ordering"] >= 0].tolist()) >= set(np.unique(item["labels"][fov]).tolist())
        assert window.shape == item["labels"].shape
    with pytest.raises(ValueError, match="needs the SuReNav maps"):
        PacerDataset(bank, params.pacer.data, Recipe("real", "real", "seen", "realistic"), "train", 4, 0)


def test_no_street_windows_leaves_every_item_as_before(bank, smoke_params, smoke_data):
    """street_windows 0 draws nothing, so the procedural items (and every trained model) stay the same."""
    recipe = Recipe("real", "real", "seen", "realistic")
    plain = PacerDataset(bank, smoke_params.pacer.data, recipe, "train", 4, 0)
    given = PacerDataset(bank, smoke_params.pacer.data, recipe, "train", 4, 0, street_maps=load_maps(smoke_data, "train"))
    for a, b in zip(_items(plain, 4), _items(given, 4), strict=True):
        assert all(np.array_equal(a[k], b[k]) for k in a)


def test_heldout_bev_sets_stay_procedural_whatever_share_of_training_items_are_street_windows(bank, smoke_params):
    """The pair agreement's held-out BEV sets (``experiments.heldout_bev_params``) are the items a training mix
    without street windows draws: the same images and contexts, no SuReNav maps needed; nothing else changes."""
    from navlab.pacer.experiments import heldout_bev_params

    data = smoke_params.pacer.data
    streets = with_pacer_data(smoke_params, layout=dataclasses.replace(data.layout, street_windows=0.5))
    with pytest.raises(ValueError, match="needs the SuReNav maps"):
        evaluation_dataset(streets, None, "seen", "realistic", bank=bank)
    heldout = heldout_bev_params(streets)
    assert heldout == smoke_params  # street_windows back to 0, every other parameter as given
    ours, plain = (evaluation_dataset(p, None, "seen", "realistic", bank=bank) for p in (heldout, smoke_params))
    for a, b in zip(_items(ours, 4), _items(plain, 4), strict=True):
        assert all(np.array_equal(a[k], b[k]) for k in a)


def test_context_targets_rank_every_terrain_the_context_was_drawn_over(bank, smoke_params):
    """A terrain's target cost is its rank in the whole superset ordering, not among its window neighbours."""
    params = with_pacer_data(smoke_params, train_target="context", train_context="superset")
    dataset = pacer_dataset(params, None, "shuffled", bank=bank)
    wider = 0
    for item in _items(dataset, 12):
        ordering = item["ordering"][item["ordering"] >= 0]
        fov = item["fov_mask"]
        shown = np.unique(item["labels"][fov])
        assert set(shown.tolist()) <= set(ordering.tolist())
        wider += len(ordering) > len(shown)
        for t in shown:
            rank = int(np.flatnonzero(ordering == t)[0])
            np.testing.assert_allclose(item["costmap"][fov & (item["labels"] == t)], rank / max(len(ordering) - 1, 1))
    assert wider > 0  # the extras are ranked too
    in_view = _in_view(smoke_params).pacer.data
    assert max_terrains(params.pacer.data) == max_terrains(in_view) + params.pacer.data.context_extra


# --- metrics ----------------------------------------------------------------------------------------------

def test_cost_tier_proportions_on_a_hand_made_path():
    labels = np.array([[0, 1, 2], [3, 3, 3]])
    tiers = np.array([0, 1, 2, 0])
    path = np.array([[0, 0], [0, 1], [1, 2], [1, 1], [0, 2]])
    assert cost_tier_proportions(path, labels, tiers) == {"low": 0.6, "medium": 0.2, "high": 0.2}
    with pytest.raises(ValueError, match="no tier"):
        cost_tier_proportions(path, labels, np.array([0, 1, -1, 0]))
    with pytest.raises(ValueError, match="leave"):
        cost_tier_proportions(np.array([[2, 0]]), labels, tiers)


def test_margin_ranking_error_on_hand_made_costmaps():
    labels = np.array([[0, 0], [1, 1]])
    pred = np.array([[0.2, 0.4], [0.1, 0.1]])
    # pairs: same rank 0.2 vs 0.4 -> 0.2; rank-1 points cost 0.1 < 0.2 and < 0.4 -> 0.1, 0.1, 0.3, 0.3;
    # the two rank-1 points agree -> 0. Mean over the 6 pairs.
    assert margin_ranking_error(pred, labels, np.array([0, 1]), n_points=4, rng=rng(0)) == pytest.approx(1.0 / 6)
    # a costmap that follows the ordering scores 0, wherever the view is not (label -1) it is never drawn
    labels = rng(0, "labels").integers(0, 4, size=(32, 32))
    labels[:, :5] = IGNORE
    ordering = np.array([2, 0, 3, 1])
    truth = target_costmap(labels, ordering)
    noisy_outside = np.where(labels == IGNORE, 5.0, truth * 0.5 + 0.1)  # monotone inside the view
    assert margin_ranking_error(noisy_outside, labels, ordering, rng=rng(1)) == 0.0
    inverted = margin_ranking_error(1.0 - truth, labels, ordering, rng=rng(1))
    assert inverted > 0.3
    assert margin_ranking_error(1.0 - truth, labels, ordering[::-1].copy(), rng=rng(1)) == 0.0
