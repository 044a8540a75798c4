"""PACER map-window metrics, chain contexts and checkpoint selection on map windows (issue 24)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
import torch

from navlab.core.params import load_params
from navlab.core.seeding import rng
from navlab.pacer.checkpoints import read_summary
from navlab.pacer.context import chain_pairs
from navlab.pacer.map_windows import METRICS, MapWindow, map_windows, window_counts, window_scores
from navlab.pacer.preferences import IGNORE, implied_pairs
from navlab.pacer.train import PhaseRun, Selection, improves, run_key, train_phase
from test_pacer_model import TinyTerrainSet


def test_implied_pairs_follow_transitivity_and_leave_the_rest_open():
    terrains = np.array([1, 2, 3, 4])
    decided = implied_pairs(terrains, np.array([[1, 2], [2, 3], [9, 4], [4, 9]][:2]))
    assert decided[0, 1] and decided[1, 2] and decided[0, 2]  # 1 > 2 > 3 decides 1 > 3
    assert not decided[:, 3].any() and not decided[3].any() and not decided[2, 0]
    via_other = implied_pairs(np.array([1, 4]), np.array([[1, 7], [7, 4]]))  # chains through a terrain not listed
    assert via_other[0, 1] and not via_other[1, 0]


@pytest.mark.parametrize("count", [2, 3, 4, 5, 6])
def test_chain_pairs_are_consecutive_in_the_ordering_and_decide_its_terrains(count):
    ordering = np.array([7, 3, 5, 1, 9, 2])[:count]
    for k in range(20):
        pairs = chain_pairs(ordering, 3, rng(0, "chain", k))
        rank = {int(t): r for r, t in enumerate(ordering)}
        assert pairs.shape == (3, 2) and all(rank[int(a)] < rank[int(b)] for a, b in pairs)
        named = np.unique(pairs)
        assert len(named) == min(count, 4)
        decided = implied_pairs(named[np.argsort([rank[int(t)] for t in named])], pairs)
        assert decided[np.triu_indices(len(named), 1)].all()  # a total order of the terrains it names


def _window(ordering=(4, 6, 8), pairs=((4, 6), (4, 6), (4, 6))) -> MapWindow:
    labels = np.full((8, 8), IGNORE, dtype=np.int64)
    labels[2:, 0:3], labels[2:, 3:6], labels[2:, 6:8] = 8, 4, 6
    return MapWindow(np.zeros((3, 8, 8), np.float32), labels, np.asarray(ordering, dtype=np.int64),
                     np.zeros((9, 4, 2), np.float32), np.asarray(pairs, dtype=np.int64))


def test_window_counts_of_a_perfect_and_a_reversed_costmap():
    window = _window()
    rank = {4: 0.0, 6: 0.5, 8: 1.0}
    perfect = np.vectorize(lambda v: rank.get(int(v), 0.0), otypes=[np.float32])(window.labels)
    counts = window_counts(perfect, window, cost_scale=10.0).reshape(-1, 2)
    values = dict(zip(METRICS, counts))
    assert values["all_pairs"].tolist() == [3, 3]
    assert values["decided"].tolist() == [1, 1] and values["open"].tolist() == [2, 2]  # only 4 > 6 is named
    assert values["auc"].tolist() == [3, 3]
    # tiers of (4, 6, 8): low 4, medium 6, high 8; rest mean cost over 12 + 18 pixels
    rest = (12 * 0.5 + 18 * 1.0) / 30
    assert values["tier_ratio"] == pytest.approx([1 + 10 * rest, 1.0])
    reversed_ = window_counts(1.0 - perfect, window, cost_scale=10.0).reshape(-1, 2)
    assert reversed_[0].tolist() == [0, 3] and reversed_[3].tolist() == [0, 3]
    flat = window_counts(np.full((8, 8), 0.3, np.float32), window, cost_scale=10.0).reshape(-1, 2)
    assert flat[3].tolist() == [1.5, 3] and flat[4, 0] == pytest.approx(flat[4, 1])  # ties: AUC 1/2, ratio 1


class ConstantModel(torch.nn.Module):
    def __init__(self, costs):
        super().__init__()
        self.costs = costs

    def costmap(self, image, context):
        return torch.as_tensor(self.costs[: len(image)])


def test_window_scores_pool_windows_with_intervals():
    windows = [_window(), _window((8, 6, 4))]
    rank = {4: 0.0, 6: 0.5, 8: 1.0}
    perfect = np.vectorize(lambda v: rank.get(int(v), 0.0), otypes=[np.float32])(windows[0].labels)
    scores = window_scores(ConstantModel(np.stack([perfect, perfect])), windows, 10.0, seed=0)
    assert scores.values["all_pairs"] == pytest.approx(0.5) and scores.counts["all_pairs"] == 6
    assert scores.values["auc"] == pytest.approx(0.5) and scores.counts["tier_ratio"] == 2
    lo, hi = scores.cis["all_pairs"]
    assert 0.0 <= lo <= 0.5 <= hi <= 1.0


def test_map_windows_come_from_training_geography_and_are_deterministic(smoke_params, smoke_data):
    a = map_windows(smoke_params, smoke_data, "val", "seen", ("realistic", "inverted"), 4)
    b = map_windows(smoke_params, smoke_data, "val", "seen", ("realistic", "inverted"), 4)
    size = smoke_params.pacer.data.image_size
    for x, y in zip(a, b):
        assert np.array_equal(x.image, y.image) and np.array_equal(x.labels, y.labels)
        assert x.image.shape == (3, size, size) and (x.image[:, x.labels == IGNORE] == 0).all()
        shown = np.unique(x.labels[x.labels != IGNORE])
        assert np.isin(shown, x.ordering).all() and np.isin(np.unique(x.pairs), x.ordering).all()
    assert a[0].ordering.tolist() != a[1].ordering.tolist() or len(a[0].ordering) == 1  # realistic, then inverted
    other = map_windows(smoke_params, smoke_data, "test", "seen", ("realistic",), 1)
    assert not np.array_equal(other[0].labels, a[0].labels)  # report windows are not the selection windows


def test_improves_selects_on_the_score_with_the_loss_breaking_ties():
    best = {"epoch": 1, "val_loss": 0.5, "select_score": 0.7}

    def row(score, val):
        return {"epoch": 2, "val_loss": val, "select_score": score}

    assert improves("map_windows", row(0.8, 0.9), best) and not improves("map_windows", row(0.6, 0.1), best)
    assert improves("map_windows", row(0.7, 0.4), best) and not improves("map_windows", row(0.7, 0.6), best)
    assert improves("val_loss", row(0.1, 0.4), best) and not improves("val_loss", row(0.99, 0.6), best)
    assert not improves("map_windows", row(float("nan"), 0.1), best)
    nan_best = {**best, "select_score": float("nan")}  # no window showed two terrains: the loss decides
    assert improves("map_windows", row(float("nan"), 0.4), nan_best) and improves("map_windows", row(0.1, 0.9), nan_best)
    with pytest.raises(ValueError, match="select_on = 'loss'.*map_windows, val_loss"):
        improves("loss", row(0.5, 0.5), best)


def _tiny_windows(count: int) -> list[MapWindow]:
    items = [TinyTerrainSet(count, seed=5)[i] for i in range(count)]
    return [MapWindow(it["image"] * it["fov_mask"], np.where(it["fov_mask"], it["labels"], IGNORE),
                      np.asarray(it["ordering"], dtype=np.int64), it["context"], np.array([[0, 1], [1, 2], [0, 2]]))
            for it in items]


def test_training_selects_the_epoch_of_best_map_window_score(tmp_path):
    smoke = load_params("smoke").pacer
    cfg = dataclasses.replace(smoke.train, examples_per_epoch=8, batch_size=4, threads=1, lr=0.05, patience=3)
    windows = _tiny_windows(6)
    train, val = TinyTerrainSet(16), TinyTerrainSet(4, seed=1)
    with pytest.raises(ValueError, match="needs validation map windows"):
        train_phase(smoke.model, cfg, [train], [val], tmp_path / "none", PhaseRun("phase1", epochs=1, seed=0),
                    progress=False)
    train_phase(smoke.model, cfg, [train], [val], tmp_path, PhaseRun("phase1", epochs=4, seed=0), progress=False,
                selection=Selection(windows))
    log = np.loadtxt(tmp_path / "val_loss.tsv", skiprows=1, ndmin=2)
    summary = read_summary(tmp_path)
    best = max(range(len(log)), key=lambda k: (log[k, 3], -log[k, 2]))
    assert summary["select_on"] == "map_windows" and summary["best_epoch"] == best + 1
    assert summary["best_select_score"] == pytest.approx(log[best, 3], abs=1e-6)
    # what the phase cost, for issue 24's budget: positive time, a process's memory, the settings it ran with
    assert summary["train_seconds"] > 0 and summary["peak_rss_mib"] > 0
    assert (summary["threads"], summary["workers"]) == (cfg.threads, cfg.workers)
    assert np.isfinite(log[:, 3]).all() and ((0 <= log[:, 3]) & (log[:, 3] <= 1)).all()



def test_a_retrained_folder_is_byte_identical_but_for_its_cost_file(tmp_path):
    """The phase folder is a DVC output: a timing inside a hashed file made every rebuild a new output (and every
    stage downstream stale). Two runs of one key write the same bytes; only ``training_cost.json``, which
    ``.dvcignore`` names, differs, and it holds each epoch's time."""
    smoke = load_params("smoke").pacer
    cfg = dataclasses.replace(smoke.train, examples_per_epoch=8, batch_size=4, threads=1, lr=0.05, patience=3)
    windows = _tiny_windows(4)
    for run in ("a", "b"):
        train_phase(smoke.model, cfg, [TinyTerrainSet(16)], [TinyTerrainSet(4, seed=1)], tmp_path / run,
                    PhaseRun("phase1", epochs=2, seed=0), progress=False, selection=Selection(windows))
    files = sorted(p.name for p in (tmp_path / "a").iterdir())
    assert "training_cost.json" in files and "train_seconds" not in (tmp_path / "a" / "summary.json").read_text()
    for name in files:
        if name != "training_cost.json":
            assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name
    cost = json.loads((tmp_path / "a" / "training_cost.json").read_text())
    assert sorted(cost["epoch_seconds"]) == ["1", "2"] and cost["train_seconds"] > 0
    assert "training_cost.json" in (Path(__file__).resolve().parents[1] / ".dvcignore").read_text().split()

def test_the_run_key_includes_the_selection_and_the_thread_count_not_the_workers():
    smoke = load_params("smoke").pacer
    keys = {run_key(smoke.model, dataclasses.replace(smoke.train, **change), seed=0, phase="phase1", epochs=1,
                    sizes=[1], init_from=None, code="c")
            for change in ({}, {"select_on": "val_loss"}, {"select_windows": 3}, {"threads": 2})}
    assert len(keys) == 4  # a thread count sums convolutions in its own order: its checkpoint is its own
    assert run_key(smoke.model, dataclasses.replace(smoke.train, workers=3), seed=0, phase="phase1", epochs=1,
                   sizes=[1], init_from=None, code="c") == run_key(smoke.model, smoke.train, seed=0, phase="phase1",
                                                                   epochs=1, sizes=[1], init_from=None, code="c")


def test_select_on_is_validated_when_params_load(tmp_path):
    text = Path("params.yaml").read_text()
    assert "    select_on: map_windows" in text
    bad = tmp_path / "params.yaml"
    bad.write_text(text.replace("    select_on: map_windows", "    select_on: best_auc", 1))
    with pytest.raises(ValueError, match="select_on"):
        load_params("smoke", path=bad)
