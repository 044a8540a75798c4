"""The context benchmark's pieces (issue 25, steps 2-4): real train/val tiles, the relaxation mix, the
context features and estimator, training samples, and the non-learned Psi of its reference rows."""

from __future__ import annotations

import re

import numpy as np
import pytest
import torch

from navlab.core.grid import RasterFrame
from navlab.core.labels import NUM_LABELS, SOFT_IDS, label_id
from navlab.core.params import load_params
from navlab.graphs.region_graph import superpixel_graph
from navlab.maps.network import WalkableNetwork
from navlab.maps.semantic_map import SemanticMap
from navlab.maps.tiles import Tile
from navlab.surenav.benchmark import Outcome
from navlab.surenav.claims import context_checks
from navlab.surenav.context.benchmark import LABEL_PSI, label_table_cost, oracle_cost, run_name
from navlab.surenav.context.dataset import relaxation_mix
from navlab.surenav.context.features import CONTEXT_FEATURES, ContextEstimator, EstimatorCost, context_input
from navlab.surenav.context.tiles import check_disjoint, split_tiles
from navlab.surenav.context.training import (
    EstimatorRun,
    context_model_path,
    demo_sample,
    estimator_runs,
    held_out_runs,
    main_run,
    tile_city,
    without_city,
)
from navlab.surenav.demo_priors import DSTAR, DSTAR_SENTENCE, LabelTraversal, dstar_note, dstar_readings
from navlab.surenav.experts.environments import Demonstration
from navlab.surenav.experts.store import MapDemos
from synthetic_city import city

SIDEWALK, ROAD, GRASS, BUILDING = (label_id(n) for n in ("sidewalk", "road", "grass", "building"))
PARAMS = load_params("smoke")


def _tile(city_name: str, k: int, sidewalk: float) -> Tile:
    lab = np.full((10, 10), BUILDING, dtype=np.uint8)
    lab.ravel()[:round(sidewalk * 100)] = SIDEWALK
    empty = WalkableNetwork(np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64))
    return Tile(city_name, 0, k, SemanticMap(f"{city_name}_r0c{k}", lab, RasterFrame((10, 10), 1.0)), empty)


def test_train_and_val_tiles_are_disjoint_from_the_test_tiles_and_from_each_other():
    tiles = [_tile(c, k, 0.05 + 0.02 * k) for c in ("helsinki", "monaco", "kouvola") for k in range(5)]
    tiles.append(_tile("monaco", 9, 0.0))  # too little sidewalk: in no split
    maps = PARAMS.data.maps
    split = split_tiles(tiles, maps, val_tiles=2, max_train_tiles=0, seed=0)
    names = {k: {t.map.name for t in v} for k, v in split.items()}
    assert len(names["test"]) == 3 + maps.extra_test_tiles and len(names["val"]) == 2
    assert not (names["train"] & names["test"] or names["val"] & names["test"] or names["train"] & names["val"])
    assert len(names["train"]) == 15 - len(names["test"]) - 2 and "monaco_r0c9" not in set().union(*names.values())
    again = split_tiles(tiles, maps, val_tiles=2, max_train_tiles=3, seed=0)
    assert [t.map.name for t in again["val"]] == [t.map.name for t in split["val"]] and len(again["train"]) == 3
    with pytest.raises(ValueError, match="val_tiles"):
        split_tiles(tiles, maps, val_tiles=len(tiles), max_train_tiles=0, seed=0)


def test_a_tile_in_two_splits_is_refused():
    """The guard ``split_tiles`` ends with: the same ground (city, row, col) under two splits, or twice in one,
    whatever the tile objects or their names."""
    a, b = _tile("helsinki", 0, 0.1), _tile("helsinki", 1, 0.1)
    check_disjoint({"train": [a], "val": [b], "test": []})
    copy = Tile("helsinki", 0, 0, SemanticMap("renamed", a.map.labels.copy(), a.map.frame), a.network)
    with pytest.raises(ValueError, match="tile renamed is in the train split and again in the test split"):
        check_disjoint({"train": [a], "val": [b], "test": [copy]})
    with pytest.raises(ValueError, match="tile helsinki_r0c1 is in the val split and again in the val split"):
        check_disjoint({"train": [a], "val": [b, b], "test": []})


def _demo(relaxed_cells, jaywalked=False, delta=None) -> Demonstration:
    delta = (np.zeros(0, np.int64), np.zeros(0, np.uint8)) if delta is None else delta
    return Demonstration("semi_static", np.zeros((2, 2), np.float32), np.zeros(2), np.ones(2), 0, jaywalked,
                         np.asarray(relaxed_cells, np.int64), np.zeros(0, np.int64), delta[0], delta[1], 0)


def test_relaxation_mix_counts_demonstrations_per_label_group():
    lab = np.full((4, 4), SIDEWALK, dtype=np.uint8)
    lab[0] = ROAD
    lab[3] = GRASS
    smap = SemanticMap("m", lab, RasterFrame((4, 4), 1.0))
    # the third demonstration's only relaxed cell became grass by its change (labels_on)
    demos = [_demo([0, 1, 12], jaywalked=True), _demo([2]), _demo([5], delta=(np.array([5]), np.array([GRASS], np.uint8)))]
    mix = relaxation_mix([(smap, MapDemos("m", "train", np.zeros((4, 4), np.int32), [], demos))])
    assert mix["demonstrations"] == 3 and mix["road"] == pytest.approx(2 / 3, abs=1e-4) and mix["grass"] == pytest.approx(2 / 3, abs=1e-4)
    assert mix["parking"] == 0 and mix["jaywalked"] == pytest.approx(1 / 3, abs=1e-4)


@pytest.mark.parametrize("floor", [0.01, 0.1])
def test_dstar_readings_share_the_scaled_value(floor):
    traversal = LabelTraversal(np.arange(NUM_LABELS) % 3 + 1, np.full(NUM_LABELS, 4))
    r = dstar_readings(traversal, floor)
    other = 0.1 if floor == 0.01 else 0.01
    assert set(r) == {"D* Lite", f"D* Lite (floor {other:g})", "D* Lite (1 + scaled)"}  # every reading, once
    finite = np.isfinite(r["D* Lite"])
    scaled = (r["D* Lite"][finite] - floor) / (1 - floor)
    assert scaled.min() == pytest.approx(0.0) and scaled.max() == pytest.approx(1.0)
    assert r[f"D* Lite (floor {other:g})"][finite] == pytest.approx(other + (1 - other) * scaled)
    assert r["D* Lite (1 + scaled)"][finite] == pytest.approx(1.0 + scaled)


def test_the_main_dstar_reading_is_the_papers_0_1_scaling():
    assert PARAMS.surenav.benchmark.dstar_cost_floor == load_params("default").surenav.benchmark.dstar_cost_floor == 0.01
    note = dstar_note(0.01)
    assert DSTAR_SENTENCE in note and "[0.01, 1]" in note and "0-1 scaling" in DSTAR_SENTENCE


@pytest.fixture(scope="module")
def town():
    smap = city(120)
    graph = superpixel_graph(smap.labels, smap.frame, PARAMS.surenav.graph)
    return smap, graph


def test_label_table_and_oracle_psi(town):
    smap, graph = town
    nodes = np.arange(graph.num_nodes)
    soft = np.isin(graph.node_label, SOFT_IDS)
    table = np.full(NUM_LABELS, 1.5)
    psi = label_table_cost(table)(graph, nodes)
    assert psi[~soft] == pytest.approx(0.0) and psi[soft] == pytest.approx(0.5 * np.sqrt(graph.area[soft]))
    relaxed = np.zeros(smap.labels.shape, dtype=bool)
    target = int(np.flatnonzero(soft)[0])
    relaxed[graph.node_raster == target] = True
    psi = oracle_cost(relaxed, 1000.0)(graph, nodes)
    assert psi[target] == 0.0 and np.all(psi[soft & (nodes != target)] == 1000.0) and np.all(psi[~soft] == 0.0)


def test_context_input_widths_and_estimator(town):
    smap, graph = town
    walk = np.argwhere(smap.labels == SIDEWALK)
    g = graph.with_endpoints(*smap.frame.cell_to_world(walk[[0, -1]]))
    nodes = np.arange(g.num_nodes)
    model_params = PARAMS.surenav.model
    old = context_input(g, nodes, model_params.walk_steps, "labels")
    new = context_input(g, nodes, model_params.walk_steps, "context")
    assert new.x.shape[1] == old.x.shape[1] + len(CONTEXT_FEATURES) and torch.equal(new.x[:, :old.x.shape[1]], old.x)
    torch.manual_seed(0)
    model = ContextEstimator(model_params, True, len(CONTEXT_FEATURES)).eval()
    with torch.no_grad():
        psi = model(new)
    assert psi.shape == (g.num_nodes,) and torch.all(psi[~new.soft] == 0) and torch.all(psi[new.soft] > 0)
    with pytest.raises(ValueError, match="node features"):
        model(old)
    cost = EstimatorCost(model, "context")
    assert cost(g, nodes) == pytest.approx(psi.double().numpy())


def test_the_first_graph_fixes_the_known_hard_space(town):
    _, graph = town
    model = ContextEstimator(PARAMS.surenav.model, True, len(CONTEXT_FEATURES)).eval()
    cost = EstimatorCost(model, "context")
    cost(graph, np.arange(graph.num_nodes))  # first graph: the known hard space
    assert cost.known_hard is not None and cost.known_hard.sum() == (graph.superpixels == -1).sum()


def test_demo_sample_targets_the_soft_nodes_the_demonstration_entered(town):
    smap, _ = town
    rows, cols = np.nonzero(smap.labels == ROAD)
    cells = np.ravel_multi_index((rows[:5], cols[:5]), smap.labels.shape)
    demo = Demonstration("semi_static", np.zeros((2, 2), np.float32), smap.frame.cell_to_world(np.array([2, 10])),
                         smap.frame.cell_to_world(np.array([100, 10])), 0, False, np.sort(cells), np.zeros(0, np.int64),
                         np.zeros(0, np.int64), np.zeros(0, np.uint8), 0)
    s = PARAMS.surenav
    for features, width in (("labels", 0), ("context", len(CONTEXT_FEATURES))):
        sample = demo_sample(smap, demo, s.graph, s.model, features, "t")
        assert sample.data.x.shape[1] == NUM_LABELS + 2 + s.model.walk_steps + width
        assert sample.target.any() and np.all(sample.data.soft.numpy()[sample.target])


def test_estimator_runs_train_the_papers_run_on_every_seed_and_each_variant_on_the_ablation_seeds():
    s = load_params("default").surenav
    runs = estimator_runs(s.demos.context, s.train)
    main = EstimatorRun("context", "straight_through", "closed")
    assert main_run(s.demos.context, s.train) == main
    assert runs == {main: (0, 1, 2), EstimatorRun("labels", "straight_through", "closed"): (0,),
                    EstimatorRun("context", "blackbox", "path"): (0,),
                    EstimatorRun("context", "straight_through", "path"): (0,)}
    assert [run_name(r, main) for r in runs] == [
        "SuReNav", "SuReNav, labels input (ablation)", "SuReNav, blackbox gradient (ours, variant)",
        "SuReNav, false positives on the plan (ours, variant)"]
    assert len({r.folder for r in runs}) == len(runs)  # every run trains into its own folder
    held = held_out_runs(s.demos.context, s.train)
    assert list(held) == ["helsinki", "kouvola", "monaco"]
    assert held["kouvola"] == (main._replace(held_out="kouvola"), 0)
    assert run_name(held["kouvola"][0], main) == "SuReNav trained without kouvola"
    assert held_out_runs(PARAMS.surenav.demos.context, PARAMS.surenav.train) == {}  # smoke lists no city
    from navlab.surenav.track import TRACK  # the manifest's plot reads the main run's log

    assert TRACK.plots[0][0] == (context_model_path("artifacts", main, 0).parent / "log.tsv").as_posix()


def test_a_held_out_run_sees_no_tile_of_its_city():
    from types import SimpleNamespace

    samples = [SimpleNamespace(name=f"{t}/semi_static/{i}") for t in ("helsinki_r0c1", "kouvola_r1c1", "monaco_r10c2")
               for i in range(2)]
    assert [tile_city(x.name.split("/")[0]) for x in samples[::2]] == ["helsinki", "kouvola", "monaco"]
    assert [x.name for x in without_city(samples, "monaco")] == [x.name for x in samples[:4]]
    assert without_city(samples, "") == samples


def _split(split: str, name: str) -> tuple[SemanticMap, MapDemos]:
    lab = np.full((4, 4), SIDEWALK, dtype=np.uint8)
    smap = SemanticMap(name, lab, RasterFrame((4, 4), 1.0))
    return smap, MapDemos(name, split, np.zeros((4, 4), np.int32), [], [_demo([0]), _demo([5])])


def test_the_best_per_label_field_is_chosen_on_validation_demonstrations_only(monkeypatch):
    from types import SimpleNamespace

    from navlab.surenav.context import measure

    fields = {"a": np.full(NUM_LABELS, 1.0), "b": np.full(NUM_LABELS, 2.0), "c": np.full(NUM_LABELS, 3.0)}
    seen = {}
    monkeypatch.setattr(measure, "per_label_fields", lambda maps: seen.setdefault("fields_from", sorted(maps)) and fields)

    def run_method(envs, stored, policy, settings, graph):  # the IoU each field scores on the envs it is given
        seen.setdefault("envs", set()).update(e.group for e in envs)
        cost = float(policy(envs[0], None).label_costs[0])
        return [SimpleNamespace(relaxation_iou={1.0: 0.2, 2.0: 0.6, 3.0: 0.4}[cost]) for _ in envs]

    monkeypatch.setattr(measure, "run_method", run_method)
    train, val, test = _split("train", "t1"), _split("val", "v1"), _split("test", "x1")
    choice = measure.select_field([train], [val], PARAMS.surenav.benchmark, PARAMS.surenav.graph)
    assert choice.name == "b" and choice.val_iou == {"a": 0.2, "b": 0.6, "c": 0.4}
    assert np.array_equal(choice.table, fields["b"]) and "validation" in choice.note()
    assert seen["fields_from"] == ["t1"] and seen["envs"] == {"v1"}  # fields from train tiles, chosen on val
    for args in (([train], [test]), ([test], [val]), ([train], [])):
        with pytest.raises(ValueError, match="never chosen on the test set"):
            measure.select_field(*args, PARAMS.surenav.benchmark, PARAMS.surenav.graph)


def test_context_checks_hold_only_where_the_paired_interval_excludes_zero():
    def outcome(method: str, env: int, frechet: float, iou: float) -> Outcome:
        return Outcome(method, f"env{env}", "tile", "reached", True, 10.0, 10.0, 1.0, 0.0, frechet, iou, (),
                       np.zeros((0, 2)))

    surenav = [(0.30 + 0.01 * e, 0.50 + 0.01 * e) for e in range(6)]
    outcomes = [outcome(f"SuReNav [seed {s}]", e, f, i) for s in (0, 1) for e, (f, i) in enumerate(surenav)]
    outcomes += [outcome(DSTAR, e, f + 0.2, i - 0.1) for e, (f, i) in enumerate(surenav)]  # SuReNav better
    outcomes += [outcome(LABEL_PSI, e, f + (0.05 if e % 2 else -0.05), i + 0.1)  # Fréchet: no difference
                 for e, (f, i) in enumerate(surenav)]
    got = context_checks(outcomes, [DSTAR, LABEL_PSI], seed=0)
    assert [(c.claim, c.verdict, c.source) for c in got] == [
        ("SuReNav's relaxation IoU above D* Lite's", "holds", "ours"),
        ("SuReNav's Fréchet distance below D* Lite's", "holds", "ours"),
        (f"SuReNav's relaxation IoU above {LABEL_PSI}'s", "does not hold", "ours"),  # 0.1 below it
        (f"SuReNav's Fréchet distance below {LABEL_PSI}'s", "inconclusive", "ours"),  # no difference
    ]
    assert [c.ours.split(",")[0] for c in got] == [
        f"SuReNav - {DSTAR} = +0.1", f"SuReNav - {DSTAR} = -0.2", f"SuReNav - {LABEL_PSI} = -0.1",
        f"SuReNav - {LABEL_PSI} = +0"]


def test_rerating_a_trajectory_integrates_the_other_table_along_the_same_cells():
    from navlab.metrics.navigation import risk_table, total_risk
    from navlab.surenav.context.safety import rating_sets, rerated
    from navlab.surenav.episodes import Environment

    lab = np.full((6, 6), SIDEWALK, dtype=np.uint8)
    lab[2:4, :] = ROAD
    lab[:, 4] = GRASS
    frame = RasterFrame((6, 6), 0.5)
    smap = SemanticMap("t", lab, frame)
    cells = np.array([[0, 0], [1, 1], [2, 2], [3, 3], [4, 4], [5, 5]])
    env = Environment("t/0", "t", smap, lab, cells[0], cells[-1], 0)
    ours = risk_table(PARAMS.surenav.benchmark.unit_risk)
    outcome = Outcome("m", "t/0", "t", "reached", True, 3.5, 3.5, 1.0, total_risk(cells, lab, ours, 0.5), None, None,
                      (), frame.cell_to_world(cells))
    sets = rating_sets(PARAMS)
    assert next(iter(sets)) == "our unit risks" and len(sets) == 4  # ours, RCR's table, the two of params.yaml
    assert rerated([outcome], [env], ours)[0].total_risk == pytest.approx(outcome.total_risk)
    for table in sets.values():
        assert rerated([outcome], [env], table)[0].total_risk == pytest.approx(total_risk(cells, lab, table, 0.5))
    assert rerated([outcome], [env], 2 * ours)[0].total_risk == pytest.approx(2 * outcome.total_risk)


def test_a_held_out_city_row_pairs_the_two_models_and_checks_non_inferiority():
    from navlab.surenav.context.held_out import city_row

    def outcome(method: str, env: int, iou: float) -> Outcome:
        return Outcome(method, f"e{env}", "kouvola_r0c0", "reached", True, 10.0, 10.0, 1.0, 0.0, 0.2, iou, (),
                       np.zeros((0, 2)))

    settings = load_params("default").surenav.benchmark  # the claims' resample count (2000)
    ious = 0.4 + 0.02 * np.arange(12)
    base = [outcome("SuReNav [seed 0]", e, v) for e, v in enumerate(ious)]
    for shift, verdict in ((0.0, "holds"), (0.1, "holds"), (-0.2, "does not hold")):  # better is not worse
        held = [outcome("SuReNav trained without kouvola [seed 0]", e, v + shift) for e, v in enumerate(ious)]
        row, check = city_row(base + held, "kouvola", settings)
        assert row["environments"] == 12 and row["relaxation_iou_delta"] == pytest.approx(shift)
        assert row["relaxation_iou_all_cities"] == pytest.approx(ious.mean())
        assert (check.verdict, check.source) == (verdict, "ours"), shift
    noisy = [outcome("SuReNav trained without kouvola [seed 0]", e, v + (0.3 if e % 2 else -0.3))
             for e, v in enumerate(ious)]
    row, check = city_row(base + noisy, "kouvola", settings)  # the check's interval is the row's, shifted
    lo, hi = row["relaxation_iou_delta_ci"]
    shown = [float(v) for v in re.search(r"CI \[([^,]+), ([^\]]+)\]", check.ours).groups()]
    assert check.verdict == "inconclusive" and shown == pytest.approx([lo + 0.05, hi + 0.05], abs=1e-3)
