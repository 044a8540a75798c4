"""The SuReNav benchmark on the smoke dataset: training-only priors, episodes, the runner, the claims."""

from __future__ import annotations

import shutil
from dataclasses import replace

import numpy as np
import pytest

from navlab.core.labels import FREE_IDS, HARD_IDS, NUM_LABELS, label_id
from navlab.maps.dataset import load_maps
from navlab.surenav import paper
from navlab.surenav.benchmark import (
    EXPERT,
    SURENAV,
    Learned,
    Outcome,
    fig4_rows,
    method_of,
    run_all,
    seed_run,
    surenav_runs,
    table1_rows,
)
from navlab.surenav.demo_priors import (
    LabelTraversal,
    class_order,
    dstar_label_costs,
    label_traversal,
    load_training_traversal,
)
from navlab.surenav.episodes import (
    CITIES,
    build_episodes,
    connected,
    human_likeness_environments,
    load_city_episodes,
    safety_efficiency_environments,
    window,
)
from navlab.surenav.experts.store import load_demos


@pytest.fixture(scope="module")
def episodes_dir(tmp_path_factory, smoke_params, smoke_data):
    """Only the `surenav_episodes` artefact (the others are not needed here)."""
    out = tmp_path_factory.mktemp("episodes")
    build_episodes(smoke_params, smoke_data, out)
    return out


def test_priors_never_read_test_demonstrations(smoke_data, tmp_path):
    """The traversal (and so D* Lite's costs and COA*'s order) is the same when every validation and
    test demonstration file is garbage, and label_traversal refuses them outright."""
    before = load_training_traversal(smoke_data)
    copy = tmp_path / "data"
    shutil.copytree(smoke_data, copy, symlinks=True)
    for split in ("val", "test"):
        for f in (copy / "surenav" / "demos" / split).glob("*.npz"):
            f.write_bytes(b"not an archive")
    after = load_training_traversal(copy)
    assert np.array_equal(before.traversed, after.traversed) and np.array_equal(before.total, after.total)
    with pytest.raises(ValueError, match="training demonstrations only"):
        label_traversal(load_demos(smoke_data, "test"), load_maps(smoke_data, "test"))


def test_dstar_costs_are_scaled_reciprocal_rates():
    traversed = np.array([50, 10, 5, 0, 2, 8, 1, 0, 0])
    total = np.array([100, 40, 50, 10, 20, 40, 20, 5, 5])
    t = LabelTraversal(traversed, total)
    cost = dstar_label_costs(t, 0.1)
    assert cost[0] == pytest.approx(0.1)  # the most traversed label: the floor
    assert cost[label_id("rough_terrain")] == pytest.approx(1.0)  # the least traversed: the top
    assert cost[label_id("living_street")] == 1.0  # never traversed: the top as well
    assert np.isinf(cost[HARD_IDS]).all()
    inverse = total[:7] / np.maximum(traversed[:7], 1)
    seen = traversed[:7] > 0
    expected = 0.1 + 0.9 * (inverse[seen] - inverse[seen].min()) / (inverse[seen].max() - inverse[seen].min())
    assert cost[:7][seen] == pytest.approx(expected)
    order = class_order(t)
    # soft labels only, least traversed (most critical) first; road and parking tie at 0.1 (id order)
    assert order.tolist() == [label_id(n) for n in ("living_street", "rough_terrain", "road", "parking", "grass",
                                                     "crosswalk")]
    with pytest.raises(ValueError, match="floor"):
        dstar_label_costs(t, 0.0)


def test_episodes_are_valid_and_perturbed(smoke_data, episodes_dir, smoke_params):
    cities = load_city_episodes(episodes_dir)
    assert [c.city for c in cities] == list(CITIES)
    maps = {m.name: m for m in load_maps(smoke_data, "test")}
    margin = int(np.ceil(smoke_params.surenav.benchmark.executor.window_margin_m / 2.0))
    for ce in cities:
        smap = maps[ce.map_name]
        truth = ce.truth(smap.labels)
        assert len(ce.starts) == smoke_params.surenav.benchmark.episodes.per_city
        assert len(ce.delta_cells) and (truth.ravel()[ce.delta_cells] != smap.labels.ravel()[ce.delta_cells]).all()
        for s, g in zip(ce.starts, ce.goals, strict=True):
            assert np.isin(truth[tuple(s)], FREE_IDS) and np.isin(truth[tuple(g)], FREE_IDS)
            d = np.hypot(*(s - g)) * smap.frame.resolution
            assert 30.0 <= d <= 200.0
            assert connected(truth, s, g, window(truth.shape, s, g, margin))


@pytest.fixture(scope="module")
def smoke_outcomes(smoke_data, episodes_dir, smoke_params):
    settings = smoke_params.surenav.benchmark
    learned = Learned.from_training(smoke_data, settings)
    methods = ["D* Lite", "COA*", "RCR", EXPERT]
    se = safety_efficiency_environments(smoke_data, episodes_dir)[::3]
    hl = human_likeness_environments(smoke_data)[:2]
    run = {"learned": learned, "settings": settings, "graph": smoke_params.surenav.graph, "progress": False}
    return methods, run_all(se, methods, **run), run_all(hl, methods, data_dir=smoke_data, **run)


def test_runner_outcomes_are_consistent(smoke_outcomes, smoke_params):
    methods, se, hl = smoke_outcomes
    for o in se + hl:
        assert 0.0 <= o.spl <= 1.0 and o.total_risk >= 0.0
        assert o.length_m + 1e-9 >= o.shortest_m or not o.success
        assert o.success == (o.status == "reached")
    for o in hl:
        assert o.frechet is not None and o.frechet >= 0 and 0.0 <= o.relaxation_iou <= 1.0
    rows = fig4_rows(se, methods, smoke_params.surenav.benchmark)
    assert {r["method"] for r in rows} == set(methods)
    for r in rows:
        for col in ("sr", "spl", "total_risk"):  # the bounds are rounded to 4 decimals
            assert r[f"{col}_ci"][0] - 5e-5 <= r[col] <= r[f"{col}_ci"][1] + 5e-5
    t1 = table1_rows(hl, methods, smoke_params.surenav.benchmark)
    assert [r["method"] for r in t1] == methods


def _fig4(spl, risk, length, sr=None):
    return [{"method": m, "city": c, "sr": 1.0 if sr is None else sr[m], "spl": spl[m], "total_risk": risk[m],
             "path_length_m": length[m]} for m in spl for c in paper.CITIES]


def _per_city(fmt: str, *values) -> str:
    return "; ".join(f"{c}: {fmt.format(*values)}" for c in paper.CITIES)


def _fields(claims):
    return [(c.claim, c.verdict, c.ours, c.paper, c.why) for c in claims]


SPL_NEAR = "SuReNav's SPL is near the best (at least 90% of the best method's)"
LOWER_RISK = "SuReNav has lower total risk than D* Lite in every city"
TWICE = "D* Lite has roughly twice SuReNav's total risk"
LONGEST = "COA* is the most conservative: the longest paths"
HALF_LONGER = "COA*'s paths are about 50% longer than SuReNav's"


def test_fig4_claims_hold_on_the_papers_pattern():
    spl = {"D* Lite": 0.95, "COA*": 0.6, "RCR": 0.8, "SuReNav": 0.9}
    risk = {"D* Lite": 40.0, "COA*": 15.0, "RCR": 30.0, "SuReNav": 20.0}
    length = {"D* Lite": 150.0, "COA*": 240.0, "RCR": 170.0, "SuReNav": 160.0}
    assert _fields(paper.fig4_claims(_fig4(spl, risk, length))) == [
        ("D* Lite attains the highest SPL", "holds", _per_city("best D* Lite (0.950), D* Lite 0.950"), "", ""),
        (SPL_NEAR, "holds", _per_city("0.900 = 95% of D* Lite's"), "", ""),
        (LOWER_RISK, "holds", _per_city("20.0 vs 40.0"), "", ""),
        (TWICE, "holds", _per_city("x2.00"), "", ""),
        (LONGEST, "holds", _per_city("longest COA* (240 m)"), "", ""),
        (HALF_LONGER, "holds", _per_city("x1.50"), "", ""),
        ("all methods reach 100% SR", "holds", "lowest: D* Lite/milan 1.00", "", ""),
    ]


def test_fig4_claims_fail_with_the_reason_and_the_reference_beside_them():
    spl = {"D* Lite": 0.95, "COA*": 0.6, "RCR": 0.99, "SuReNav": 0.7}
    risk = {"D* Lite": 19.0, "COA*": 15.0, "RCR": 30.0, "SuReNav": 20.0}
    length = {"D* Lite": 150.0, "COA*": 140.0, "RCR": 170.0, "SuReNav": 160.0}
    sr = {**dict.fromkeys(spl, 1.0), "COA*": 0.9}
    assert _fields(paper.fig4_claims(_fig4(spl, risk, length, sr=sr))) == [
        ("D* Lite attains the highest SPL", "does not hold", _per_city("best RCR (0.990), D* Lite 0.950"), "", ""),
        (SPL_NEAR, "does not hold", _per_city("0.700 = 71% of RCR's"), "", ""),
        (LOWER_RISK, "does not hold", _per_city("20.0 vs 19.0"), "", paper.WHY_UNIT_RISK),
        (TWICE, "does not hold", _per_city("x0.95"), "", paper.WHY_UNIT_RISK),  # no reference row: no comparison
        (LONGEST, "does not hold", _per_city("longest RCR (170 m)"), "", ""),
        (HALF_LONGER, "does not hold", _per_city("x0.88"), "", paper.WHY_COA_LEXICOGRAPHIC),
        ("all methods reach 100% SR", "does not hold", "lowest: COA*/milan 0.90", "", paper.WHY_SR),
    ]
    expert = [{"method": "Expert (reference)", "city": c, "sr": 0.95, "spl": 0.9, "total_risk": 25.0,
               "path_length_m": 150.0} for c in paper.CITIES]
    claims = paper.fig4_claims(_fig4(spl, risk, length, sr=sr) + expert)
    versus = "Expert (reference), whose choices SuReNav imitates: " + "; ".join(
        f"{c} {{}} vs {{}}" for c in paper.CITIES)
    risk_why = f"{paper.WHY_UNIT_RISK}; risk of the {versus.format(*(25.0, 19.0) * 3)} (D* Lite's)"
    assert [(c.verdict, c.why) for c in claims[2:4]] == [("does not hold", risk_why)] * 2
    assert claims[6].why == f"{paper.WHY_SR}; SR of the {versus.format(*('0.95', '1.00') * 3)} (SuReNav's)"
    assert "; why: " + risk_why in claims[2].line()


def test_fig4_claims_without_surenav_are_inconclusive():
    spl = {"D* Lite": 0.95, "COA*": 0.6, "RCR": 0.99}
    risk = {"D* Lite": 19.0, "COA*": 15.0, "RCR": 30.0}
    length = {"D* Lite": 150.0, "COA*": 240.0, "RCR": 170.0}
    expert = [{"method": "Expert (reference)", "city": c, "sr": 1.0, "spl": 0.9, "total_risk": 25.0,
               "path_length_m": 150.0} for c in paper.CITIES]
    assert _fields(paper.fig4_claims(_fig4(spl, risk, length) + expert)) == [
        ("D* Lite attains the highest SPL", "does not hold", _per_city("best RCR (0.990), D* Lite 0.950"), "", ""),
        (SPL_NEAR, "inconclusive", "SuReNav not run", "", ""),
        (LOWER_RISK, "inconclusive", "SuReNav not run", "", ""),
        (TWICE, "inconclusive", "SuReNav not run; D* Lite / lowest-risk baseline: " + _per_city("x1.27"), "", ""),
        (LONGEST, "holds", _per_city("longest COA* (240 m)"), "", ""),
        (HALF_LONGER, "inconclusive", "SuReNav not run", "", ""),
        ("all methods reach 100% SR", "holds", "lowest: D* Lite/milan 1.00", "", ""),
    ]


FRECHET_ORDER = "baselines by Fréchet distance, best first: D* Lite < RCR < COA*"
IOU_ORDER = "baselines by relaxation IoU, best first: COA* > RCR > D* Lite"
LOWEST_FRECHET, HIGHEST_IOU = "SuReNav has the lowest Fréchet distance", "SuReNav has the highest relaxation IoU"
MARGIN = "SuReNav's relaxation IoU is at least 44% above the next best"


def _table1(changes=None):
    """The paper's Table I rows with some methods' (frechet, relaxation_iou) changed; None drops a method."""
    changes = changes or {}
    return [{**r, **dict(zip(("frechet", "relaxation_iou"), changes[r["method"]], strict=True))}
            if r["method"] in changes else dict(r) for r in paper.TABLE1 if changes.get(r["method"], ()) is not None]


def test_table1_claims_on_the_papers_rows_hold_and_carry_its_number():
    assert _fields(paper.table1_claims(_table1())) == [
        (FRECHET_ORDER, "holds", "D* Lite 0.429 < RCR 0.626 < COA* 0.701", "", ""),
        (IOU_ORDER, "holds", "COA* 0.271 > RCR 0.259 > D* Lite 0.223", "", ""),
        (LOWEST_FRECHET, "holds", "D* Lite 0.429; COA* 0.701; RCR 0.626; SuReNav 0.334", "", ""),
        (HIGHEST_IOU, "holds", "D* Lite 0.223; COA* 0.271; RCR 0.259; SuReNav 0.416", "", ""),
        (MARGIN, "holds", "SuReNav 0.416 vs next best COA* 0.271: x1.54", "0.416 vs 0.271", ""),
    ]
    assert paper.table1_claims(_table1())[4].line() == (
        f"{MARGIN}: holds (SuReNav 0.416 vs next best COA* 0.271: x1.54; paper 0.416 vs 0.271)")


def test_table1_claims_fail_with_the_reason():
    claims = paper.table1_claims(_table1({"D* Lite": (0.9, 0.5), "RCR": (0.2, 0.1), "SuReNav": (0.3, 0.3)}))
    assert _fields(claims) == [
        (FRECHET_ORDER, "does not hold", "RCR 0.200 < COA* 0.701 < D* Lite 0.900", "", paper.WHY_SYNTHETIC_EXPERT),
        (IOU_ORDER, "does not hold", "D* Lite 0.500 > COA* 0.271 > RCR 0.100", "", paper.WHY_SYNTHETIC_EXPERT),
        (LOWEST_FRECHET, "does not hold", "D* Lite 0.900; COA* 0.701; RCR 0.200; SuReNav 0.300", "",
         paper.WHY_PERSONA_BLIND),
        (HIGHEST_IOU, "does not hold", "D* Lite 0.500; COA* 0.271; RCR 0.100; SuReNav 0.300", "",
         paper.WHY_PERSONA_BLIND + paper.WHY_DSTAR_FITTED),  # D* Lite won: its fitted costs named
        (MARGIN, "does not hold", "SuReNav 0.300 vs next best D* Lite 0.500: x0.60", "0.416 vs 0.271",
         paper.WHY_PERSONA_BLIND + paper.WHY_DSTAR_FITTED),
    ]
    margin = paper.table1_claims(_table1({"SuReNav": (0.3, 0.3)}))[4]  # best, but only 11% above COA*
    assert (margin.verdict, margin.ours, margin.why) == (
        "does not hold", "SuReNav 0.300 vs next best COA* 0.271: x1.11", paper.WHY_PERSONA_BLIND)


def test_table1_claims_without_a_method_are_inconclusive():
    claims = paper.table1_claims(_table1({"D* Lite": (0.9, 0.223), "SuReNav": None}))
    assert _fields(claims) == [
        (FRECHET_ORDER, "does not hold", "RCR 0.626 < COA* 0.701 < D* Lite 0.900", "", paper.WHY_SYNTHETIC_EXPERT),
        (IOU_ORDER, "holds", "COA* 0.271 > RCR 0.259 > D* Lite 0.223", "", ""),
        *((text, "inconclusive", "SuReNav not run", "", "") for text in (LOWEST_FRECHET, HIGHEST_IOU, MARGIN)),
    ]
    claims = paper.table1_claims(_table1({"RCR": None}))  # a baseline missing: its orderings cannot be told
    assert _fields(claims[:2]) == [(FRECHET_ORDER, "inconclusive", "D* Lite 0.429 < COA* 0.701", "", ""),
                                   (IOU_ORDER, "inconclusive", "COA* 0.271 > D* Lite 0.223", "", "")]


def test_dstar_costs_of_the_smoke_data_are_finite_on_walkable_labels(smoke_data, smoke_params):
    learned = Learned.from_training(smoke_data, smoke_params.surenav.benchmark)
    walkable = ~np.isin(np.arange(NUM_LABELS), HARD_IDS)
    assert np.isfinite(learned.dstar_costs[walkable]).all() and (learned.dstar_costs[walkable] > 0).all()
    assert learned.dstar_costs[label_id("sidewalk")] == pytest.approx(smoke_params.surenav.benchmark.dstar_cost_floor)


def test_workers_do_not_change_outcomes(smoke_data, episodes_dir, smoke_params):
    settings = smoke_params.surenav.benchmark
    learned = Learned.from_training(smoke_data, settings)
    envs = safety_efficiency_environments(smoke_data, episodes_dir)[:2]
    run = {"learned": learned, "graph": smoke_params.surenav.graph, "progress": False}
    one = run_all(envs, ["RCR", EXPERT], settings=settings, **run)
    two = run_all(envs, ["RCR", EXPERT], settings=replace(settings, workers=2), **run)
    assert [(o.method, o.environment) for o in one] == [(o.method, o.environment) for o in two]
    for a, b in zip(one, two, strict=True):
        assert np.array_equal(a.trajectory, b.trajectory) and a.total_risk == b.total_risk


def _outcome(run, env, success, spl, iou):
    return Outcome(run, env, "milan", "reached" if success else "stuck", success, 100.0, 90.0, spl, 1.0, 0.2, iou,
                   (0.01,), np.zeros((2, 2)))


def test_seed_runs_are_averaged_per_environment_with_their_spread(smoke_params):
    settings = smoke_params.surenav.benchmark
    assert method_of(seed_run(SURENAV, 2)) == SURENAV and method_of("RCR") == "RCR"
    assert [method_of(r) for r in surenav_runs([0, 1], [0])].count(SURENAV) == 2
    spl = {(0, "e0"): 0.8, (0, "e1"): 0.6, (0, "e2"): 1.0, (1, "e0"): 0.4, (1, "e1"): 0.6, (1, "e2"): 0.8}
    outcomes = [_outcome(seed_run(SURENAV, k), e, spl[k, e] > 0.5, spl[k, e], spl[k, e] / 2) for k, e in spl]
    outcomes += [_outcome("RCR", e, True, 0.5, 0.25) for e in ("e0", "e1", "e2")]
    rows = {r["method"]: r for r in fig4_rows(outcomes, [SURENAV, "RCR"], settings)}
    row = rows[SURENAV]
    assert row["episodes"] == 3 and row["seeds"] == 2
    assert row["spl"] == pytest.approx(np.mean(list(spl.values())))
    assert row["spl_seed_sd"] == pytest.approx(np.std([0.8, 0.6], ddof=1), abs=1e-4)  # seed means 0.8 and 0.6
    assert row["sr"] == pytest.approx(5 / 6) and row["sr_seed_sd"] == pytest.approx(np.std([1.0, 2 / 3], ddof=1), abs=1e-4)
    assert row["spl_ci"][0] <= row["spl"] <= row["spl_ci"][1]
    assert rows["RCR"]["seeds"] == 1 and rows["RCR"]["spl_seed_sd"] is None
    t1 = {r["method"]: r for r in table1_rows(outcomes, [SURENAV, "RCR"], settings)}
    assert t1[SURENAV]["environments"] == 3 and t1[SURENAV]["relaxation_iou"] == pytest.approx(0.35)
