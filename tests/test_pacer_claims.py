"""navlab.pacer.claims: the paper's numbers and the verdicts of its claims on constructed per-map results."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.seeding import rng
from navlab.pacer.claims import (
    PAPER,
    agreement_against_target,
    gap_closed,
    gap_fraction,
    margin_ranking_claims,
    on_par,
    paired_difference,
    phase1_cannot_follow_inverted,
    seen_claims,
    synthetic_generalises_best,
    unseen_claims,
)


def shares(low: np.ndarray) -> np.ndarray:
    """(maps, 3) shares with the given low share and the rest split evenly."""
    low = np.clip(low, 0, 1)
    return np.stack([low, (1 - low) / 2, (1 - low) / 2], axis=1)


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


def test_paired_difference_cancels_what_the_maps_share():
    gen = rng(0, "maps")
    difficulty = gen.uniform(0.2, 0.8, 20)  # maps differ a lot; the methods differ by a constant
    mean, (lo, hi) = paired_difference(difficulty + 0.05, difficulty, "test")
    assert mean == pytest.approx(0.05) and lo == pytest.approx(0.05) and hi == pytest.approx(0.05)
    with pytest.raises(ValueError, match="equal-length"):
        paired_difference(np.ones(3), np.ones(4))


def test_seen_and_unseen_verdicts_follow_the_paired_intervals():
    gen = rng(1, "maps")
    base = gen.uniform(0.3, 0.7, 24)
    noise = lambda s: 0.01 * rng(s, "noise").standard_normal(24)
    seen = {"PACER": shares(base + noise(1)), "STERLING-style": shares(base + noise(2)),
            "PACER (uninformative context)": shares(base - 0.3 + noise(3)), "Classifier": shares(base + noise(4))}
    par, prior = seen_claims(seen)
    assert par.verdict == "holds" and prior.verdict == "does not hold"  # 0.3 below: not on par
    unseen = {"PACER": shares(base + 0.2 + noise(5)), "STERLING-style": shares(base + noise(6)),
              "PACER (uninformative context)": shares(base + 0.2 + noise(5))}
    beats, adapt = unseen_claims(unseen)
    assert beats.verdict == "holds" and adapt.verdict == "inconclusive"  # equal: the interval straddles 0
    worse = unseen_claims({**unseen, "PACER": shares(base - 0.2 + noise(8))})[0]
    assert worse.verdict == "does not hold" and "PACER low - STERLING low" in str(worse)
    wide = on_par("x", base + rng(9, "wide").normal(0, 0.3, 24), base, ("a", "b"), "wide")
    assert wide.verdict == "inconclusive"  # too noisy to call equivalence either way


def test_phase1_and_synthetic_claims():
    maps = rng(2, "maps").uniform(0.2, 0.6, 20)
    follows = phase1_cannot_follow_inverted((0.48, (0.40, 0.56)), maps, maps + 0.3)
    assert follows.verdict == "holds" and "0.480" in follows.ours
    assert phase1_cannot_follow_inverted((0.80, (0.72, 0.88)), maps, maps).verdict == "does not hold"
    assert phase1_cannot_follow_inverted((0.60, (0.50, 0.70)), maps, maps).verdict == "inconclusive"
    jitter = 0.01 * rng(3, "j").standard_normal(20)
    best = synthetic_generalises_best({"D_real": maps, "D_shuffled": maps + 0.1, "D_synthetic": maps + 0.2 + jitter})
    assert best.verdict == "holds"
    second = synthetic_generalises_best({"D_real": maps, "D_shuffled": maps + 0.3, "D_synthetic": maps + 0.2 + jitter})
    assert second.verdict == "does not hold"


def test_margin_ranking_claims_read_the_diagonal():
    paper = margin_ranking_claims(PAPER["table5_margin_ranking"])
    assert [c.verdict for c in paper] == ["holds", "holds"]  # the paper's own table supports both claims
    swapped = [dict(r) for r in PAPER["table5_margin_ranking"]]
    swapped[0]["test_shuffled"] = 0.001  # D_real now beats D_shuffled on D_shuffled's test set
    assert margin_ranking_claims(swapped)[0].verdict == "does not hold"


def test_agreement_target_sentence():
    met = {("seen", "realistic"): (0.9, (0.85, 0.95)), ("unseen", "inverted"): (0.86, None)}
    assert "is met" in agreement_against_target(met)
    assert "NOT met" in agreement_against_target({**met, ("seen", "inverted"): (0.7, (0.6, 0.8))})
    summary = {"steps": 1536, "epochs_run": 24, "max_epochs": 24, "stopped_early": False, "best_epoch": 22,
               "best_val_loss": 0.4123, "entropy_floor": 0.2011}
    sentence = agreement_against_target(met, summary)
    assert "1536 optimiser steps" in sentence and "ran every epoch" in sentence
    assert "0.412 beside the entropy floor 0.201" in sentence


def test_gap_closed_is_the_share_of_the_chance_to_ceiling_gap():
    chance = np.array([0.2, 0.3, 0.25, 0.2] * 5)
    ceiling = chance + 0.4
    closes = gap_closed("m", chance + 0.36, chance, ceiling, "seen", "realistic")  # 0.9 of the gap on every map
    assert closes.verdict == "holds" and "0.90 of the gap" in closes.ours
    assert gap_closed("m", chance + 0.36, chance, ceiling, "seen", why="w").why == ""  # a claim that holds needs none
    short = gap_closed("m", chance + 0.2, chance, ceiling, "seen", "realistic", why="w")  # half the gap
    assert short.verdict == "does not hold" and "0.50 of the gap" in short.ours and short.why == "w"
    assert gap_fraction(chance + 0.2, chance, ceiling) == pytest.approx(0.5)
    assert gap_fraction(chance, chance, chance) is None
    noisy = gap_closed("m", chance + np.tile([0.0, 0.6], 10), chance, ceiling, "seen")  # 0.75 on average, spread
    assert noisy.verdict == "inconclusive"
    assert gap_closed("m", chance, chance, chance, "seen").verdict == "inconclusive"  # no room to close
