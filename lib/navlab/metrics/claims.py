"""Strict verdicts on a paper's claims: one rule per kind of claim, shared by the three tracks.

Why one strict implementation: a reproduction is only as useful as the trust a reader can put in its
verdicts. A comparison read off two means ("0.1541 < 0.1542") or a ``>=`` counts ties and noise as
agreement. Every rule here decides on the table's own units (maps, tasks, trips, episodes, seeds),
paired wherever the methods ran on the same units, at the 5% level:

- a comparison ("higher", "fewer", "raises", "outperforms"): :func:`paired_difference` (percentile
  bootstrap of the mean per-unit difference, Efron & Tibshirani 1993, ch. 13) or, for success counts,
  :func:`paired_success` (exact McNemar test: a two-sided binomial sign test on the discordant units,
  McNemar 1947). It holds only when the test finds the difference in the claimed direction; it does
  not hold when it finds the opposite; anything else, a tie included, is *inconclusive*;
- "best of all" (:func:`best_of`): the claimed method beats every other one, each pairwise as above;
- "on par" / "similar" (:func:`on_par`): the margin is part of the claim record; holds only if the
  whole 95% interval of the paired difference lies inside it;
- a magnitude ("about 2x", "44% above", :func:`magnitude`): holds when the interval of our ratio covers
  the paper's value or lies beyond it in the claimed direction; an interval past 1 but short of the
  paper's value is its own verdict, *holds in direction only*; an interval short of it that reaches 1
  rejects the stated magnitude: does not hold;
- a deterministic quantity (a value function at a state, a count over every unit):
  :func:`exact_comparison` / :func:`every`, no sampling, but still strict: equal is never "holds".

A table with too few units for any verdict (fewer than :data:`MIN_UNITS`; an exact sign test's
smallest two-sided p over n units is 2^(1-n)) is inconclusive, and the record says what the test
would need. Each rule returns a :class:`Test` (verdict and the statistic behind it); a track's claim
registry (:class:`PaperClaim`) turns it into the :class:`Claim` a report carries.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np
from scipy.stats import binomtest

from navlab.metrics.intervals import LEVEL, RESAMPLES

Verdict = Literal["holds", "holds in direction only", "does not hold", "inconclusive", "not tested"]
VERDICTS: tuple[str, ...] = get_args(Verdict)
Source = Literal["paper", "ours"]
Direction = Literal["higher", "lower"]
ALPHA = 1.0 - LEVEL
MIN_UNITS = 6  # 2^(1-6) = 0.031 < 0.05: the fewest paired units an exact two-sided test can decide on


@dataclass(frozen=True)
class Test:
    """A rule's outcome: the verdict and the statistic behind it, in words and numbers."""

    verdict: Verdict
    evidence: str


@dataclass(frozen=True)
class Claim:
    """One claim as a report carries it: the paper's (quoted, with where it stands) or ours."""

    claim: str  # the claim in our words
    verdict: Verdict
    ours: str  # the measured numbers and the test behind the verdict
    source: Source = "paper"
    quote: str = ""  # the paper's own sentence, verbatim (source "paper")
    where: str = ""  # section, table or figure of the paper
    paper: str = ""  # the numbers the paper prints for it
    why: str = ""  # what in our set-up explains a verdict other than "holds"
    key: str = ""  # the registry key (source "paper"): ties a report's claim to its track's registry

    def __post_init__(self):
        if self.verdict not in VERDICTS:
            raise ValueError(f"claim {self.claim!r}: verdict {self.verdict!r}; use one of {', '.join(VERDICTS)}")
        if self.source not in get_args(Source):
            raise ValueError(f"claim {self.claim!r}: source {self.source!r}; use 'paper' or 'ours'")
        if self.source == "paper" and not (self.quote and self.where):
            raise ValueError(f"claim {self.claim!r}: a paper's claim needs its quote and where it stands")

    @classmethod
    def from_dict(cls, d: Mapping) -> Claim:
        """A claim as a report's JSON holds it (``dataclasses.asdict``)."""
        return cls(**{k: d.get(k) or "" for k in ("claim", "ours", "quote", "where", "paper", "why", "key")},
                   verdict=d["verdict"], source=d.get("source") or "paper")

    def __str__(self) -> str:
        return f"{self.claim}: {self.verdict} ({self.ours})"


@dataclass(frozen=True)
class PaperClaim:
    """A registry entry: one of the paper's claims, quoted, with the report that decides it here (``report``)
    or, when none does, why it is not tested (``not_tested``)."""

    key: str  # stable identifier within the track
    claim: str  # in our words
    quote: str  # the paper's sentence, verbatim (up to whitespace and case)
    where: str  # section, table or figure
    paper: str = ""  # the numbers the paper prints for it
    report: str = ""  # table id of the report that decides it
    not_tested: str = ""  # why no report decides it
    margin: float | None = None  # "on par" claims: the margin the interval must lie inside

    def __post_init__(self):
        if bool(self.report) == bool(self.not_tested):
            raise ValueError(f"claim {self.key!r}: name the report that decides it or why it is not tested, not both")

    def decide(self, test: Test, ours: str = "", why: str = "") -> Claim:
        """The claim with a rule's verdict; ``ours`` (numbers beside the test's) leads the evidence; ``why``
        is kept unless it holds."""
        evidence = f"{ours}; {test.evidence}" if ours else test.evidence
        return Claim(self.claim, test.verdict, evidence, "paper", self.quote, self.where, self.paper,
                     why if test.verdict != "holds" else "", self.key)

    def untested(self, why: str = "") -> Claim:
        """The claim as not tested: the registry's reason, or ``why`` (a report that cannot test it this run)."""
        return Claim(self.claim, "not tested", "", "paper", self.quote, self.where, self.paper,
                     why or self.not_tested, self.key)


def ours(claim: str, test: Test, detail: str = "", why: str = "") -> Claim:
    """One of our own checks (a diagnostic the paper does not state), counted apart from the paper's."""
    evidence = f"{detail}; {test.evidence}" if detail else test.evidence
    return Claim(claim, test.verdict, evidence, "ours", why=why if test.verdict != "holds" else "")


def registry(*claims: PaperClaim) -> dict[str, PaperClaim]:
    """A track's claims by key; a key given twice is a mistake."""
    out: dict[str, PaperClaim] = {}
    for c in claims:
        if c.key in out:
            raise ValueError(f"claim key {c.key!r} appears twice in the registry")
        out[c.key] = c
    return out


# ---------------------------------------------------------------------------------------------- rules

def _signed(direction: Direction) -> float:
    if direction not in get_args(Direction):
        raise ValueError(f"direction {direction!r}: use 'higher' or 'lower'")
    return 1.0 if direction == "higher" else -1.0


def _paired(a, b) -> tuple[np.ndarray, np.ndarray]:
    a, b = np.asarray(a, dtype=np.float64).ravel(), np.asarray(b, dtype=np.float64).ravel()
    if a.shape != b.shape or a.size == 0:
        raise ValueError(f"a paired test needs two equally long, non-empty samples (got {a.size} and {b.size})")
    if not (np.isfinite(a).all() and np.isfinite(b).all()):
        raise ValueError("a paired test's samples hold NaN or inf: drop the units a method did not finish first")
    return a, b


def _too_few(n: int, unit: str) -> str:
    return (f"{n} {unit}: too few for a verdict; an exact two-sided test at 5% needs at least {MIN_UNITS} paired "
            f"{unit}, all differing the same way")


def _bootstrap(values: np.ndarray, rng: np.random.Generator) -> tuple[float, float]:
    means = values[rng.integers(0, len(values), size=(RESAMPLES, len(values)))].mean(axis=1)
    lo, hi = np.percentile(means, [100 * ALPHA / 2, 100 * (1 - ALPHA / 2)])
    return float(lo), float(hi)


def _side(lo: float, hi: float, sign: float) -> Verdict:
    """A two-sided interval of a (signed) difference against zero: wholly on the claimed side, wholly on the
    other, or covering zero (a tie's degenerate [0, 0] included)."""
    lo, hi = sorted((sign * lo, sign * hi))
    return "holds" if lo > 0 else "does not hold" if hi < 0 else "inconclusive"


def paired_difference(a, b, direction: Direction, rng: np.random.Generator, unit: str = "units",
                      names: tuple[str, str] = ("A", "B")) -> Test:
    """Is ``a`` ``direction`` than ``b`` on the same units? The 95% bootstrap interval of mean(a - b)."""
    a, b = _paired(a, b)
    sign, n = _signed(direction), len(a)
    d = a - b
    if n < MIN_UNITS:
        return Test("inconclusive", f"{names[0]} - {names[1]} = {d.mean():+.4g}; " + _too_few(n, unit))
    lo, hi = _bootstrap(d, rng)
    return Test(_side(lo, hi, sign), f"{names[0]} - {names[1]} = {d.mean():+.4g}, 95% CI [{lo:+.4g}, {hi:+.4g}], "
                                     f"paired over {n} {unit}")


def paired_success(a, b, direction: Direction = "higher", unit: str = "tasks",
                   names: tuple[str, str] = ("A", "B")) -> Test:
    """Does ``a`` succeed more often (``higher``) than ``b`` on the same units? Exact McNemar test on the
    discordant units (a two-sided binomial sign test); a tie (no or balanced discordant units) is never
    "holds"."""
    a, b = np.asarray(a, dtype=bool).ravel(), np.asarray(b, dtype=bool).ravel()
    if a.shape != b.shape or a.size == 0:
        raise ValueError(f"paired_success needs two equally long, non-empty outcome lists (got {a.size}, {b.size})")
    sign = _signed(direction)
    only_a, only_b = int((a & ~b).sum()), int((b & ~a).sum())
    counts = (f"{names[0]} {int(a.sum())}/{a.size}, {names[1]} {int(b.sum())}/{b.size}; discordant {unit}: "
              f"{only_a} only {names[0]}, {only_b} only {names[1]}")
    if only_a + only_b < MIN_UNITS:
        return Test("inconclusive", f"{counts}; {_too_few(only_a + only_b, 'discordant ' + unit)}")
    p = binomtest(only_a, only_a + only_b, 0.5).pvalue
    verdict: Verdict = "inconclusive"
    if p < ALPHA:
        verdict = "holds" if sign * (only_a - only_b) > 0 else "does not hold"
    return Test(verdict, f"{counts}; exact McNemar p = {p:.3g}")


def best_of(values: Mapping[str, Sequence], claimed: str, direction: Direction, rng: np.random.Generator,
            unit: str = "units", success: bool = False) -> Test:
    """Is ``claimed`` the best of all ``values`` (per-unit samples by method, the same units)? It holds only
    if it beats each other method (paired); it does not hold if any other beats it; else inconclusive."""
    if claimed not in values or len(values) < 2:
        raise ValueError(f"best_of: {claimed!r} and at least one other method are needed (got {list(values)})")
    tests = {m: (paired_success(values[claimed], v, direction, unit, (claimed, m)) if success else
                 paired_difference(values[claimed], v, direction, rng, unit, (claimed, m)))
             for m, v in values.items() if m != claimed}
    verdicts = {t.verdict for t in tests.values()}
    verdict: Verdict = ("does not hold" if "does not hold" in verdicts else
                        "holds" if verdicts == {"holds"} else "inconclusive")
    return Test(verdict, " | ".join(f"vs {m}: {t.verdict} ({t.evidence})" for m, t in tests.items()))


def all_of(parts: Mapping[str, Test]) -> Test:
    """One verdict for a claim stated for every part (every city, both metrics, each pruner, each pair of an
    ordering): holds if every part holds, does not hold if any part does not, holds in direction only if
    every part holds at least in direction, else inconclusive. The evidence names each part's."""
    if not parts:
        raise ValueError("all_of: no parts to combine")
    verdicts = {t.verdict for t in parts.values()}
    verdict: Verdict = ("does not hold" if "does not hold" in verdicts else "holds" if verdicts == {"holds"} else
                        "holds in direction only" if verdicts <= {"holds", "holds in direction only"} else
                        "inconclusive")
    return Test(verdict, " | ".join(f"{part}: {t.verdict} ({t.evidence})" for part, t in parts.items()))


def on_par(a, b, margin: float, rng: np.random.Generator, unit: str = "units",
           names: tuple[str, str] = ("A", "B")) -> Test:
    """Equivalence within ``margin`` (stated in the claim record): holds if the whole 95% interval of the
    paired mean difference lies inside (-margin, margin), does not hold if it lies wholly outside."""
    if not margin > 0:
        raise ValueError(f"on_par: margin {margin} must be positive")
    a, b = _paired(a, b)
    d = a - b
    if len(d) < MIN_UNITS:
        return Test("inconclusive", f"{names[0]} - {names[1]} = {d.mean():+.4g}; " + _too_few(len(d), unit))
    lo, hi = _bootstrap(d, rng)
    verdict: Verdict = ("holds" if -margin < lo and hi < margin else
                        "does not hold" if lo >= margin or hi <= -margin else "inconclusive")
    return Test(verdict, f"{names[0]} - {names[1]} = {d.mean():+.4g}, 95% CI [{lo:+.4g}, {hi:+.4g}] over {len(d)} "
                         f"{unit}; on par means inside ±{margin:g}")


def magnitude(numerators, denominators, paper_ratio: float, rng: np.random.Generator, unit: str = "units",
              names: tuple[str, str] = ("A", "B")) -> Test:
    """A stated ratio ("about 2x", "44% above": ``paper_ratio`` 2.0, 1.44) of mean(numerators) to
    mean(denominators), resampling the paired units: holds when the 95% interval covers the paper's value
    or lies beyond it; *holds in direction only* when it lies past 1 on the paper's side but short of its
    value; else it excludes the stated magnitude: does not hold (inconclusive only with too few units)."""
    num, den = _paired(numerators, denominators)
    n = len(num)
    ratio = num.mean() / den.mean() if den.mean() != 0 else np.inf
    head = f"{names[0]} / {names[1]} = {ratio:.3g} (paper {paper_ratio:g})"
    if n < MIN_UNITS:
        return Test("inconclusive", f"{head}; {_too_few(n, unit)}")
    draws = rng.integers(0, n, size=(RESAMPLES, n))
    ratios = num[draws].mean(axis=1) / np.maximum(np.abs(den[draws].mean(axis=1)), 1e-300)
    lo, hi = (float(x) for x in np.percentile(ratios, [100 * ALPHA / 2, 100 * (1 - ALPHA / 2)]))
    return Test(_ratio_verdict(lo, hi, paper_ratio), f"{head}, 95% CI [{lo:.3g}, {hi:.3g}] over {n} {unit}")


def _ratio_verdict(lo: float, hi: float, paper_ratio: float) -> Verdict:
    """Covers the paper's ratio or lies beyond it: holds; short of it but wholly past 1: holds in direction
    only; otherwise the interval excludes the stated magnitude (a tie included): does not hold."""
    up = paper_ratio > 1
    if lo <= paper_ratio <= hi or (lo > paper_ratio if up else hi < paper_ratio):
        return "holds"
    if (lo > 1) if up else (hi < 1):
        return "holds in direction only"
    return "does not hold"


def ratio_of_values(value: float, reference: float, paper_ratio: float, tolerance: float,
                    names: tuple[str, str] = ("A", "B")) -> Test:
    """A stated ratio on two single measurements with a known relative ``tolerance`` (a timing's spread
    over repeats): the interval value/reference x (1 ± tolerance) is judged as :func:`magnitude` does."""
    ratio = value / reference
    lo, hi = ratio * (1 - tolerance), ratio * (1 + tolerance)
    return Test(_ratio_verdict(lo, hi, paper_ratio),
                f"{names[0]} / {names[1]} = {ratio:.3g} [{lo:.3g}, {hi:.3g}] (paper {paper_ratio:g})")


def exact_comparison(a: float, b: float, direction: Direction, names: tuple[str, str] = ("A", "B"),
                     tolerance: float = 0.0) -> Test:
    """A comparison of two deterministic values (no sampling: a value function at a state): holds when
    ``a`` is ``direction`` than ``b`` by more than ``tolerance`` (the numerics' error), does not hold when
    it is the other way by more than that, else (equal within it) inconclusive."""
    d = _signed(direction) * (a - b)
    verdict: Verdict = "holds" if d > tolerance else "does not hold" if d < -tolerance else "inconclusive"
    return Test(verdict, f"{names[0]} {a:.4g} vs {names[1]} {b:.4g} (deterministic; tolerance {tolerance:g})")


def every(outcomes, unit: str = "units", name: str = "") -> Test:
    """"Solves every task", "100% SR": holds when every unit succeeded, does not hold otherwise."""
    o = np.asarray(outcomes, dtype=bool).ravel()
    if o.size == 0:
        raise ValueError("every: no outcomes")
    who = f"{name} " if name else ""
    return Test("holds" if o.all() else "does not hold", f"{who}{int(o.sum())}/{o.size} {unit}")


def equal_count(ours_count: int, of: int, paper_count: int, paper_of: int, unit: str = "tasks") -> Test:
    """A count the paper states ("fails 5 of 12"): the exact two-sided binomial interval of our rate holds
    the paper's rate (holds) or not (does not hold)."""
    ci = binomtest(ours_count, of).proportion_ci(LEVEL, method="exact")
    rate = paper_count / paper_of
    verdict: Verdict = "holds" if ci.low <= rate <= ci.high else "does not hold"
    return Test(verdict, f"{ours_count}/{of} {unit}, 95% CI [{ci.low:.2f}, {ci.high:.2f}] vs the paper's "
                         f"{paper_count}/{paper_of} = {rate:.2f}")


def tally(claims: Sequence[Claim]) -> dict[str, int]:
    """How many claims have each verdict, every verdict listed."""
    return {v: sum(c.verdict == v for c in claims) for v in VERDICTS}
