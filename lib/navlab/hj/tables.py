"""HJ-search Tables I, II and VII as report tables: our rows, the paper's, the notes and the claim verdicts.

The notebooks only run the searches and the timings and hand the results here; what the notes say and
which of the paper's claims hold (``metrics.hj_paper.check_claims``) are decided in this module.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from navlab.metrics.hj_paper import (
    ANA_COLUMNS,
    ASTAR_COLUMNS,
    PAPER,
    ana_rows,
    anytime_budget,
    astar_rows,
    check_claims,
    failure_modes,
    summarise,
)
from navlab.metrics.tables import Table

TABLE7_COLUMNS = ["component", "states", "total_s", "per_call_us", "per_state_ns", "in_search_total_s",
                  "in_search_evaluated_states", "in_search_per_state_ns", "in_search_cpu_per_state_ns",
                  "paper_per_state_ns", "cheaper_than_paper_per_state"]
PAPER_CALLS = 10_000  # Table VII's calls per component


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


def table1(results: Mapping[str, list], excess: Mapping[str, float], seed: int) -> Table:
    """Table I: A* with the Dist and the TTR heuristic on the table's start headings (``reach.planning.run_tasks``
    results by method)."""
    rows = _rows(results, seed)
    claims = check_claims("table1_heuristics_astar", astar_rows(rows))
    notes = ("Our lattice (35 primitives, 0.5 s steps), room and start/goal (params.yaml hj.planner.table1); "
             "time_s = total search seconds of our compiled search, not comparable with the paper's Python. "
             "Means over successful tasks with 95% bootstrap CIs over tasks; success CIs Wilson. Paper node "
             "counts are blank in its text (null). " + excess_note(excess) + " Claims: " + "; ".join(claims) + ". "
             + failure_modes(rows))
    return Table("table1_heuristics_astar", "HJ-search Table I", ASTAR_COLUMNS, astar_rows(rows),
                 PAPER["table1_heuristics_astar"], notes, claims)


def table2(results: Mapping[str, list], excess: Mapping[str, float], seed: int, max_expansions: int) -> Table:
    """Table II: ANA* with either heuristic; ``max_expansions``: its budget (``hj.planner.anastar_max_expansions``)."""
    rows = _rows(results, seed)
    claims = check_claims("table2_heuristics_anastar", ana_rows(rows))
    notes = (anytime_budget(dict(results), max_expansions) + " nodes = expansions to the first "
             "solution, cost = the final (best) solution's cost. *_common: over tasks both solved; *_all: over "
             "each method's successes; 95% bootstrap CIs over tasks, Wilson for success. Our car cannot reverse "
             "(v in [0, v_max], as the HJ grids), so re-orientation is by turning arcs. " + excess_note(excess)
             + " Claims: " + "; ".join(claims) + ". " + failure_modes(rows))
    return Table("table2_heuristics_anastar", "HJ-search Table II", ANA_COLUMNS, ana_rows(rows),
                 PAPER["table2_heuristics_anastar"], notes, claims)


def table7(rows: Sequence[dict], calls: int, grid_shapes: tuple[tuple[int, ...], tuple[int, ...]]) -> Table:
    """Table VII: per-component timings (``metrics.hj_paper.compare_table7`` rows) beside the paper's, its
    totals scaled to our ``calls``; ``grid_shapes``: (TTR, BRT) grid shapes."""
    paper_rows = [{"component": r["component"], "states": r["states"], "total_s": r["total_s"] * calls / PAPER_CALLS,
                   "per_call_us": r["total_s"] / PAPER_CALLS * 1e6,
                   "per_state_ns": r["total_s"] / PAPER_CALLS / r["states"] * 1e9}
                  for r in PAPER["table7_compute"]]
    claims = check_claims("table7_compute", list(rows))
    notes = (f"{calls} calls per component (paper: 10,000; its totals scaled to our call count). Our grids: "
             f"TTR {grid_shapes[0]}, BRT {grid_shapes[1]}. Wall-clock on the machine that ran "
             "this notebook (shared CPUs inflate it) except in_search_cpu_per_state_ns (CPU time of the compiled loop "
             "the search runs, per state it evaluated; a pruner stops a segment at its first failing sample); "
             "single-run timings, no CI. Claims: " + "; ".join(claims))
    return Table("table7_compute", "HJ-search Table VII", TABLE7_COLUMNS, list(rows), paper_rows, notes, claims)
