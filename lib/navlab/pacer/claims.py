"""PACER's printed numbers (Tables I-V) and the checks of its claims against what we measured.

The paper (Mao et al., RA-L 2025, Sec. VI) makes five claims that its tables support:

1. seen environments (Table I, question 1a): PACER is on par with STERLING;
2. seen, uninformative context (1b): PACER is on par with the classifier (a learned realistic prior);
3. unseen environments (Table II, 2a): PACER beats STERLING; with an uninformative context (2b) it
   cannot adapt (worse than with an informative one);
4. ablation (Table III): the phase-1 model (D_real only) cannot follow inverted preferences;
5. ablation (Tables IV, V): the synthetic phase generalises best to unseen terrains.

Every check compares methods *on the same maps* through a paired bootstrap interval of the per-map
difference (``navlab.metrics.intervals``), and answers one of three verdicts: ``holds``, ``does not
hold`` or ``inconclusive`` (the interval cannot tell). "On par" means the whole 95% interval of the
difference lies within ``PAR_MARGIN`` of zero; "beats" means it lies above zero. The notebooks only
call these functions and print what they return.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from navlab.core.seeding import rng
from navlab.metrics.intervals import bootstrap_mean_ci, bootstrap_ratio_ci
from navlab.metrics.tables import Claim

PAR_MARGIN = 0.10  # "on par": the low-tier share differs by less than this, with 95% confidence
CHANCE_MARGIN = 0.60  # "cannot follow": pair agreement not clearly above chance (CI's upper end below this)
TIERS = ("low", "medium", "high")


def _tier_rows(key: str, rows: Mapping[str, Sequence[float]]) -> list[dict]:
    return [{key: name, **dict(zip(TIERS, values, strict=True))} for name, values in rows.items()]


def _phase_rows(rows: Mapping[tuple[str, str], Sequence[float]]) -> list[dict]:
    return [{"preference": p, "model": m, **dict(zip(TIERS, v, strict=True))} for (p, m), v in rows.items()]


# The paper's numbers, as printed (percentages as fractions; Table II's STERLING row sums to 98.37 % in
# the paper itself). Our STERLING row is "STERLING-style".
PAPER = {
    "table1_seen": _tier_rows("method", {
        "PACER": (0.7383, 0.1970, 0.0647),
        "PACER (uninformative context)": (0.6797, 0.1589, 0.1615),
        "STERLING-style": (0.7472, 0.1865, 0.0663),
        "Classifier": (0.6586, 0.2146, 0.1269),
        "Ground truth": (0.8282, 0.1369, 0.0349),
    }),
    "table2_unseen": _tier_rows("method", {
        "PACER": (0.8185, 0.0800, 0.1015),
        "PACER (uninformative context)": (0.5383, 0.0220, 0.4397),
        "STERLING-style": (0.6139, 0.1012, 0.2686),
        "Ground truth": (0.9185, 0.0602, 0.0213),
    }),
    "table3_phases_seen": _phase_rows({
        ("realistic", "D_real"): (0.9597, 0.0170, 0.0232),
        ("realistic", "D_shuffled"): (0.7050, 0.1894, 0.1055),
        ("realistic", "D_synthetic"): (0.7666, 0.1843, 0.0491),
        ("inverted", "D_real"): (0.1855, 0.2097, 0.6048),
        ("inverted", "D_shuffled"): (0.6921, 0.2256, 0.0823),
        ("inverted", "D_synthetic"): (0.7022, 0.2132, 0.0846),
    }),
    "table4_phases_unseen": _phase_rows({
        ("realistic", "D_real"): (0.6078, 0.0705, 0.3218),
        ("realistic", "D_shuffled"): (0.6516, 0.0644, 0.2840),
        ("realistic", "D_synthetic"): (0.8809, 0.0257, 0.0934),
        ("inverted", "D_real"): (0.2259, 0.1531, 0.6210),
        ("inverted", "D_shuffled"): (0.3986, 0.1396, 0.4617),
        ("inverted", "D_synthetic"): (0.6565, 0.2210, 0.1225),
    }),
    "table5_margin_ranking": [
        {"model": "D_real", "test_real": 0.017, "test_shuffled": 0.099, "test_synthetic": 0.072},
        {"model": "D_shuffled", "test_real": 0.086, "test_shuffled": 0.019, "test_synthetic": 0.064},
        {"model": "D_synthetic", "test_real": 0.053, "test_shuffled": 0.069, "test_synthetic": 0.013},
    ],
    "context_following": [],  # ours: the paper reports no held-out agreement
}
GAP_TARGET = 0.75  # issue 24's goal: share of the chance-to-oracle gap the phase-3 model closes (never tuned to)
TRAINING_BUDGET_MIN = 45.0  # issue 24: `default` trains every phase and both baselines within this on 2 cores
AGREEMENT_TARGET = 0.85  # issue 14's goal for the default phase-3 model on each of the four sets (never tuned to)


def sentence(claim: Claim) -> str:
    """How PACER's notes state a claim among their prose: ``Claim '<claim>': <verdict> (<ours>).`` (the form
    ``pipeline.results.claims_of`` reads back)."""
    return f"Claim '{claim.claim}': {claim.verdict} ({claim.ours})."


def paired_difference(a: np.ndarray, b: np.ndarray, *keys: object) -> tuple[float, tuple[float, float]]:
    """(mean, 95% interval) of a - b over the same environments (paired bootstrap, seeded by ``keys``)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if a.shape != b.shape or a.ndim != 1 or len(a) == 0:
        raise ValueError(f"paired_difference needs two equal-length 1-D samples (got {a.shape} and {b.shape})")
    return float((a - b).mean()), bootstrap_mean_ci(a - b, rng(0, "pacer.claims", *keys))


def on_par(statement: str, a: np.ndarray, b: np.ndarray, names: tuple[str, str], *keys: object) -> Claim:
    """Equivalence within ``PAR_MARGIN``: holds if the whole interval of a - b is inside ±margin, does
    not hold if it lies wholly outside, else inconclusive."""
    mean, (lo, hi) = paired_difference(a, b, *keys)
    if -PAR_MARGIN < lo and hi < PAR_MARGIN:
        verdict = "holds"
    elif lo >= PAR_MARGIN or hi <= -PAR_MARGIN:
        verdict = "does not hold"
    else:
        verdict = "inconclusive"
    return Claim(statement, verdict, f"{names[0]} - {names[1]} = {mean:+.3f}, 95% CI [{lo:+.3f}, {hi:+.3f}] "
                                     f"over {len(a)} maps; on par means inside ±{PAR_MARGIN:g}")


def greater(statement: str, a: np.ndarray, b: np.ndarray, names: tuple[str, str], *keys: object) -> Claim:
    """a > b: holds if the interval of a - b lies above 0, does not hold if it lies below, else inconclusive."""
    mean, (lo, hi) = paired_difference(a, b, *keys)
    verdict = "holds" if lo > 0 else "does not hold" if hi < 0 else "inconclusive"
    return Claim(statement, verdict, f"{names[0]} - {names[1]} = {mean:+.3f}, 95% CI [{lo:+.3f}, {hi:+.3f}] "
                                     f"over {len(a)} maps")


def _low(shares: Mapping[str, np.ndarray | None], name: str) -> np.ndarray:
    values = shares.get(name)
    if values is None:
        raise ValueError(f"no per-map shares for {name!r}: it cannot take this preference")
    return np.asarray(values)[:, 0]


def seen_claims(shares: Mapping[str, np.ndarray | None]) -> list[Claim]:
    """Table I (questions 1a/1b) from per-map (low, medium, high) shares keyed by method."""
    return [
        on_par("PACER is on par with STERLING in seen environments (1a)", _low(shares, "PACER"),
               _low(shares, "STERLING-style"), ("PACER low", "STERLING low"), "seen", "sterling"),
        on_par("PACER with an uninformative context is on par with the classifier (1b)",
               _low(shares, "PACER (uninformative context)"), _low(shares, "Classifier"),
               ("PACER-uninformative low", "classifier low"), "seen", "classifier"),
    ]


def unseen_claims(shares: Mapping[str, np.ndarray | None]) -> list[Claim]:
    """Table II (questions 2a/2b)."""
    return [
        greater("PACER beats STERLING in unseen environments (2a)", _low(shares, "PACER"),
                _low(shares, "STERLING-style"), ("PACER low", "STERLING low"), "unseen", "sterling"),
        greater("without an informative context PACER cannot adapt to unseen terrain (2b)", _low(shares, "PACER"),
                _low(shares, "PACER (uninformative context)"), ("informative low", "uninformative low"),
                "unseen", "uninformative"),
    ]


def phase1_cannot_follow_inverted(agreement: tuple[float, tuple[float, float] | None],
                                  phase1_low: np.ndarray, phase3_low: np.ndarray) -> Claim:
    """Table III: the D_real model's held-out pair agreement under inverted contexts on seen terrain is
    not clearly above chance (its 95% interval's upper end below ``CHANCE_MARGIN``); the maps' inverted
    low-tier shares of phase 1 vs phase 3 are given as evidence."""
    fraction, ci = agreement
    mean, (lo, hi) = paired_difference(phase3_low, phase1_low, "phase1", "inverted")
    evidence = (f"phase-1 pair agreement with inverted contexts {fraction:.3f}"
                + (f", 95% CI [{ci[0]:.3f}, {ci[1]:.3f}]" if ci else "")
                + f" (chance 0.5; 'cannot follow' means the CI's upper end is below {CHANCE_MARGIN:g}); on the "
                f"maps, inverted low-tier share phase 3 - phase 1 = {mean:+.3f}, 95% CI [{lo:+.3f}, {hi:+.3f}]")
    if ci is None:
        return Claim("phase 1 (D_real) cannot follow inverted preferences", "inconclusive", evidence)
    verdict = "holds" if ci[1] < CHANCE_MARGIN else "does not hold" if ci[0] > CHANCE_MARGIN else "inconclusive"
    return Claim("phase 1 (D_real) cannot follow inverted preferences", verdict, evidence)


def synthetic_generalises_best(unseen_low: Mapping[str, np.ndarray]) -> Claim:
    """Table IV: on unseen maps, D_synthetic's low-tier share (realistic and inverted preferences, per
    map) beats each other phase's (paired intervals above 0)."""
    others = [m for m in unseen_low if m != "D_synthetic"]
    tests = [greater("", unseen_low["D_synthetic"], unseen_low[m], ("D_synthetic", m), "synthetic", m)
             for m in others]
    verdicts = {t.verdict for t in tests}
    verdict = "holds" if verdicts == {"holds"} else "does not hold" if "does not hold" in verdicts else "inconclusive"
    return Claim("the synthetic phase generalises best to unseen terrains", verdict,
                 "; ".join(t.ours for t in tests) + " (low-tier share, realistic and inverted maps together)")


def gap_fraction(low: np.ndarray, chance_low: np.ndarray, ceiling_low: np.ndarray) -> float | None:
    """sum(low - chance) / sum(ceiling - chance) over maps; None where the ceiling gains nothing on chance."""
    room = float(np.sum(np.asarray(ceiling_low, dtype=np.float64) - np.asarray(chance_low, dtype=np.float64)))
    gain = float(np.sum(np.asarray(low, dtype=np.float64) - np.asarray(chance_low, dtype=np.float64)))
    return gain / room if room > 0 else None


def gap_closed(name: str, low: np.ndarray, chance_low: np.ndarray, ceiling_low: np.ndarray, *keys: object,
               why: str = "") -> Claim:
    """What the robot gains, on a scale fixed by two references on the same maps: the share of the gap
    from the uniform costmap (chance) to the window oracle (ceiling) that ``name``'s low-tier share
    closes, sum(model - chance) / sum(ceiling - chance), with a bootstrap 95% interval over maps.
    Holds when the interval lies at or above ``GAP_TARGET``, does not when it lies below; ``why`` (measured
    diagnostics) goes with any verdict but holds."""
    gain = np.asarray(low, dtype=np.float64) - np.asarray(chance_low, dtype=np.float64)
    room = np.asarray(ceiling_low, dtype=np.float64) - np.asarray(chance_low, dtype=np.float64)
    statement = f"{name} closes at least {GAP_TARGET:.0%} of the chance-to-oracle gap ({', '.join(map(str, keys))})"
    if room.sum() <= 0:
        return Claim(statement, "inconclusive", "the oracle keeps no more to the low tier than chance here")
    share = float(gain.sum() / room.sum())
    lo, hi = bootstrap_ratio_ci(gain, room, rng(0, "pacer.gap", name, *keys))
    verdict = "holds" if lo >= GAP_TARGET else "does not hold" if hi < GAP_TARGET else "inconclusive"
    return Claim(statement, verdict, f"{share:.2f} of the gap, 95% CI [{lo:.2f}, {hi:.2f}] over {len(gain)} maps "
                                     f"(chance {np.mean(chance_low):.3f}, ceiling {np.mean(ceiling_low):.3f}, "
                                     f"{name} {np.mean(low):.3f})", why=why if verdict != "holds" else "")


def margin_ranking_claims(rows: Sequence[Mapping[str, float]]) -> list[Claim]:
    """Table V: each model has the lowest error on its own training set's test split; D_synthetic has
    the lowest or second-lowest error on every test set."""
    own = {"test_real": "D_real", "test_shuffled": "D_shuffled", "test_synthetic": "D_synthetic"}
    ranked = {c: [r["model"] for r in sorted(rows, key=lambda r: r[c])] for c in own}
    diagonal = all(ranked[c][0] == m for c, m in own.items())
    top_two = all("D_synthetic" in ranked[c][:2] for c in own)
    order = "; ".join(f"{c}: {' < '.join(ranked[c])}" for c in own)
    return [Claim("each model is best on its own training set", "holds" if diagonal else "does not hold", order),
            Claim("D_synthetic is lowest or second-lowest on every test set", "holds" if top_two else "does not hold",
                  order)]


def agreement_against_target(agreement: Mapping[tuple[str, str], tuple[float, tuple[float, float] | None]],
                             training: Mapping[str, object] | None = None) -> str:
    """One sentence: the phase-3 held-out agreement on each (terrains, preference) set beside the target,
    and, given its ``training`` summary (``summary.json``), how much training it had: optimiser steps,
    whether early stopping ended it, and its best validation loss beside the entropy floor."""
    parts = [f"{env}/{pref} {frac:.3f}" + (f" [{ci[0]:.3f}, {ci[1]:.3f}]" if ci else "")
             for (env, pref), (frac, ci) in agreement.items()]
    met = all(frac >= AGREEMENT_TARGET for frac, _ in agreement.values())
    sentence = (f"phase-3 held-out pair agreement with superset contexts: {', '.join(parts)}; the target of "
                f"{AGREEMENT_TARGET:g} on each set is {'met' if met else 'NOT met'}")
    if training is not None:
        t = training
        stop = "stopped early" if t["stopped_early"] else "ran every epoch"
        sentence += (f" after {t['steps']} optimiser steps in phase 3 ({t['epochs_run']} of {t['max_epochs']} epochs, "
                     f"{stop}; best epoch {t['best_epoch']}, validation loss {t['best_val_loss']:.3f} beside the "
                     f"entropy floor {t['entropy_floor']:.3f})")
    return sentence
