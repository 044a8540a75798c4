"""The PACER playground without a browser: its rules, what each choice changes, and one-line refusals.

The networks are untrained (built from the smoke profile's shapes, fixed seed): every rule here holds
for any weights, and the trained ones are what the notebook smoke run and the browser test load.
"""

from __future__ import annotations

import copy
import itertools

import numpy as np
import pytest
import torch

from navlab.core.io import DataError
from navlab.core.params import ParamsError
from navlab.pacer.baselines.sterling import SterlingEncoder
from navlab.pacer.bev import fov_mask
from navlab.pacer.evaluate import costmap_over_map
from navlab.pacer.model import build_model
from navlab.pacer.preferences import environment_tiers
from navlab.pacer.terrain import load_terrain_bank
from navlab.viz.playground.common import ERROR_MARK, Memo, UserError, one_line
from navlab.viz.playground.pacer import (
    PacerPlayground,
    PacerView,
    find_cycle,
    ordering_from_pairs,
    outcome_figure,
    pacer_costmap,
)


@pytest.fixture(scope="module")
def parts(smoke_data, smoke_params):
    pacer = smoke_params.pacer
    with torch.random.fork_rng():
        torch.manual_seed(0)
        model = build_model(pacer.model, context_pairs=pacer.data.n_pairs).eval()
        sterling = pacer.baselines.sterling
        encoder = SterlingEncoder(sterling.channels, sterling.embed_dim, pacer.baselines.patch_size).eval()
    return smoke_params, smoke_data, load_terrain_bank(smoke_data, pacer.data), model, encoder


@pytest.fixture
def playground(parts):
    torch.set_num_threads(parts[0].pacer.train.threads)  # as PacerPlayground.load does (conftest resets it)
    played = PacerPlayground(*parts)
    played.choose_map("seen 0")
    return played


def realistic(playground) -> list[int]:
    """The chosen map's terrains, most preferred first by the realistic ordering."""
    terrains = playground.amap.terrains
    return terrains[np.argsort(playground.bank.realistic_rank[terrains])].tolist()


def test_adding_a_pair_changes_the_costmap(playground):
    playground.clear()
    before = playground.outcome()
    best, worst = realistic(playground)[0], realistic(playground)[-1]
    playground.add_pair(worst, best)
    after = playground.outcome()
    assert np.abs(after.costmaps["PACER"] - before.costmaps["PACER"]).max() > 1e-4
    assert not np.array_equal(after.context, before.context)
    order = after.ordering.tolist()
    assert order.index(worst) < order.index(best)  # the tiers follow the pair, the window oracle with them
    assert np.abs(after.costmaps["Window oracle"] - before.costmaps["Window oracle"]).max() > 0.1


def test_inverting_flips_the_tier_ordering(playground):
    chain = realistic(playground)[: playground.data.n_pairs + 1]
    playground.set_context(", ".join(f"{playground.name(a)} > {playground.name(b)}" for a, b in itertools.pairwise(chain)))
    before = playground.outcome()
    playground.invert()
    after = playground.outcome()
    position = {t: k for k, t in enumerate(after.ordering.tolist())}
    assert [position[t] for t in chain] == sorted((position[t] for t in chain), reverse=True)
    if len(chain) == len(before.ordering):  # the chain names every terrain of the map: a full reversal
        assert after.ordering.tolist() == before.ordering[::-1].tolist()
        tiers = environment_tiers(before.ordering, len(playground.bank)), environment_tiers(after.ordering,
                                                                                            len(playground.bank))
        assert (tiers[0][chain[0]], tiers[1][chain[0]]) == (0, 2)
    assert not np.array_equal(after.costmaps["PACER"], before.costmaps["PACER"])
    playground.invert()  # and back: the cached outcome, not a recomputation
    hits = playground.outcomes.hits
    assert playground.outcome() is before and playground.outcomes.hits == hits + 1


def test_ordering_from_pairs_follows_pairs_then_the_realistic_rank():
    rank = np.arange(10)
    assert ordering_from_pairs([1, 2, 3], [], rank).tolist() == [1, 2, 3]
    assert ordering_from_pairs([1, 2, 3], [(3, 1)], rank).tolist() == [2, 3, 1]
    assert ordering_from_pairs([1, 3], [(3, 7), (7, 1)], rank).tolist() == [3, 1]  # through a terrain off the map
    assert find_cycle([(1, 2), (2, 3)], 3, 1) == [3, 1, 2, 3]
    assert find_cycle([(1, 2)], 1, 3) is None


def test_reorder_remove_and_the_network_s_pair_count(playground):
    a, b, c, d = (int(t) for t in playground.candidates()[:4])
    playground.set_context(f"{playground.name(a)} > {playground.name(b)}, {playground.name(c)} over {playground.name(d)}")
    first = playground.context()
    playground.move_pair(1, -1)
    assert playground.pairs == ((c, d), (a, b))
    h = first.shape[0] // playground.data.n_pairs  # each pair's 3 channels move with it
    assert np.array_equal(playground.context()[:h], first[h:2 * h])
    playground.remove_pair(0)
    assert playground.pairs == ((a, b),)
    assert np.array_equal(playground.context()[h:2 * h], playground.context()[:h])  # one pair, repeated
    playground.add_pair(c, d)
    playground.add_pair(a, c)
    with pytest.raises(UserError, match=f"reads {playground.data.n_pairs} pairs"):
        playground.add_pair(d, b)


@pytest.mark.parametrize(("action", "message"), [
    (lambda p, a, b: p.add_pair(a, a), "names one terrain twice"),
    (lambda p, a, b: (p.add_pair(a, b), p.add_pair(b, a)), "closes the cycle {b} > {a} > {b}"),
    (lambda p, a, b: (p.pick(b), p.pick(b)), "names one terrain twice"),
    (lambda p, a, b: p.choose_map(""), "choose a map"),
    (lambda p, a, b: p.choose_map(None), "choose a map"),
    (lambda p, a, b: p.choose_map("unseen 99"), "choose a map"),
    (lambda p, a, b: p.set_context("grass > moon dust"), "'moon dust' is not a seen terrain"),
    (lambda p, a, b: p.remove_pair(5), "no pair 6"),
])
def test_bad_input_is_one_line_in_the_widget(playground, action, message):
    """What the view shows for a refused choice: one line (marked), no traceback, the drawing unchanged."""
    view = PacerView(playground, "seen 0", "uninformative")
    drawn = view.result.value
    a, b = (int(t) for t in playground.candidates()[:2])
    pairs = playground.pairs
    assert not view.act(action, playground, a, b)
    assert view.message.kind == "error"
    assert message.format(a=playground.name(a), b=playground.name(b)) in view.message.text
    assert "\n" not in view.message.text and "Traceback" not in view.message.widget.value
    assert view.message.widget.value.count(ERROR_MARK) == 1
    assert view.result.value == drawn
    assert playground.pairs in (pairs, ((a, b),))  # a refused pair is not added


def test_widgets_drive_the_playground(playground):
    """Clicks on the view's own buttons and menu, as the browser test makes them in JupyterLab."""
    view = PacerView(playground, "seen 0", "operator")
    assert view.message.kind == "info" and len(playground.pairs) > 0
    buttons = {b.description: b for b in view.widget.children[3].children}
    shown = view.result.value
    buttons["uninformative"].click()
    assert playground.pairs == () and view.result.value != shown
    cards = view.gallery.children
    cards[0].children[1].click()
    assert playground.pending is not None and cards[0].children[1].button_style == "warning"
    cards[1].children[1].click()
    assert len(playground.pairs) == 1 and len(view.pair_rows.children) == 1
    one_pair = view.result.value
    buttons["invert"].click()
    assert view.result.value != one_pair and view.message.kind == "info"
    view.maps.value = ""  # the menu's empty entry
    assert view.message.kind == "error" and "choose a map" in view.message.text
    view.maps.value = "unseen 1"
    assert playground.choice == ("unseen", 1) and playground.pairs == ()
    assert "your 1 pair(s) named the other group's terrains and were cleared" in view.message.text  # said
    labels = [c.children[1].description for c in view.gallery.children]
    assert set(labels) == {playground.name(t) for t in playground.candidates()} and len(set(labels)) == len(labels)
    for card in view.gallery.children:  # each button wide enough for its whole name (was "mono_…" three times)
        button = card.children[1]
        assert int(button.layout.width.removesuffix("px")) >= 8 * len(button.description) + 16


def test_a_refused_pair_leaves_no_terrain_highlighted(playground):
    view = PacerView(playground, "seen 0", "uninformative")
    cards = view.gallery.children
    cards[0].children[1].click()
    assert cards[0].children[1].button_style == "warning"
    cards[0].children[1].click()  # the same terrain again: refused, and the pick is cleared
    assert view.message.kind == "error" and playground.pending is None
    assert all(card.children[1].button_style != "warning" for card in cards)


def test_the_result_figure_has_a_cost_colour_bar(playground):
    fig = outcome_figure(playground.outcome(), "seen 0")
    bars = [ax for ax in fig.axes if ax.get_ylabel().startswith("cost (0 cheap")]
    assert len(bars) == 1 and len(fig.axes) == 2 + len(playground.outcome().costmaps)


def test_pacer_costmap_matches_costmap_over_map(playground, parts):
    model = parts[3]
    amap = playground.amap
    mask = fov_mask(playground.data.image_size, playground.data.camera.near_width)
    context = playground.context()
    expected = costmap_over_map(model, torch.as_tensor(amap.image), torch.as_tensor(context), mask).numpy()
    np.testing.assert_allclose(pacer_costmap(model, amap.image, context, mask), expected, atol=1e-5)
    fast = copy.deepcopy(model).to(memory_format=torch.channels_last)  # as PacerPlayground.load runs it
    # another convolution algorithm sums in another order: float32 rounding, 1e-5 here, far below a cost step
    np.testing.assert_allclose(pacer_costmap(fast, amap.image, context, mask), expected, atol=1e-4)


def test_missing_models_are_named_at_once_with_one_command(smoke_data, tmp_path):
    """Every stage the playground reads, missing, named in one line with the command for this profile and
    these folders, and the smoke path (was: one stage per try, the command without --profile or folders)."""
    with pytest.raises(DataError, match=(
            rf"needs pacer_phase1, pacer_phase2, pacer_phase3, pacer_sterling \(profile smoke, not in {tmp_path}\): "
            rf"build them with `python -m navlab artifacts build --profile smoke --data-dir {smoke_data} "
            rf"--artifacts-dir {tmp_path} --only pacer_phase1 --only pacer_phase2 --only pacer_phase3 --only "
            rf"pacer_sterling`; or, for a first look in minutes, the smoke profile")) as refused:
        PacerPlayground.load("smoke", smoke_data, tmp_path)
    assert "\n" not in str(refused.value)


def test_memo_keeps_the_most_recent_and_errors_are_one_line():
    calls = []
    memo = Memo(lambda k: calls.append(k) or k * 2, size=2)
    assert [memo(1), memo(2), memo(1), memo(3), memo(2)] == [2, 4, 2, 6, 4]
    assert calls == [1, 2, 3, 2] and (memo.hits, memo.misses) == (1, 4)
    assert one_line(UserError("refused\nmore")) == "refused"
    assert one_line(KeyError("x")) == "KeyError: 'x'"


@pytest.mark.parametrize("map_choice, context, message", [
    ("nope", "operator", r"notebook parameter map_choice = 'nope': choose a map: 'seen k' or 'unseen k' with k in 0\.\."),
    ("seen 0", "lava > grass", r"notebook parameter context = 'lava > grass': terrain 'lava' is not a seen terrain"),
])
def test_a_bad_notebook_scenario_stops_with_one_line_naming_the_parameter(parts, map_choice, context, message):
    """papermill's ``-p map_choice nope``: a ParamsError (shown as one line by the notebook) naming the
    parameter, its value and the choices, not a later cell's traceback on a map never chosen."""
    with pytest.raises(ParamsError, match=message):
        PacerView(PacerPlayground(*parts), map_choice, context)

