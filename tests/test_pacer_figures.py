"""PACER's figure runs and figures (notebooks 01-03 call them; no figure is assembled in a notebook cell)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest
import torch

from navlab.pacer.aerial import aerial_maps
from navlab.pacer.experiments import (
    FIGURE_PREFERENCES,
    Agreement,
    bev_context_costmaps,
    context_runs,
    ground_truth_method,
    map_context,
    navigation_rows,
    uniform_method,
)
from navlab.pacer.terrain import load_terrain_bank
from navlab.viz.pacer import (
    agreement_figure,
    bev_contexts_figure,
    context_paths_figure,
    method_paths_figure,
    save,
)
from navlab.viz.report import show


def path_cost(cost: np.ndarray, cells: np.ndarray) -> float:
    """A path's cost as ``grid_astar`` counts it: each move the mean of its two cells' costs times its length."""
    a, b = cells[:-1], cells[1:]
    return float(np.sum(0.5 * (cost[a[:, 0], a[:, 1]] + cost[b[:, 0], b[:, 1]]) * np.hypot(*(b - a).T)))


@pytest.fixture(scope="module")
def bank(smoke_data, smoke_params):
    return load_terrain_bank(smoke_data, smoke_params.pacer.data)


@pytest.fixture(scope="module")
def unseen_runs(bank, smoke_params, smoke_data):
    P = smoke_params.pacer
    amap = aerial_maps(smoke_params, smoke_data, "unseen", bank)[0]
    return amap, context_runs(ground_truth_method(), amap, bank, P.data, FIGURE_PREFERENCES, P.seed,
                              P.evaluation.cost_scale)


def test_each_context_run_plans_the_cheapest_path_under_its_own_costs(unseen_runs, bank, smoke_params):
    amap, runs = unseen_runs
    scale = smoke_params.pacer.evaluation.cost_scale
    assert [r.preference for r in runs] == list(FIGURE_PREFERENCES)
    for run in runs:
        assert tuple(run.path[0]) == tuple(amap.start) and tuple(run.path[-1]) == tuple(amap.goal)
        own = path_cost(1.0 + scale * run.cost, run.path)
        # no other context's path is cheaper under this context's costs (A* is optimal on its own costmap)
        assert all(own <= path_cost(1.0 + scale * run.cost, other.path) + 1e-9 for other in runs)
    # four distinct preferences: the two random orderings repeat neither each other nor realistic / inverted
    orderings = [tuple(r.ordering) for r in runs]
    assert len(set(orderings)) == 4 or len(amap.terrains) < 3
    assert orderings[1] == orderings[0][::-1]  # inverted is realistic reversed
    # realistic and inverted are the draw the tables make for the map (map_context's index 0)
    for run in runs[:2]:
        np.testing.assert_array_equal(run.context, map_context(bank, smoke_params.pacer.data, amap, run.preference,
                                                               True, smoke_params.pacer.seed, 0)[1])
    # inverted is realistic reversed: the ground truth's costs of the two add up to a constant over the map's terrains
    on_map = np.isin(amap.labels, amap.terrains)
    total = runs[0].cost + runs[1].cost
    assert np.ptp(total[on_map]) < 1e-6


def test_the_context_paths_figure_has_the_map_and_a_context_and_costmap_per_run(unseen_runs, tmp_path):
    amap, runs = unseen_runs
    fig = context_paths_figure(amap, runs, "aerial map (unseen terrains)")
    assert len(fig.axes) == 1 + 2 * len(runs)
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert legend == ["realistic context", "inverted context", "random context 1", "random context 2"]
    save(fig, tmp_path / "fig5.png")
    assert (tmp_path / "fig5.png").stat().st_size > 0 and not matplotlib.pyplot.fignum_exists(fig.number)


def test_method_paths_figure_draws_every_method_on_the_first_maps(bank, smoke_params, smoke_data):
    P = smoke_params.pacer
    maps = aerial_maps(smoke_params, smoke_data, "seen", bank)
    methods = {"Uniform costmap (chance)": (uniform_method(), True), "Ground truth": (ground_truth_method(), True)}
    result = navigation_rows(maps, methods, bank, P.data, "realistic", P.evaluation.cost_scale, P.seed, 1)
    fig = method_paths_figure(maps, result.paths, "seen map", shown=2)
    assert len(fig.axes) == min(2, len(maps))
    for ax in fig.axes:
        assert [t.get_text() for t in ax.get_legend().get_texts()] == list(methods)


def test_bev_contexts_pick_one_item_with_enough_terrains_and_cost_it_per_context(bank, smoke_params, smoke_data):
    from navlab.pacer.datasets import evaluation_dataset
    from navlab.pacer.experiments import heldout_bev_params

    class Echo(torch.nn.Module):  # a costmap read straight off the image: shows which item each row took
        def costmap(self, image, context):
            return image[:, 0]

    sets = {p: evaluation_dataset(heldout_bev_params(smoke_params), smoke_data, "seen", p, bank=bank)
            for p in ("realistic", "inverted")}
    costed = bev_context_costmaps(Echo(), sets, min_terrains=2)
    (_, first, cost_a), (_, second, _) = costed
    assert len(np.unique(first["labels"][first["fov_mask"]])) >= 2
    np.testing.assert_array_equal(first["image"], second["image"])  # the same image under both contexts
    np.testing.assert_array_equal(cost_a, first["image"][0].numpy())
    assert len(bev_contexts_figure(costed).axes) == 8


def test_agreement_figure_bars_every_model_and_set_with_its_interval():
    sets = [(e, p) for e in ("seen", "unseen") for p in ("realistic", "inverted")]
    agreement = {(m, e, p, c): Agreement(0.5 + 0.1 * k, 10, (0.4, 0.9))
                 for k, m in enumerate(("D_real", "D_synthetic")) for e, p in sets for c in ("in_view", "superset")}
    fig = agreement_figure(agreement, ["D_real", "D_synthetic"], ["in_view", "superset"])
    assert len(fig.axes) == 2
    heights = sorted(round(bar.get_height(), 6) for bar in fig.axes[0].patches)
    assert heights == [0.5] * 4 + [0.6] * 4


def test_show_displays_the_reports_markdown_and_each_figure(tmp_path, monkeypatch):
    import IPython.display

    shown = []
    monkeypatch.setattr(IPython.display, "display", lambda *objs: shown.extend(objs))
    (tmp_path / "t.md").write_text("| a |\n|---|\n| 1 |\n", encoding="utf8")
    matplotlib.pyplot.figure().savefig(tmp_path / "f.png")
    show(tmp_path / "t.json", [tmp_path / "f.png"])
    assert shown[0].data == "| a |\n|---|\n| 1 |\n"
    assert isinstance(shown[-1], IPython.display.Image)
