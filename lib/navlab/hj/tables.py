"""HJ-search Tables I-IX and the sensitivity curves as report tables: our rows, the paper's, the notes and the claims.

The notebooks only run the searches and the timings and hand the results here, per unit (tasks, runs);
this module lays out the rows and the notes (set-up and differences only) and hands the per-unit results
to ``hj.claims``, which decides the paper's claims and our own checks.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from navlab.core.params.hj import PlannerParams
from navlab.core.params.hj_dynamic import DynamicParams
from navlab.hj import claims as hj_claims
from navlab.hj import closed_loop as hj_closed_loop
from navlab.hj.paper import (
    ANA_COLUMNS,
    ASTAR_COLUMNS,
    PAPER,
    ana_rows,
    anytime_budget,
    astar_rows,
    failure_modes,
    summarise,
)
from navlab.hj.receding_horizon import Run
from navlab.hj.scenarios import ROOM_NAMES
from navlab.hj.sensitivity import BUDGET_COLUMNS, LOOP_COLUMNS, budget_rows, loop_rows
from navlab.hj.state_lattice_runs import TTR, StateLatticeRuns
from navlab.metrics.claims import Claim
from navlab.metrics.tables import Table

TABLE7_COLUMNS = ["component", "states", "total_s", "per_call_us", "per_state_ns", "in_search_total_s",
                  "in_search_evaluated_states", "in_search_per_state_ns", "in_search_cpu_per_state_ns",
                  "paper_per_state_ns", "cheaper_than_paper_per_state"]
PAPER_CALLS = 10_000  # Table VII's calls per component
SEARCH_REFS = {"table1_heuristics_astar": "HJ-search Table I", "table2_heuristics_anastar": "HJ-search Table II",
               "table3_pruning_astar": "HJ-search Table III", "table4_pruning_anastar": "HJ-search Table IV",
               "table5_static_general": "HJ-search Table V"}
TABLE6_COLUMNS = ["method", "scenario", "success", "runs", "success_rate", "success_rate_ci", "collisions",
                  "contacts_on_plan", "time_s", "time_s_ci", "time_all_s", "detour_m", "detour_m_ci"]


FORWARD_ONLY_NOTE = ("Rows 'forward-only car (ours)': the old default, v in [0, v_max] in the lattice (the same "
                     "speed spacing) with its own TTR grid (navlab.hj.grids.forward_only), the paper's OBS check.")
FORWARD_ONLY_LOOP_NOTE = ("Rows 'forward-only car (ours)': the old default, v in [0, v_max] in the lattice and the "
                          "simulator, with its own TTR and human-robot BRT (navlab.hj.grids.forward_only); walls "
                          "by OBS (its static BRT is not built).")
FORWARD_ONLY_OBS_NOTE = (FORWARD_ONLY_NOTE + " Its BRT rows are not run: the forward-only car's static BRT would need "
                         "its own margin solve (hj_margins, the HJ part's largest cost).")
PRUNER_NOTE = ("OBS is the paper's conventional instantaneous check (clearance at the states the search samples, 4 "
               "per 0.5 s step), BRT the static BRT there (Eq. 12); a plan either passes that grazes an obstacle "
               "between samples fails the paper's dense check (8 points per sample under the dynamics) and counts as "
               "a failure, as in the paper. Rows '(ours)': the swept check that bounds the clearance between samples "
               "(hj.pruners.obs_pruner), with which no returned plan can fail the dense check.")


def excess_note(excess: Mapping[str, float]) -> str:
    """The TTR against the lattice's true cost-to-go (``Planner.heuristic_excess``), one sentence."""
    return (f"TTR against the lattice's true cost-to-go (Dijkstra, h = 0, OBS) at these {excess['starts']} starts: "
            f"above it at {excess['over']}, by at most {excess['max_excess_s']:.3f} s (the TTR grid's "
            "interpolation error).")


def _rows(results: Mapping[str, list], seed: int) -> list[dict]:
    """``summarise`` rows with each method's total search seconds."""
    rows = summarise(dict(results), seed)
    for row, label in zip(rows, results):
        row["time_s"] = sum(r.seconds for r in results[label])
    return rows


def _search_table(table_id: str, rows: list[dict], shown: list[dict], setup: str, claims: list[Claim]) -> Table:
    """Tables I-V: the ``shown`` rows (``astar_rows`` or ``ana_rows`` of ``rows``), the claims, and notes: the
    set-up and the failure modes."""
    notes = setup + " " + PRUNER_NOTE + " " + failure_modes(rows)
    columns = ASTAR_COLUMNS if table_id in ("table1_heuristics_astar", "table3_pruning_astar") else ANA_COLUMNS
    return Table(table_id, SEARCH_REFS[table_id], columns, shown, PAPER[table_id], notes, claims)


def table1(results: Mapping[str, list], excess: Mapping[str, float], seed: int, lattice: StateLatticeRuns) -> Table:
    """Table I: A* with the Dist and the TTR heuristic on the table's start headings (``hj.planning.run_tasks``
    results by method, on the paper-style continuous lattice), and beside them Dijkstra and both A* on the
    true state lattice (``hj.state_lattice_runs.run_table``), on which "same optimal cost" is decided."""
    rows, lattice_rows = _rows(results, seed), _rows(lattice.results, seed)
    shown, lattice_shown = astar_rows(rows), astar_rows(lattice_rows)
    s = lattice.settings
    deltas = [r.delta for r in lattice.results[TTR]]
    setup = ("Our lattice (35 primitives, 0.5 s steps), room and start/goal (params.yaml hj.planner.table1); "
             "time_s = total search seconds of our compiled search, not comparable with the paper's Python. "
             "Means over successful tasks with 95% bootstrap CIs over tasks; success CIs Wilson. Paper node "
             "counts are blank in its text (null). " + excess_note(excess)
             + f" Rows '(state lattice)': the same tasks on a true state lattice (navlab.search.state_lattice): "
             f"cell {s.cell_m} m, {lattice.headings} grid-aligned headings (the table's headings snapped to the "
             f"nearest), speeds {', '.join(f'{v:g}' for v in s.speeds)} m/s, {lattice.n_primitives} motion "
             "primitives, each ending exactly on a lattice state, swept-disc collision test conservative (a plan "
             "found clears the obstacles); Dijkstra (h = 0), A* w/ Dist (distance to the goal disc / v_max) and "
             f"A* w/ TTR (the TTR grid less its largest excess over the open room's exact cost-to-go, "
             f"{max(deltas, default=0.0):.3f} s; h = 0 on goal states); cost = duration in s. " + FORWARD_ONLY_NOTE)
    claims = hj_claims.table1_claims(results, lattice, seed)
    return _search_table("table1_heuristics_astar", rows + lattice_rows, shown + lattice_shown, setup, claims)


def table2(results: Mapping[str, list], excess: Mapping[str, float], seed: int, max_expansions: int) -> Table:
    """Table II: ANA* with either heuristic; ``max_expansions``: its budget (``hj.planner.anastar_max_expansions``)."""
    rows = _rows(results, seed)
    setup = (anytime_budget(dict(results), max_expansions) + " nodes = expansions to the first "
             "solution, cost = the final (best) solution's cost. *_common: over tasks both solved; *_all: over "
             "each method's successes; 95% bootstrap CIs over tasks, Wilson for success. Our car reverses as "
             "the paper's does (v in [v_min, v_max] with v_min < 0, hj.grids.robot, in the lattice and the HJ grids). "
             + FORWARD_ONLY_NOTE + " " + excess_note(excess))
    return _search_table("table2_heuristics_anastar", rows, ana_rows(rows), setup,
                         hj_claims.search_claims("table2_heuristics_anastar", results, seed))


def table7(rows: Sequence[dict], calls: int, grid_shapes: tuple[tuple[int, ...], tuple[int, ...]]) -> Table:
    """Table VII: per-component timings (``hj.paper.compare_table7`` rows) beside the paper's, its
    totals scaled to our ``calls``; ``grid_shapes``: (TTR, BRT) grid shapes."""
    paper_rows = [{"component": r["component"], "states": r["states"], "total_s": r["total_s"] * calls / PAPER_CALLS,
                   "per_call_us": r["total_s"] / PAPER_CALLS * 1e6,
                   "per_state_ns": r["total_s"] / PAPER_CALLS / r["states"] * 1e9}
                  for r in PAPER["table7_compute"]]
    claims = hj_claims.table7_claims(list(rows))
    notes = (f"{calls} calls per component (paper: 10,000; its totals scaled to our call count). Our grids: "
             f"TTR {grid_shapes[0]}, BRT {grid_shapes[1]}. Wall-clock on the machine that ran "
             "this notebook (shared CPUs inflate it) except in_search_cpu_per_state_ns (CPU time of the compiled loop "
             "the search runs, per state it evaluated; a pruner stops a segment at its first failing sample); "
             "single-run timings, no CI.")
    return Table("table7_compute", "HJ-search Table VII", TABLE7_COLUMNS, list(rows), paper_rows, notes, claims)


def table3(results: Mapping[str, list], margin: float, margin_report: Mapping, seed: int) -> Table:
    """Table III: A* (Dist) with the OBS and the BRT pruner; ``margin``: the BRT margin and ``margin_report``
    how it was measured (``Planner.margin``, ``Planner.margin_report``)."""
    rows, m = _rows(results, seed), margin_report
    setup = (f"BRT margin {margin:.4f} measured on grid {m['coarse_shape']} vs a finer {m['fine_shape']} "
             f"solve ({m['scheme']}; largest stored value at a node the finer solve calls unsafe; "
             f"{m['missed_unsafe_nodes']} such nodes). Costs: dt*(1 + w*exp(-decay*clearance)), not Nav2's "
             "0-252 scale, so magnitudes differ from the paper. time_s: our compiled search. Paper node counts "
             "are blank in its text (it states a 15.1% reduction). " + FORWARD_ONLY_OBS_NOTE)
    return _search_table("table3_pruning_astar", rows, astar_rows(rows), setup,
                         hj_claims.search_claims("table3_pruning_astar", results, seed))


def table4(results: Mapping[str, list], margin: float, seed: int, max_expansions: int) -> Table:
    """Table IV: ANA* (Dist) with the OBS and the BRT pruner."""
    rows = _rows(results, seed)
    setup = (f"ANA* with the Dist heuristic; BRT margin {margin:.4f}. {anytime_budget(dict(results), max_expansions)} "
             "nodes = expansions to the first solution, cost = final solution; success needs the densified check. "
             "95% bootstrap CIs over tasks, Wilson for success. " + FORWARD_ONLY_OBS_NOTE)
    return _search_table("table4_pruning_anastar", rows, ana_rows(rows), setup,
                         hj_claims.search_claims("table4_pruning_anastar", results, seed))


def table5(results: Mapping[str, list], margin: float, seed: int, planner: PlannerParams) -> Table:
    """Table V: every heuristic x pruner combination on ``planner.table5``'s random start-goal pairs."""
    rows = _rows(results, seed)
    t5 = planner.table5
    setup = (f"{t5.pairs} pairs drawn with seed hj.seed, blocked line of sight or >= {t5.min_distance_m} m apart; "
             f"BRT margin {margin:.4f}. {anytime_budget(dict(results), planner.anastar_max_expansions)} 95% bootstrap "
             "CIs over tasks, Wilson for success. " + FORWARD_ONLY_OBS_NOTE)
    return _search_table("table5_static_general", rows, ana_rows(rows), setup,
                         hj_claims.search_claims("table5_static_general", results, seed))


def _loop_table(table_id: str, paper_ref: str, columns: list[str], rows: Sequence[dict], setup: str,
                claims: list[Claim]) -> Table:
    """Tables VI, VIII, IX: the closed-loop rows beside the paper's, the set-up as notes, the claims."""
    return Table(table_id, paper_ref, columns, list(rows), hj_closed_loop.PAPER[table_id], setup.rstrip(), claims)


def table6(rows: Sequence[dict], runs: Mapping[tuple[str, str], Sequence[Run]], dynamic: DynamicParams, rules: str,
           speed: Mapping[str, float]) -> Table:
    """Table VI / Fig. 8: the closed-loop rows (``hj.closed_loop.summarise_runs``) and the runs behind them
    ({(method, scenario): runs}, as ``hj.scenarios.run_cells`` returns them), on which the claims are
    decided; ``rules``: the policy's re-plan rules (``ClosedLoop.rules``); ``speed``:
    ``hj.closed_loop.timing`` with the run's ``wall_s`` and ``cpu_s``."""
    t6, c = dynamic.table6, dynamic.closed_loop
    setup = (f"Simulated, as in the paper; our coordinates (params.yaml hj.dynamic.table6) in an empty 9.6 x 5.4 m room, "
             f"walls pruned by OBS in every row. {t6.runs} runs per cell, run r seeded {dynamic.seed}+r; exact poses (human "
             f"noise {t6.human_noise_m} m, as in the paper's simulation), runs differ by where the human starts, U(0, "
             f"{t6.human_start_jitter_m}) m along its line. {c.algorithm}, {c.heuristic} heuristic, {c.max_expansions} "
             f"expansions per 12 Hz re-plan. {rules} Success: every trip without human contact, deadlock or timeout "
             f"(Wilson 95% CI); time_s: mean navigation time of the successful runs (bootstrap 95% CI over runs; "
             f"null = the paper's 'Failed'); time_all_s: over all runs (a contact does not stop a run); collisions: "
             "human contacts over all runs (contacts_on_plan: those that began while the car executed a plan the pruner "
             "had accepted, not while braking without one); detour_m: robot-human distance "
             f"when the car first left the head-on line by {t6.detour_lateral_m} m (Fig. 8). Speed: "
             f"{speed['simulated_s']:.0f} s simulated in {speed['wall_s']:.0f} s wall on the shared 2-core machine "
             f"({speed['simulated_s'] / speed['wall_s']:.1f}x real time, {speed['cpu_s']:.0f} s CPU); re-plan median "
             f"{speed['plan_median_ms']:.1f} ms. " + FORWARD_ONLY_LOOP_NOTE)
    return _loop_table("table6_dynamic", "HJ-search Table VI, Fig. 8", TABLE6_COLUMNS, rows, setup,
                       [*hj_claims.table6_claims(runs, dynamic), *hj_claims.loop_reversing_checks(runs)])


TABLE8_COLUMNS = ["method", "room", "success", "trips", "success_rate", "success_rate_ci", "time_s", "wall_hits",
                  "deadlocks", "timeouts"]
TABLE9_COLUMNS = ["method", "setting", "humans", "runs", "time_s", "time_s_ci", "collisions", "contacts_on_plan",
                  "success", "trips", "success_rate", "success_rate_ci", "collision", "deadlock", "timeout"]


def table8(rows: Sequence[dict], runs: Mapping[tuple[str, str], Sequence[Run]], dynamic: DynamicParams, rules: str,
           speed: Mapping[str, float], dense_plan_median_ms: float) -> Table:
    """Table VIII: the room patrols (``hj.closed_loop.summarise_trips`` rows) and the runs behind them
    ({(method, room): runs}, rooms by their ``hj.scenarios.ROOM_NAMES`` key, as ``run_cells`` returns them);
    ``speed`` as for ``table6``; ``dense_plan_median_ms``: the Dense Room's median re-plan time."""
    t8, c = dynamic.table8, dynamic.closed_loop
    setup = (f"Simulated (the paper: a real QBot). Rooms and goals: navlab.maps.rooms (our layouts of Fig. 9), "
             f"{t8.cycles} cycles, {t8.runs} seeded run(s) per cell (seeds {dynamic.seed}+r) pooled; pose noise "
             f"{t8.pose_noise_m} m. {c.algorithm} with "
             f"{c.max_expansions} expansions per {c.replan_hz:g} Hz re-plan (sized to the period by "
             f"benchmarks/hj_closed_loop.py). {rules} "
             f"BRT = static BRT with its measured margin. A trip "
             f"fails on a wall hit, a deadlock ({c.deadlock_s} s without {c.deadlock_progress_m} m progress) or a "
             f"{c.trip_timeout_s} s timeout, and the car is then put at the goal (the paper's intervention). "
             f"Success counts with Wilson 95% CIs; time_s: total time of the successful trips (null = 'Failed'). "
             f"Speed: {speed['simulated_s']:.0f} s simulated in {speed['wall_s']:.0f} s wall ({speed['cpu_s']:.0f} s CPU) "
             f"on the shared 2-core machine; Dense Room re-plan median {dense_plan_median_ms:.1f} ms "
             f"(target <= 83 ms). " + FORWARD_ONLY_LOOP_NOTE)
    by_room = {(method, ROOM_NAMES[room]): cell for (method, room), cell in runs.items()}
    return _loop_table("table8_rooms", "HJ-search Table VIII", TABLE8_COLUMNS, rows, setup,
                       [*hj_claims.table8_claims(by_room, dynamic.seed), *hj_claims.loop_reversing_checks(by_room)])


def table9(rows: Sequence[dict], runs: Mapping[tuple[str, int], Sequence[Run]], dynamic: DynamicParams, rules: str,
           speed: Mapping[str, float]) -> Table:
    """Table IX: the patrols among humans (``hj.closed_loop.summarise_patrols`` rows) and the runs behind
    them ({(method, humans): runs}, as ``hj.scenarios.run_cells`` returns them)."""
    t9, c = dynamic.table9, dynamic.closed_loop
    setup = (f"Simulated (the paper: a real QBot and people). Our set-up (hj.dynamic.table9): the open 9.6 x 5.4 m room, "
             f"robot goals {list(t9.robot_goals)} patrolled {t9.cycles} cycles, humans patrolling "
             f"{[list(p) for p in t9.human_pois]} at 0.8 m/s under the paper's three rules; pose noise "
             f"{t9.pose_noise_m} m, human noise {c.human_noise_m} m; {t9.runs} run(s) per cell, seeded {dynamic.seed}+r. "
             f"time_s: total patrol time including failed trips (mean over runs); collisions: human contacts plus "
             f"wall hits (total over runs; contacts_on_plan: human contacts that began on a plan "
             f"the pruner had accepted, not while braking without one); trip success with Wilson 95% CIs; "
             f"collision/deadlock/timeout: failed trips by cause. {rules} Speed: {speed['simulated_s']:.0f} s simulated "
             f"in {speed['wall_s']:.0f} s wall ({speed['simulated_s'] / speed['wall_s']:.1f}x real time, "
             f"{speed['cpu_s']:.0f} s CPU, shared 2-core machine). " + FORWARD_ONLY_LOOP_NOTE)
    return _loop_table("table9_humans", "HJ-search Table IX", TABLE9_COLUMNS, rows, setup,
                       [*hj_claims.table9_claims(runs, dynamic.seed), *hj_claims.loop_reversing_checks(runs)])


def sensitivity_budget(results, dynamic: DynamicParams, rules: str) -> Table:
    """Table VIII as a curve of ANA*'s expansions per re-plan (``hj.sweeps.run_sweep`` results)."""
    rows = budget_rows(results)
    claims = hj_claims.budget_claims(rows)
    t8, c = dynamic.table8, dynamic.closed_loop
    notes = (f"Table VIII (rooms, routes, {t8.cycles} cycles, pose noise {t8.pose_noise_m} m; one seeded run per "
             f"point, seed {dynamic.seed}, where the table pools {t8.runs}) re-run with ANA* given each budget "
             f"of expansions per re-plan ({c.replan_hz:g} "
             f"Hz; the table itself uses {c.max_expansions}); a car at rest lets its search run on, "
             f"resumed, while it waits (neither room has humans), so a search from rest gets one budget per period "
             f"waited, up to the {c.deadlock_s:g} s deadlock timer. "
             f"Success: trips without a wall hit, deadlock or timeout, Wilson 95% CIs. The paper states a time "
             f"budget on its robot, not an expansion count. {rules}")
    return Table("sensitivity_budget", "HJ-search Table VIII, as a curve", BUDGET_COLUMNS, rows, [], notes, claims)


def sensitivity_loop(results, dynamic: DynamicParams) -> Table:
    """Table VI as curves of the re-planning rate, the human position noise and the prediction horizon, each
    varied with the other two at the table's own values (``loop_own``)."""
    rows = loop_rows(results)
    own = loop_own(dynamic)
    claims = hj_claims.loop_claims(rows, own)
    notes = (f"Table VI (Face-to-Face and Zig-Zag, {dynamic.table6.runs} seeded runs per cell) re-run along one setting "
             f"at a time, the other two at the table's own ({own[0]:g} Hz, {own[1]:g} m, {own[2]:g} s): the "
             f"re-planning rate (ANA*'s {dynamic.closed_loop.max_expansions} expansions per re-plan at every rate), the "
             f"std of the observed human position, and how far ahead FI-/FS-BRT prune the humans along their "
             f"observed velocity (0 s: where seen, the paper's text). Success: every trip without contact, "
             f"deadlock or timeout, Wilson 95% CIs; collisions: human contacts over all runs (contacts_on_plan: "
             f"those that began on a plan the pruner had accepted).")
    return Table("sensitivity_loop", "HJ-search Table VI, as curves", LOOP_COLUMNS, rows, [], notes, claims)


def loop_own(dynamic: DynamicParams) -> tuple[float, float, float]:
    """Table VI's own (re-planning rate, human noise, prediction horizon): where each loop curve crosses it."""
    return dynamic.closed_loop.replan_hz, dynamic.table6.human_noise_m, dynamic.closed_loop.human_prediction_s
