"""HJ-search paper (Hu, Siu & Chen), closed-loop tables: its printed numbers for Tables VI, VIII and IX, the
summaries our tables use (Sec. VII-D, VIII-B, VIII-C). Its claims and their verdicts: ``hj.claims``.

Scoring follows the paper. A trip (one goal to the next) succeeds only without a collision, deadlock or
timeout (an "external intervention"); a Table VI run succeeds when all of its trips do. Table VI's time
is the mean navigation time of the successful runs ("Failed": none); Table VIII's the total time of the
successful trips ("Failed": none); Table IX's the total time of the whole patrol and its collision count
(contacts with humans plus static collisions). The paper gives bare counts; ours carry Wilson 95 %
intervals, and means over runs a 95 % bootstrap interval over runs.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from navlab.hj.paper import bootstrap_mean, wilson
from navlab.hj.receding_horizon import Run

PAPER = {
    "table6_dynamic": [
        {"method": "FI-BRT", "scenario": "Face-to-Face", "success": 5, "runs": 5, "time_s": 15.64,
         "detour_m": 3.5},  # Fig. 8: "starts to detour when the relative distance is still approximately 3.5 m"
        {"method": "FS-BRT", "scenario": "Face-to-Face", "success": 0, "runs": 5, "time_s": None},
        {"method": "OBS", "scenario": "Face-to-Face", "success": 0, "runs": 5, "time_s": None},
        # the paper's Zig-Zag times, also as time_all_s: its text does not say over which runs they average
        {"method": "FI-BRT", "scenario": "Zig-Zag", "success": 5, "runs": 5, "time_s": 39.85, "time_all_s": 39.85},
        {"method": "FS-BRT", "scenario": "Zig-Zag", "success": 5, "runs": 5, "time_s": 31.17, "time_all_s": 31.17},
        {"method": "OBS", "scenario": "Zig-Zag", "success": 1, "runs": 5, "time_s": 30.41, "time_all_s": 30.41},
    ],
    "table8_rooms": [
        {"method": "Dist + OBS", "room": "Long Hallway", "success": 2, "trips": 9, "time_s": 29.8},
        {"method": "Dist + BRT", "room": "Long Hallway", "success": 2, "trips": 9, "time_s": 24.5},
        {"method": "TTR + OBS", "room": "Long Hallway", "success": 9, "trips": 9, "time_s": 89.6},
        {"method": "TTR + BRT", "room": "Long Hallway", "success": 9, "trips": 9, "time_s": 85.9},
        {"method": "Dist + OBS", "room": "Dense Room", "success": 0, "trips": 6, "time_s": None},
        {"method": "Dist + BRT", "room": "Dense Room", "success": 1, "trips": 6, "time_s": 20.1},
        {"method": "TTR + OBS", "room": "Dense Room", "success": 0, "trips": 6, "time_s": None},
        {"method": "TTR + BRT", "room": "Dense Room", "success": 6, "trips": 6, "time_s": 115.6},
    ],
    "table9_humans": [
        {"method": "FI-BRT", "setting": "1 human", "humans": 1, "time_s": 157.6, "collisions": 0},
        {"method": "FS-BRT", "setting": "1 human", "humans": 1, "time_s": 118.2, "collisions": 0},
        {"method": "OBS", "setting": "1 human", "humans": 1, "time_s": 111.5, "collisions": 1},
        {"method": "FI-BRT", "setting": "2 humans", "humans": 2, "time_s": 264.3, "collisions": 0},
        {"method": "FS-BRT", "setting": "2 humans", "humans": 2, "time_s": 171.3, "collisions": 0},
        {"method": "OBS", "setting": "2 humans", "humans": 2, "time_s": 134.9, "collisions": 3},
    ],
}


def _ci(ci) -> list | None:
    return None if ci is None or any(not math.isfinite(c) for c in ci) else [round(float(c), 4) for c in ci]


def _rate(k: int, n: int) -> tuple[float | None, list | None]:
    return (k / n, _ci(wilson(k, n))) if n else (None, None)


def run_success(run: Run) -> bool:
    """A run of Table VI succeeds when every trip does (no contact, deadlock, timeout or wall hit)."""
    return all(t.success for t in run.trips)


def summarise_runs(method: str, scenario: str, runs: Sequence[Run], seed: int,
                   detours: Sequence[dict | None] | None = None) -> dict:
    """Table VI row: successful runs (Wilson), human contacts, mean navigation time of the successes (the
    paper's "Failed" where none), of all runs (contacts do not stop a run) and, given ``detour_start`` per
    run, the mean distance to the human where the detour began (Fig. 8)."""
    ok = [r for r in runs if run_success(r)]
    rate, rate_ci = _rate(len(ok), len(runs))
    mean, ci = bootstrap_mean([r.navigation_time for r in ok], seed)
    row = {"method": method, "scenario": scenario, "success": len(ok), "runs": len(runs), "success_rate": rate,
           "success_rate_ci": rate_ci, "collisions": int(sum(r.collisions for r in runs)),
           "contacts_on_plan": contacts_on_plan(runs),
           "time_s": None if not ok else round(mean, 3), "time_s_ci": _ci(ci) if ok else None,
           "time_all_s": round(float(np.mean([r.navigation_time for r in runs])), 3) if runs else None,
           "detour_m": None, "detour_m_ci": None}
    found = [d["distance_to_human_m"] for d in detours or () if d is not None]
    if found:
        d_mean, d_ci = bootstrap_mean(found, seed)
        row["detour_m"], row["detour_m_ci"] = round(d_mean, 3), _ci(d_ci)
    return row


def contacts_on_plan(runs: Sequence[Run]) -> int:
    """Human contacts that began while the car executed a plan the pruner had accepted (the others began
    while it braked without one): what tells a pruner's miss from a search out of budget."""
    return int(sum(t.human_contacts - t.contacts_braking for r in runs for t in r.trips))


def timing(runs: Sequence[Run]) -> dict:
    """Simulated seconds, re-plans, the planner's measured wall time per re-plan and the runs' CPU seconds
    over ``runs`` (summed per run; each process's first run also carries its one-time warm-up, ~0.3 s)."""
    seconds = np.concatenate([np.asarray(r.plan_seconds, float) for r in runs]) if runs else np.zeros(0)
    simulated = float(sum(r.trajectory[-1][0] for r in runs if r.trajectory))
    return {"simulated_s": simulated, "replans": int(seconds.size), "cpu_s": float(sum(r.cpu_s for r in runs)),
            "plan_median_ms": float(np.median(seconds) * 1e3) if seconds.size else None,
            "plan_p95_ms": float(np.quantile(seconds, 0.95) * 1e3) if seconds.size else None}


def outcome_counts(runs: Sequence[Run]) -> dict[str, int]:
    trips = [t for r in runs for t in r.trips]
    return {k: sum(t.outcome == k for t in trips) for k in ("collision", "deadlock", "timeout")}


def summarise_trips(method: str, room: str, runs: Sequence[Run]) -> dict:
    """Table VIII row: successful trips (Wilson), total time of the successful trips, why the others failed."""
    trips = [t for r in runs for t in r.trips]
    ok = [t for t in trips if t.success]
    rate, rate_ci = _rate(len(ok), len(trips))
    counts = outcome_counts(runs)
    return {"method": method, "room": room, "success": len(ok), "trips": len(trips), "success_rate": rate,
            "success_rate_ci": rate_ci, "time_s": round(sum(t.time_s for t in ok), 3) if ok else None,
            "wall_hits": counts["collision"], "deadlocks": counts["deadlock"], "timeouts": counts["timeout"]}


def summarise_patrols(method: str, humans: int, runs: Sequence[Run], seed: int) -> dict:
    """Table IX row: completion time of the whole patrol (mean over runs, bootstrap), collisions (total
    over runs), successful trips (Wilson)."""
    trips = [t for r in runs for t in r.trips]
    ok = sum(t.success for t in trips)
    rate, rate_ci = _rate(ok, len(trips))
    mean, ci = bootstrap_mean([r.navigation_time for r in runs], seed)
    return {"method": method, "setting": f"{humans} human" + ("s" if humans > 1 else ""), "humans": humans,
            "runs": len(runs), "time_s": round(mean, 3),
            "time_s_ci": _ci(ci) if len(runs) > 1 else None, "collisions": int(sum(r.collisions for r in runs)),
            "contacts_on_plan": contacts_on_plan(runs),
            "success": int(ok), "trips": len(trips), "success_rate": rate, "success_rate_ci": rate_ci,
            **outcome_counts(runs)}


def detour_start(run: Run, line_start, line_end, lateral_m: float) -> dict | None:
    """Fig. 8: where the car first leaves the straight line ``line_start -> line_end`` by more than
    ``lateral_m``: the time, the car's position and its distance to the (first) human then; None if it
    never does."""
    a, b = np.asarray(line_start, float), np.asarray(line_end, float)
    u = (b - a) / np.linalg.norm(b - a)
    traj = np.asarray(run.trajectory)
    off = np.abs((traj[:, 1] - a[0]) * u[1] - (traj[:, 2] - a[1]) * u[0])
    hit = np.flatnonzero(off > lateral_m)
    if len(hit) == 0:
        return None
    i = int(hit[0])
    human = np.asarray(run.humans[i])[0]
    return {"time_s": float(traj[i, 0]), "xy": traj[i, 1:3].tolist(),
            "distance_to_human_m": float(np.hypot(*(traj[i, 1:3] - human)))}
