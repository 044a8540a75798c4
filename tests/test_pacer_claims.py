"""navlab.pacer.claims: the paper's numbers, the claims registry, and the verdicts of each report's claims on
constructed per-map (per-item for Table V) results: a tie, an overlap and a clear difference each, the
paper's claims apart from our own checks."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.seeding import rng
from navlab.metrics.claims import Test as Outcome
from navlab.pacer.claims import (
    BLIND,
    CLAIMS,
    CLASSIFIER,
    PACER,
    PAPER,
    PAR_MARGIN,
    PHASE_MODELS,
    STERLING,
    UNIFORM,
    above_target,
    agreement_target,
    all_of,
    any_of,
    gap_closed,
    gap_fraction,
    margin_ranking_claims,
    phase_seen_claims,
    phase_unseen_claims,
    seen_claims,
    training_budget,
    two_sample_difference,
    unseen_claims,
)
from navlab.pipeline.reports import TABLE_IDS

MAPS = 24
BASE = rng(1, "maps").uniform(0.3, 0.7, MAPS)  # maps differ a lot; the methods differ by what each test sets


def noise(key: str, scale: float = 0.01) -> np.ndarray:
    return scale * rng(2, "noise", key).standard_normal(MAPS)


def shares(low: np.ndarray) -> np.ndarray:
    """(maps, 3) shares with the given low share and the rest split evenly."""
    low = np.clip(low, 0, 1)
    return np.stack([low, (1 - low) / 2, (1 - low) / 2], axis=1)


def verdicts(claims) -> dict[str, str]:
    return {c.key: c.verdict for c in claims}


def test_paper_tables_are_shares_that_sum_to_one():
    for table_id in ("table1_seen", "table2_unseen", "table3_phases_seen", "table4_phases_unseen"):
        for row in PAPER[table_id]:
            total = row["low"] + row["medium"] + row["high"]
            if (table_id, row.get("method")) == ("table2_unseen", "STERLING-style"):
                assert total == pytest.approx(0.9837)  # as printed: 61.39 + 10.12 + 26.86 = 98.37 %
            else:
                assert total == pytest.approx(1.0, abs=2e-4), (table_id, row)
    assert {r["method"] for r in PAPER["table1_seen"]} >= {"PACER", "STERLING-style", "Classifier"}
    assert "Classifier" not in {r["method"] for r in PAPER["table2_unseen"]}  # the paper omits it on unseen
    diagonal = {r["model"]: r[f"test_{r['model'].removeprefix('D_')}"] for r in PAPER["table5_margin_ranking"]}
    assert diagonal == {"D_real": 0.017, "D_shuffled": 0.019, "D_synthetic": 0.013}


def test_registry_names_a_pacer_report_or_why_not_and_keeps_the_real_robot_apart():
    for entry in CLAIMS.values():
        assert entry.report in TABLE_IDS["pacer"] or entry.not_tested, entry.key
        assert (entry.margin is not None) == ("on par" in entry.claim), entry.key  # an on-par claim states its margin
    untested = {k for k, c in CLAIMS.items() if c.not_tested}
    assert {k for k in CLAIMS if k.startswith("table6_")} <= untested
    assert all("robot" in CLAIMS[k].not_tested for k in untested)
    assert {c.report for c in CLAIMS.values() if c.report} == set(TABLE_IDS["pacer"]) - {"context_following"}


def seen_shares(**lows: np.ndarray) -> dict[str, np.ndarray]:
    default = {PACER: BASE + noise("p"), BLIND: BASE + noise("b"), STERLING: BASE + noise("s"),
               CLASSIFIER: BASE + noise("c"), UNIFORM: BASE - 0.2 + noise("u")}
    return {m: shares(v) for m, v in (default | lows).items()}


def test_table1_claims_are_every_table1_entry_decided_on_maps():
    claims = seen_claims(seen_shares())
    assert [c.key for c in claims] == [k for k, c in CLAIMS.items() if c.report == "table1_seen"]
    assert all(c.source == "paper" and c.quote == CLAIMS[c.key].quote and c.where for c in claims)
    assert verdicts(claims) == {"table1_pacer_similar_to_sterling": "holds",
                                "table1_uninformative_on_par_with_classifier": "holds",
                                "table1_uninformative_prior": "holds",
                                "table1_sterling_best_baseline": "inconclusive"}  # STERLING and classifier tie
    assert f"on par means inside ±{PAR_MARGIN:g}" in claims[0].ours and f"over {MAPS} maps" in claims[0].ours
    apart = verdicts(seen_claims(seen_shares(**{BLIND: BASE - 0.3 + noise("b"), STERLING: BASE + 0.2 + noise("s")})))
    assert apart["table1_uninformative_on_par_with_classifier"] == "does not hold"  # 0.3 below: not on par
    assert apart["table1_pacer_similar_to_sterling"] == "does not hold"
    assert apart["table1_sterling_best_baseline"] == "holds"
    wide = seen_claims(seen_shares(**{PACER: BASE + noise("p", 0.3)}))[0]
    assert wide.verdict == "inconclusive"  # too noisy to call equivalence either way


def test_table2_claims_and_the_abstract_share_the_sterling_test():
    unseen = {PACER: shares(BASE + 0.2 + noise("p")), STERLING: shares(BASE + noise("s")),
              BLIND: shares(BASE + 0.2 + noise("p"))}
    claims = unseen_claims(unseen)
    assert [c.key for c in claims] == [k for k, c in CLAIMS.items() if c.report == "table2_unseen"]
    got = verdicts(claims)
    assert got["table2_pacer_outperforms_sterling"] == "holds"
    assert got["table2_uninformative_cannot_adapt"] == "inconclusive"  # informative and uninformative tie
    assert claims[0].ours == claims[2].ours  # the abstract's claim against STERLING is Table II's test
    worse = unseen_claims({**unseen, PACER: shares(BASE - 0.2 + noise("w"))})[0]
    assert worse.verdict == "does not hold" and "PACER low - STERLING low" in worse.ours
    with pytest.raises(ValueError, match="cannot take this preference"):
        unseen_claims({**unseen, STERLING: None})


def phase_shares(lows: dict[str, dict[str, float]], key: str) -> dict[str, dict[str, np.ndarray]]:
    """{preference: {model: per-map shares}} around the given low shares."""
    return {pref: {m: shares(BASE + low + noise(f"{key}/{pref}/{m}")) for m, low in by_model.items()}
            for pref, by_model in lows.items()}


PAPER_LIKE_SEEN = {"realistic": {"D_real": 0.3, "D_shuffled": 0.05, "D_synthetic": 0.1, UNIFORM: -0.2},
                   "inverted": {"D_real": -0.3, "D_shuffled": 0.05, "D_synthetic": 0.06, UNIFORM: -0.2}}
PAPER_LIKE_UNSEEN = {"realistic": {"D_real": -0.1, "D_shuffled": 0.0, "D_synthetic": 0.3},
                     "inverted": {"D_real": -0.3, "D_shuffled": -0.2, "D_synthetic": 0.1}}


def test_table3_claims_on_results_shaped_like_the_papers():
    claims = phase_seen_claims(phase_shares(PAPER_LIKE_SEEN, "seen"))
    assert [c.key for c in claims] == [k for k, c in CLAIMS.items() if c.report == "table3_phases_seen"]
    assert set(verdicts(claims).values()) == {"holds"}
    ours_like = {"realistic": {"D_real": 0.0, "D_shuffled": 0.1, "D_synthetic": 0.1, UNIFORM: -0.2},
                 "inverted": {"D_real": -0.1, "D_shuffled": -0.05, "D_synthetic": 0.1, UNIFORM: -0.2}}
    got = verdicts(phase_seen_claims(phase_shares(ours_like, "ours")))
    assert got["table3_real_best_with_realistic"] == "does not hold"  # D_real the worst with realistic preferences
    assert got["table3_real_cannot_adapt_to_inverted"] == "does not hold"  # above chance under inverted ones
    assert got["table3_shuffled_adapts"] == "does not hold"  # 0.15 apart: outside the margin
    assert got["table3_preference_training_trade_off"] == "does not hold"


def test_table4_drops_resample_seen_and_unseen_maps_apart():
    seen, unseen = phase_shares(PAPER_LIKE_SEEN, "seen"), phase_shares(PAPER_LIKE_UNSEEN, "unseen")
    claims = phase_unseen_claims(seen, unseen)
    assert [c.key for c in claims] == [k for k, c in CLAIMS.items() if c.report == "table4_phases_unseen"]
    got = verdicts(claims)
    assert got["table4_real_worst"] == got["table4_synthetic_respects_and_recognises"] == "holds"
    assert got["table4_shuffled_drops_to_unseen"] == got["table4_synthetic_least_drop"] == "holds"
    # D_synthetic rises from seen to unseen here (as in the paper's own numbers): not every phase drops
    assert got["table4_every_phase_drops_to_unseen"] == "does not hold"
    least = next(c for c in claims if c.key == "table4_synthetic_least_drop")
    assert "unpaired" in least.ours and "resampled apart" in least.ours
    same = phase_unseen_claims(seen, seen)  # no drop at all: a tie is never a drop
    assert {c.key: c.verdict for c in same}["table4_shuffled_drops_to_unseen"] == "inconclusive"


def item_errors(cells: dict[str, tuple[float, float, float]], spread: float = 0.002) -> dict:
    gen = rng(3, "items")
    difficulty = gen.uniform(0.0, 0.02, 40)  # items differ; the models differ by the cell
    return {m: {s: difficulty + v + spread * gen.standard_normal(40) for s, v in zip(("real", "shuffled", "synthetic"),
                                                                                     values, strict=True)}
            for m, values in cells.items()}


def test_table5_claims_pair_models_by_item():
    paper = {r["model"]: (r["test_real"], r["test_shuffled"], r["test_synthetic"]) for r in PAPER["table5_margin_ranking"]}
    claims = margin_ranking_claims(item_errors(paper))
    assert [c.key for c in claims] == [k for k, c in CLAIMS.items() if c.report == "table5_margin_ranking"]
    assert set(verdicts(claims).values()) == {"holds"}  # the paper's own cells support all three
    assert "paired over 40 test items" in claims[0].ours and "120 test items (3 splits pooled)" in claims[2].ours
    tied = dict(paper, D_shuffled=(0.086, 0.069, 0.064))  # D_shuffled ties D_synthetic on its own split
    assert verdicts(margin_ranking_claims(item_errors(tied)))["table5_own_test_set_lowest"] == "inconclusive"
    worst = dict(paper, D_synthetic=(0.1, 0.12, 0.013))  # D_synthetic above both others on two splits
    got = verdicts(margin_ranking_claims(item_errors(worst)))
    assert got["table5_synthetic_top_two"] == "does not hold" and got["table5_synthetic_best_overall"] == "does not hold"


def test_combinations_and_the_two_sample_rule():
    yes, no, maybe = Outcome("holds", "y"), Outcome("does not hold", "n"), Outcome("inconclusive", "m")
    assert all_of({"a": yes, "b": yes}).verdict == "holds" and all_of({"a": yes, "b": maybe}).verdict == "inconclusive"
    assert all_of({"a": maybe, "b": no}).verdict == "does not hold" and "b: does not hold (n)" in all_of({"b": no}).evidence
    assert any_of({"a": no, "b": yes}).verdict == "holds" and any_of({"a": no, "b": maybe}).verdict == "inconclusive"
    assert any_of({"a": no, "b": no}).verdict == "does not hold"
    a, b = rng(4, "a").uniform(0.4, 0.6, 20), rng(4, "b").uniform(0.4, 0.6, 25)
    assert two_sample_difference(a, a, "higher", rng(0, "t")).verdict == "inconclusive"  # a tie
    assert two_sample_difference(a, b, "higher", rng(0, "t")).verdict == "inconclusive"  # an overlap
    assert two_sample_difference(a + 0.3, b, "higher", rng(0, "t")).verdict == "holds"
    assert two_sample_difference(a + 0.3, b, "lower", rng(0, "t")).verdict == "does not hold"
    assert "too few" in two_sample_difference(a[:5], b, "higher", rng(0, "t")).evidence
    assert above_target(0.9, (0.85, 0.95), 0.85, "x").verdict == "inconclusive"  # at the target is not above it
    assert above_target(0.9, (0.86, 0.95), 0.85, "x").verdict == "holds"
    assert above_target(0.8, (0.7, 0.84), 0.85, "x").verdict == "does not hold"
    assert above_target(0.9, None, 0.85, "x").verdict == "inconclusive"


def test_gap_closed_is_our_check_on_the_share_of_the_chance_to_ceiling_gap():
    chance = np.array([0.2, 0.3, 0.25, 0.2] * 5)
    ceiling = chance + 0.4
    closes = gap_closed("m", chance + 0.36, chance, ceiling, "seen", "realistic")  # 0.9 of the gap on every map
    assert closes.verdict == "holds" and closes.source == "ours" and not closes.quote
    assert "share of the gap closed 0.900" in closes.ours and "over 20 maps" in closes.ours
    assert gap_closed("m", chance + 0.36, chance, ceiling, "seen", why="w").why == ""  # a check that holds needs none
    short = gap_closed("m", chance + 0.2, chance, ceiling, "seen", "realistic", why="w")  # half the gap
    assert short.verdict == "does not hold" and "0.500" in short.ours and short.why == "w"
    assert gap_fraction(chance + 0.2, chance, ceiling) == pytest.approx(0.5)
    assert gap_fraction(chance, chance, chance) is None
    noisy = gap_closed("m", chance + np.tile([0.0, 0.6], 10), chance, ceiling, "seen")  # 0.75 on average, spread
    assert noisy.verdict == "inconclusive"
    assert gap_closed("m", chance, chance, chance, "seen").verdict == "inconclusive"  # no room to close


def test_agreement_target_and_training_budget_are_our_checks():
    met = {("seen", "realistic"): (0.9, (0.87, 0.95)), ("unseen", "inverted"): (0.9, (0.86, 0.93))}
    assert agreement_target(met).verdict == "holds" and agreement_target(met).source == "ours"
    assert agreement_target({**met, ("seen", "inverted"): (0.86, None)}).verdict == "inconclusive"
    short = agreement_target({**met, ("seen", "inverted"): (0.7, (0.6, 0.8))})
    assert short.verdict == "does not hold" and "seen/inverted: does not hold" in short.ours
    within = training_budget({"D_real": 3.5, "D_shuffled": 7.3, "D_synthetic": 17.2})
    assert within.verdict == "holds" and within.source == "ours" and "D_shuffled 7.3 min" in within.ours
    assert training_budget({"D_real": 45.0}).verdict == "inconclusive"  # exactly the budget is not within it
    assert training_budget({"D_real": 30.0, "D_synthetic": 20.0}).verdict == "does not hold"
    assert set(PHASE_MODELS) == {"D_real", "D_shuffled", "D_synthetic"}
