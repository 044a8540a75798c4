"""The HJ closed-loop tables as curves over a setting the paper does not state (issue 26; the sweep is
``hj.sweeps``): the report rows of every point and the curves along each axis.

The checks along these curves are ours, not the paper's claims (``hj.claims.budget_claims`` and
``loop_claims``): each says at which settings the paper's pattern of counts appears ("holds at <= 3,000
expansions per re-plan"), so a reader sees whether a finding is wrong or sits at another setting.
"""

from __future__ import annotations

from collections.abc import Sequence

BUDGET_COLUMNS = ["method", "room", "setting", "budget", "success", "trips", "success_rate", "success_rate_ci", "wall_hits",
                  "deadlocks", "timeouts"]
LOOP_COLUMNS = ["method", "scenario", "setting", "replan_hz", "human_noise_m", "human_prediction_s", "success", "runs",
                "success_rate", "success_rate_ci", "collisions", "contacts_on_plan"]


def budget_rows(results: Sequence[dict]) -> list[dict]:
    """Table VIII rows of every ``budget`` point, with the point's budget."""
    return [{"setting": f"{r['value']:,} expansions", "budget": r["value"],
             **{k: row[k] for k in BUDGET_COLUMNS if k in row}}
            for r in results if r["kind"] == "budget" for row in r["rows"]]


def loop_rows(results: Sequence[dict]) -> list[dict]:
    """Table VI rows of every ``loop`` point, with its rate, noise and prediction horizon."""
    out = []
    for r in results:
        if r["kind"] != "loop":
            continue
        hz, noise, ahead = r["value"]
        for row in r["rows"]:
            out.append({"setting": f"{hz:g} Hz, {noise:g} m, {ahead:g} s", "replan_hz": hz, "human_noise_m": noise,
                        "human_prediction_s": ahead,
                        **{k: row[k] for k in LOOP_COLUMNS if k in row}})
    return out


LOOP_AXES = {"replan_hz": "Hz re-planning", "human_noise_m": "m of human-position noise",
             "human_prediction_s": "s of human prediction"}


def loop_curve(rows: Sequence[dict], axis: str, own: tuple[float, float, float]) -> list[dict]:
    """The rows along ``axis`` (a LOOP_AXES key) with the other two settings at the table's own ``own`` =
    (re-plan Hz, human noise m, prediction s)."""
    others = {k: v for k, v in zip(LOOP_AXES, own, strict=True) if k != axis}
    return [r for r in rows if all(r[k] == v for k, v in others.items())]
