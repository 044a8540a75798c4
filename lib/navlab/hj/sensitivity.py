"""The HJ closed-loop claims as curves over a setting the paper does not state (issue 26; the sweep is
``hj.sweeps``): report rows per point, and each claim's verdict as the range of settings where it holds.

A claim is checked at every point of its curve with the table's own rule (``hj.closed_loop``'s
counts); its verdict is "holds" where it holds at every point, "does not hold" where at none, and
"inconclusive" in between, with the range that decides it stated ("holds at <= 3,000 expansions per
re-plan"), so a reader sees whether the paper's finding is wrong or sits at another setting.
"""

from __future__ import annotations

from collections.abc import Sequence

from navlab.metrics.tables import Claim

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


def _fmt(v: float) -> str:
    return f"{v:,.0f}" if float(v).is_integer() else f"{v:g}"


def holding_range(values: Sequence[float], holds: Sequence[bool], unit: str) -> str:
    """Where along a sorted axis a claim holds: "at every ...", "at none of ...", "at <= x", "at >= x", or the
    list of points."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    v, h = [values[i] for i in order], [holds[i] for i in order]
    span = f"{_fmt(v[0])}-{_fmt(v[-1])} {unit}"
    if all(h):
        return f"holds at every point measured ({span})"
    if not any(h):
        return f"holds at none of the points measured ({span})"
    k = h.index(False) if h[0] else h.index(True)
    if all(h[:k]) and not any(h[k:]):
        return f"holds at <= {_fmt(v[k - 1])} {unit}, not from {_fmt(v[k])} (of {span})"
    if not any(h[:k]) and all(h[k:]):
        return f"holds at >= {_fmt(v[k])} {unit}, not at {_fmt(v[k - 1])} or below (of {span})"
    return f"holds at {', '.join(_fmt(x) for x, ok in zip(v, h, strict=True) if ok)} {unit} only (of {span})"


def _verdict(text: str, holds: Sequence[bool], detail: str, counts: str) -> Claim:
    """The claim over the curve: holds at every point, at none, or inconclusive (where; the counts)."""
    verdict = "holds" if all(holds) else "does not hold" if not any(holds) else "inconclusive"
    return Claim(text, verdict, f"{detail}; successes {counts}")


def _success(rows: Sequence[dict], **match) -> dict[str, int]:
    """method -> successes among ``rows`` matching every key of ``match``."""
    return {r["method"]: r["success"] for r in rows if all(r[k] == v for k, v in match.items())}


def _counts(cells: Sequence[tuple[float, list[dict]]], methods: Sequence[str], n_key: str) -> str:
    """The measured successes behind a verdict: "a / b / c of n at x; ..." per point (methods in order)."""
    parts = []
    for value, cell in cells:
        s = _success(cell)
        parts.append(f"{' / '.join(str(s[m]) for m in methods)} of {cell[0][n_key]} at {_fmt(value)}")
    return f"{', '.join(methods)}: " + "; ".join(parts)


def budget_claims(rows: Sequence[dict]) -> list[Claim]:
    """Table VIII's two claims along the per-re-plan budget; the why gives every row's successes per point."""
    budgets = sorted({r["budget"] for r in rows})
    methods = ("Dist + OBS", "Dist + BRT", "TTR + OBS", "TTR + BRT")
    unit = "expansions per re-plan"
    rules = (("Long Hallway", "in the Long Hallway TTR succeeds more often than Dist under both pruners",
              lambda s, n: s["TTR + OBS"] > s["Dist + OBS"] and s["TTR + BRT"] > s["Dist + BRT"]),
             ("Dense Room", "in the Dense Room only TTR + BRT succeeds on every trip",
              lambda s, n: s["TTR + BRT"] == n and all(s[m] < n for m in s if m != "TTR + BRT")))
    claims = []
    for room, text, rule in rules:
        cells = [(b, [r for r in rows if r["room"] == room and r["budget"] == b]) for b in budgets]
        holds = [rule(_success(cell), cell[0]["trips"]) for _, cell in cells]
        claims.append(_verdict(text, holds, holding_range(budgets, holds, unit), _counts(cells, methods, "trips")))
    return claims


LOOP_AXES = {"replan_hz": "Hz re-planning", "human_noise_m": "m of human-position noise",
             "human_prediction_s": "s of human prediction"}


def loop_curve(rows: Sequence[dict], axis: str, own: tuple[float, float, float]) -> list[dict]:
    """The rows along ``axis`` (a LOOP_AXES key) with the other two settings at the table's own ``own`` =
    (re-plan Hz, human noise m, prediction s)."""
    others = {k: v for k, v in zip(LOOP_AXES, own, strict=True) if k != axis}
    return [r for r in rows if all(r[k] == v for k, v in others.items())]


def loop_claims(rows: Sequence[dict], own: tuple[float, float, float]) -> list[Claim]:
    """Table VI's two claims along each of the three axes (``loop_curve``); the why gives every row's
    successful runs per point."""
    rules = (
        ("Face-to-Face", "FI-BRT clears every Face-to-Face run, FS-BRT and OBS do not",
         lambda s, n: s["FI-BRT"] == n and s["FS-BRT"] < n and s["OBS"] < n),
        ("Zig-Zag", "FI-BRT and FS-BRT clear every Zig-Zag run, OBS does not",
         lambda s, n: s["FI-BRT"] == n and s["FS-BRT"] == n and s["OBS"] < n),
    )
    claims = []
    for scenario, text, rule in rules:
        for axis, unit in LOOP_AXES.items():
            curve = [r for r in loop_curve(rows, axis, own) if r["scenario"] == scenario]
            values = sorted({r[axis] for r in curve})
            if len(values) < 2:
                continue
            cells = [(v, [r for r in curve if r[axis] == v]) for v in values]
            holds = [rule(_success(cell), cell[0]["runs"]) for _, cell in cells]
            claims.append(_verdict(f"{text}, along {unit}", holds, holding_range(values, holds, unit),
                                   _counts(cells, ("FI-BRT", "FS-BRT", "OBS"), "runs")))
    return claims
