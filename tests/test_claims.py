"""The strict verdict rules (navlab.metrics.claims, issue 58): each fed a tie, an overlap and a clear
difference, in both directions. A tie or an overlap is never "holds"."""

import numpy as np
import pytest

from navlab.metrics.claims import (
    MIN_UNITS,
    Claim,
    PaperClaim,
    best_of,
    equal_count,
    every,
    exact_comparison,
    magnitude,
    on_par,
    ours,
    paired_difference,
    paired_success,
    ratio_of_values,
    registry,
)


def _rng():
    return np.random.default_rng(0)


NOISE = np.random.default_rng(1).normal(0.0, 1.0, 40)


def test_paired_difference_tie_overlap_and_clear_difference():
    base = np.linspace(1.0, 2.0, 40)
    assert paired_difference(base, base, "higher", _rng()).verdict == "inconclusive"  # a tie
    assert paired_difference(base, base, "lower", _rng()).verdict == "inconclusive"
    overlap = paired_difference(base + 0.01 + NOISE, base, "higher", _rng())
    assert overlap.verdict == "inconclusive" and "CI [-" in overlap.evidence
    assert paired_difference(base + 1 + 0.1 * NOISE, base, "higher", _rng()).verdict == "holds"
    assert paired_difference(base + 1 + 0.1 * NOISE, base, "lower", _rng()).verdict == "does not hold"


def test_too_few_units_is_inconclusive_and_says_what_the_test_needs():
    t = paired_difference([5.0] * (MIN_UNITS - 1), [1.0] * (MIN_UNITS - 1), "higher", _rng(), unit="tasks")
    assert t.verdict == "inconclusive" and f"at least {MIN_UNITS} paired tasks" in t.evidence


def test_paired_success_is_an_exact_mcnemar_on_discordant_units():
    same = [True] * 98 + [False] * 2
    assert paired_success(same, same).verdict == "inconclusive"  # 98/100 vs 98/100: no discordant task
    a = [True] * 12
    b = [True] * 7 + [False] * 5  # the paper's Table II: 12/12 vs 7/12, five discordant tasks
    t = paired_success(a, b)
    assert t.verdict == "inconclusive" and "too few" in t.evidence  # 2 * 0.5**5 = 0.0625 > 0.05
    many = [True] * 30 + [False] * 10
    assert paired_success(many, [True] * 20 + [False] * 20).verdict == "holds"  # 10 discordant, all one way
    assert paired_success([True] * 20 + [False] * 20, many).verdict == "does not hold"
    mixed_a = [True] * 6 + [False] * 4 + [True] * 30
    mixed_b = [False] * 6 + [True] * 4 + [True] * 30
    assert paired_success(mixed_a, mixed_b).verdict == "inconclusive"  # 6 vs 4 discordant: an overlap


def test_best_of_needs_every_pairwise_win():
    base = np.linspace(0.0, 1.0, 30)
    values = {"A": base + 1.0, "B": base, "C": base + 0.5}
    assert best_of(values, "A", "higher", _rng()).verdict == "holds"
    assert best_of(values, "C", "higher", _rng()).verdict == "does not hold"
    tied = {"A": base + 1.0, "B": base + 1.0, "C": base}
    assert best_of(tied, "A", "higher", _rng()).verdict == "inconclusive"  # a tie with B is not "best"
    outcomes = {"A": [True] * 98 + [False] * 2, "B": [True] * 98 + [False] * 2}
    assert best_of(outcomes, "A", "higher", _rng(), success=True).verdict == "inconclusive"


def test_on_par_holds_only_inside_the_stated_margin():
    base = np.linspace(0.0, 1.0, 40)
    assert on_par(base + 0.01 * NOISE, base, 0.1, _rng()).verdict == "holds"
    assert on_par(base + 0.5 + 0.01 * NOISE, base, 0.1, _rng()).verdict == "does not hold"
    assert on_par(base + 0.1 + 0.05 * NOISE, base, 0.1, _rng()).verdict == "inconclusive"  # straddles the margin
    with pytest.raises(ValueError, match="margin"):
        on_par(base, base, 0.0, _rng())


def test_magnitude_covers_beyond_direction_only_and_against():
    den = np.full(40, 10.0) + 0.1 * NOISE
    assert magnitude(2.0 * den + 0.1 * NOISE, den, 2.0, _rng()).verdict == "holds"  # covers the paper's 2x
    assert magnitude(3.0 * den, den, 2.0, _rng()).verdict == "holds"  # beyond it, in the claimed direction
    assert magnitude(1.3 * den, den, 2.0, _rng()).verdict == "holds in direction only"
    assert magnitude(0.7 * den, den, 2.0, _rng()).verdict == "does not hold"
    assert magnitude(den + NOISE, den, 2.0, _rng()).verdict == "does not hold"  # a tie rejects "2x"
    assert magnitude(den[:5] * 2, den[:5], 2.0, _rng()).verdict == "inconclusive"  # too few units
    assert magnitude(0.4 * den, den, 0.5, _rng()).verdict == "holds"  # a claimed reduction ("half the cost")
    assert ratio_of_values(3.4, 1.0, 3.5, 0.1).verdict == "holds"
    assert ratio_of_values(1.5, 1.0, 3.5, 0.1).verdict == "holds in direction only"


def test_exact_comparisons_counts_and_every():
    assert exact_comparison(9.06, 7.57, "higher").verdict == "holds"
    assert exact_comparison(5.54, 5.91, "higher").verdict == "does not hold"
    assert exact_comparison(5.0, 5.0, "higher").verdict == "inconclusive"  # equal is never "holds"
    assert exact_comparison(5.01, 5.0, "higher", tolerance=0.05).verdict == "inconclusive"
    assert every([True] * 12).verdict == "holds" and every([True] * 11 + [False]).verdict == "does not hold"
    assert equal_count(7, 12, 7, 12).verdict == "holds"
    assert equal_count(12, 12, 7, 12).verdict == "does not hold"  # 12/12: exact CI [0.74, 1] misses 0.58


def test_claim_records_are_typed_and_a_papers_claim_is_quoted():
    with pytest.raises(ValueError, match="verdict"):
        Claim("x", "mostly holds", "1", quote="q", where="w")
    with pytest.raises(ValueError, match="quote"):
        Claim("x", "holds", "1")  # the paper's, without its sentence
    entry = PaperClaim("k", "TTR solves all", "TTR solves all 12 tasks", "Table II", paper="12/12", report="t2")
    got = entry.decide(every([True] * 12, "tasks"), why="never shown when it holds")
    assert (got.source, got.key, got.quote, got.verdict, got.why) == ("paper", "k", entry.quote, "holds", "")
    assert entry.untested("SuReNav not run").verdict == "not tested"
    assert ours("no plan fails", every([True] * 3)).source == "ours"
    with pytest.raises(ValueError, match="not both"):
        PaperClaim("k", "c", "q", "w", report="t", not_tested="robot")
    with pytest.raises(ValueError, match="twice"):
        registry(entry, entry)
