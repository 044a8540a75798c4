"""Training Psi_G through the differentiable graph A* (SuReNav Sec. IV-D): loss Eq. 12-14, one step,
resume after a kill, and a synthetic case the estimator must learn."""

import dataclasses

import numpy as np
import pytest
import torch

from navlab.core.labels import label_id
from navlab.core.params import load_params
from navlab.graphs.region_graph import build_region_graph
from navlab.search.graph_astar import graph_astar
from navlab.surenav import train as training
from navlab.surenav.loss import batch_loss, relaxation_loss, sample_weights
from navlab.surenav.model.estimator import build_estimator
from navlab.surenav.train import evaluate, load_estimator, plan_batch, train_estimator
from navlab.surenav.training_data import make_sample
from synthetic_city import ZEBRAS, zebra_band

SIDEWALK, CROSSWALK, GRASS = label_id("sidewalk"), label_id("crosswalk"), label_id("grass")
BLOCK = 3


def crossing_graph(start_col: int, goal_col: int):
    """``zebra_band``'s region graph with start and goal on opposite sidewalks."""
    smap, sp = zebra_band(block=BLOCK)
    graph = build_region_graph(sp, smap.labels, smap.frame, tau=1.0)
    rows = smap.labels.shape[0] // BLOCK
    centre = lambda r, c: np.array([(c + 0.5) * BLOCK, (r + 0.5) * BLOCK])
    return graph.with_endpoints(centre(0, start_col), centre(rows - 1, goal_col))


def crosswalk_route_costs(start_col: int, goal_col: int) -> list[float]:
    """The expert's route cost through each crosswalk column alone (the others and the grass blocked)."""
    graph = crossing_graph(start_col, goal_col)
    column = graph.centroid[:, 0] // BLOCK
    costs = []
    for zebra in ZEBRAS:
        blocked = (graph.node_label == GRASS) | ((graph.node_label == CROSSWALK) & (column != zebra))
        costs.append(graph_astar(graph, graph.start_node, graph.goal_node, blocked=blocked).cost)
    return costs


def crossing_sample(start_col: int, goal_col: int, model_params):
    """The expert always crosses on a crosswalk (grass is never relaxed), however long the detour."""
    graph = crossing_graph(start_col, goal_col)
    expert = graph_astar(graph, graph.start_node, graph.goal_node, blocked=graph.node_label == GRASS)
    relaxed = expert.nodes[graph.node_label[expert.nodes] != SIDEWALK]
    return make_sample(graph, relaxed, model_params, f"crossing/{start_col}-{goal_col}")


@pytest.fixture(scope="module")
def settings():
    p = load_params("smoke").surenav
    model = dataclasses.replace(p.model, window_margin_m=100.0, walk_steps=4)
    train = dataclasses.replace(p.train, epochs=2, batch_size=4, lr=0.01)
    return model, train


def one_route_pairs(n: int, seed: int = 0) -> list[tuple[int, int]]:
    """``n`` (start, goal) columns whose best crosswalk route is unique by a clear margin: with two routes of
    equal length, float rounding in the learned costs (which differs between CPUs and thread counts)
    would pick the expert's route, and no test could assert which."""
    gen, pairs = np.random.default_rng(seed), []
    while len(pairs) < n:
        a, b = (int(c) for c in gen.integers(0, 12, size=2))
        costs = crosswalk_route_costs(a, b)
        if abs(costs[0] - costs[1]) > 0.5 * BLOCK:
            pairs.append((a, b))
    return pairs


def long_detour(start_col: int, goal_col: int) -> bool:
    """The expert's crosswalk route is at least 1.5x the straight walk across the grass: only a grass cost
    learned well above the crosswalk's keeps the plan on the crosswalk here."""
    graph = crossing_graph(start_col, goal_col)
    straight = graph_astar(graph, graph.start_node, graph.goal_node).cost
    return min(crosswalk_route_costs(start_col, goal_col)) >= 1.5 * straight


def split_pairs() -> tuple[list, list, list]:
    """12 crossings to train on, 4 to select the checkpoint, 4 held out; the last two sets hold two long
    detours each, so neither selection nor the assertion is saturated by easy crossings."""
    pairs = one_route_pairs(40)
    hard = [p for p in pairs if long_detour(*p)]
    easy = [p for p in pairs if p not in hard]
    val, held_out = hard[:2] + easy[:2], hard[2:4] + easy[2:4]
    train = [p for p in pairs if p not in val + held_out][:12]
    return train, val, held_out


@pytest.fixture(scope="module")
def samples(settings):
    """Train (12), validation (4), held out (4): 20 tie-free crossings, in that order."""
    return [crossing_sample(a, b, settings[0]) for part in split_pairs() for a, b in part]


def test_fixture_routes_have_no_ties_and_the_held_out_set_has_long_detours():
    assert crosswalk_route_costs(10, 2)[0] == pytest.approx(crosswalk_route_costs(10, 2)[1])  # the old tie
    train, val, held_out = split_pairs()
    for a, b in train + val + held_out:
        c = crosswalk_route_costs(a, b)
        assert abs(c[0] - c[1]) > 0.5 * BLOCK
    assert sum(long_detour(*p) for p in held_out) == 2 and not set(train) & set(val + held_out)


def test_loss_eq12_by_hand_and_sample_weight_eq14():
    v = torch.tensor([[1.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]])
    target = torch.tensor([[1, 0, 1, 1], [0, 0, 0, 0]], dtype=torch.bool)
    # row 0: one false positive (node 1), two false negatives (2, 3), |v*| = 3
    torch.testing.assert_close(relaxation_loss(v, target, 0.3, 0.7), torch.tensor([(0.3 + 1.4) / 4, 0.0]))
    w = sample_weights(v, target, gamma=0.5)
    torch.testing.assert_close(w, torch.tensor([min(1.0, (1.5 / 4) ** 0.5), 0.0]))
    assert not w.requires_grad
    # false positives counted on the plan (path ∩ R_soft, here node 0 only): node 1 was explored, not crossed
    planned = torch.tensor([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]])
    torch.testing.assert_close(relaxation_loss(v, target, 0.3, 0.7, planned), torch.tensor([1.4 / 4, 0.0]))


def test_sample_targets_are_the_crossing_regions(samples):
    s = samples[0]
    assert s.dropped == 0 and s.target.sum() == 2  # two band rows, one crosswalk superpixel each
    assert s.data.soft.numpy()[s.target].all()


def test_one_training_step_lowers_the_loss_on_a_fixed_batch(settings, samples):
    model_params, train = settings
    torch.manual_seed(0)
    model = build_estimator(model_params).train()
    optimiser = torch.optim.AdamW(model.parameters(), lr=0.05)
    batch = samples[:8]
    _, v, target = plan_batch(model, batch, train.temperature)
    before = batch_loss(v, target, train)
    optimiser.zero_grad()
    before.backward()
    grads = [p.grad for p in model.parameters() if p.grad is not None]
    assert grads and any(float(g.abs().sum()) > 0 for g in grads)
    optimiser.step()
    _, v, target = plan_batch(model, batch, train.temperature)
    assert float(batch_loss(v, target, train).detach()) < float(before.detach())


def test_killed_training_resumes_to_the_same_weights(settings, samples, tmp_path, monkeypatch):
    model_params, train = settings
    train_set, val_set = samples[:8], samples[8:12]
    whole = torch.load(train_estimator(train_set, val_set, model_params, train, tmp_path / "whole", seed=3,
                                       progress=False), weights_only=False)
    real_write = training._write_log

    def killed(rows, path):
        real_write(rows, path)
        raise KeyboardInterrupt  # killed right after epoch 1's checkpoint

    monkeypatch.setattr(training, "_write_log", killed)
    with pytest.raises(KeyboardInterrupt):
        train_estimator(train_set, val_set, model_params, train, tmp_path / "killed", seed=3, progress=False)
    assert (tmp_path / "killed" / "checkpoint.pt").is_file() and not (tmp_path / "killed" / "model.pt").exists()
    monkeypatch.setattr(training, "_write_log", real_write)
    resumed = torch.load(train_estimator(train_set, val_set, model_params, train, tmp_path / "killed", seed=3,
                                         progress=False), weights_only=False)
    assert [r["epoch"] for r in resumed["log"]] == [1, 2]
    assert resumed["best_epoch"] == whole["best_epoch"] == 1 + int(np.argmax([r["val_iou"] for r in whole["log"]]))
    for name, value in whole["weights"].items():
        assert torch.equal(value, resumed["weights"][name]), name
    # a different key (another seed) never resumes this run's checkpoint
    other = torch.load(train_estimator(train_set, val_set, model_params, train, tmp_path / "killed", seed=4,
                                       progress=False), weights_only=False)
    assert any(not torch.equal(v, other["weights"][k]) for k, v in whole["weights"].items())


def test_learns_to_relax_the_label_the_expert_always_relaxes(settings, samples, tmp_path):
    """Untrained, the plan cuts straight across the grass; trained, it takes the crosswalks."""
    model_params, train = settings
    train = dataclasses.replace(train, epochs=20)
    held_out = samples[16:]  # never seen in training or checkpoint selection
    torch.manual_seed(0)
    _, iou_before = evaluate(build_estimator(model_params), held_out, train)
    model = load_estimator(train_estimator(samples[:12], samples[12:16], model_params, train, tmp_path, seed=0,
                                           progress=False))
    _, iou_after = evaluate(model, held_out, train)
    assert iou_before < 0.5 and iou_after > 0.9, (iou_before, iou_after)
    with torch.no_grad():
        s = held_out[0]
        psi = model(s.data)
    labels = s.data.x[:, :GRASS + 1].argmax(1)
    assert psi[labels == CROSSWALK].max() < psi[labels == GRASS].min()


def test_run_key_follows_the_code_the_training_imports(settings, samples, tmp_path, monkeypatch):
    """The key is core.fingerprint's (derived from imports): it covers the loss, the estimator and the
    differentiable A*; a finished run is rebuilt, not reused, once the code's fingerprint changes."""
    from navlab.core.fingerprint import imported_modules

    covered = imported_modules("navlab.surenav.train")
    for module in ("navlab.surenav.loss", "navlab.surenav.model.gated_gcn", "navlab.search.diff_astar",
                   "navlab.surenav.training_data"):
        assert module in covered, module
    assert "navlab.core.params.surenav_model" not in covered  # a declaration: the key holds the values
    model_params, train = settings
    train = dataclasses.replace(train, epochs=1)
    first = torch.load(train_estimator(samples[:4], samples[4:6], model_params, train, tmp_path, seed=0,
                                       progress=False), weights_only=False)
    again = torch.load(train_estimator(samples[:4], samples[4:6], model_params, train, tmp_path, seed=0,
                                       progress=False), weights_only=False)
    assert again["key"] == first["key"]
    monkeypatch.setattr(training, "code_fingerprint", lambda *names: "edited code")
    rebuilt = torch.load(train_estimator(samples[:4], samples[4:6], model_params, train, tmp_path, seed=0,
                                         progress=False), weights_only=False)
    assert rebuilt["key"] != first["key"]


def test_estimator_report_rows_give_the_gap_and_the_zero_cost_floor(settings, samples):
    from navlab.surenav.estimator_report import FLOOR, ZeroCost, estimator_rows

    model_params, train = settings
    torch.manual_seed(0)
    split = {"val": samples[:6], "test": samples[6:12]}
    runs = {"main": ([build_estimator(model_params, True) for _ in (0, 1)], split),
            "ablation": ([build_estimator(model_params, False)], split)}
    rows = {r["method"]: r for r in estimator_rows(runs, train)}
    assert len(rows) == 3 and rows[FLOOR]["val_iou"] == evaluate(ZeroCost(), split["val"], train)[1]
    for r in rows.values():
        assert r["test_minus_val"] == pytest.approx(r["test_iou"] - r["val_iou"])
    main = rows["main"]
    assert main["seeds"] == 2 and main["val_iou_sd"] is not None and 0.0 <= main["val_iou"] <= 1.0
    assert main["val_iou"] == pytest.approx(np.mean([evaluate(m, split["val"], train)[1] for m in runs["main"][0]]))
    assert rows["ablation"]["val_iou_sd"] is None
