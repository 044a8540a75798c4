"""HJ-search Figs. 2 and 3 as report tables: the four heuristics' values at the figure's robots beside the
seconds Sec. VI-A prints, and the static BRT's unsafe share by speed.

Why here: the figures only show contours; what a reader checks is what the paper states about them
(dynamics-aware above distance-based, map-based above general, the TTR rising when the robot faces away,
the BRT growing with speed). The values and the verdicts (``hj.claims``) are recorded
(reports/hj/fig2_heuristic_values, fig3_brt_growth), not printed and lost.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.hj.claims import FORWARD_ONLY, fig2_claims, fig2_forward_only_check, fig3_claims
from navlab.hj.guidance import euclidean_time
from navlab.hj.paper import PAPER
from navlab.metrics.tables import Table

FIG2_COLUMNS = ["heading", "map_ttr_s", "general_ttr_s", "map_dist_s", "general_dist_s"]
FIG3_COLUMNS = ["speed", "unsafe_fraction"]  # speed as text ("0.33 m/s"): the row's key
HEURISTICS = {"map TTR": "map_ttr_s", "general TTR": "general_ttr_s", "map Dist": "map_dist_s",
              "general Dist": "general_dist_s"}


def heuristic_values(robots: Sequence[tuple[float, float, float, float]], goal_xy, ttr: Callable, map_ttr: Callable,
                     geodesic: tuple[np.ndarray, RasterFrame], v_max: float) -> dict[tuple[int, str], float]:
    """{(robot index, heuristic): seconds to the goal} for the four heuristics of Fig. 2: map TTR (``map_ttr``,
    for this goal), general TTR (``ttr``), map Dist (``geodesic``: ``hj.guidance.geodesic_time_field``'s
    field and frame) and general Dist (straight line / v_max)."""
    field, frame = geodesic
    values = {}
    for r, state in enumerate(robots):
        x = np.array([state], float)
        row, col = frame.world_to_cell(x[0, :2])
        values[(r, "map TTR")] = float(map_ttr(x)[0])
        values[(r, "general TTR")] = float(ttr(x, goal_xy)[0])
        values[(r, "map Dist")] = float(field[row, col])
        values[(r, "general Dist")] = float(euclidean_time(x[0, :2], goal_xy, v_max))
    return values


def fig2_table(values: Mapping[tuple[int, str], float], headings: Sequence[str], slack_s: float,
               forward_only: Mapping[tuple[int, str], float] | None = None) -> Table:
    """Fig. 2's values, one row per robot heading (the upward one first, then the reversed one, as the paper's
    two rows), beside the paper's seconds, and Sec. VI-A's statements decided on them; then the forward-only
    car's two rows (``forward_only``: ``heuristic_values`` on its TTR grids, ``navlab.hj.grids.forward_only``;
    None where the paper's car is itself forward-only), a labelled variant with our own check. ``slack_s``: the goal disc's radius / v_max (the TTR is the time to
    the disc, Dist to its centre)."""
    def rows_of(vals, suffix=""):
        return [{"heading": h + suffix, **{col: vals[(r, name)] for name, col in HEURISTICS.items()}}
                for r, h in enumerate(headings)]

    rows, forward = rows_of(values), rows_of(forward_only, FORWARD_ONLY) if forward_only else []
    paper = [{"heading": h, **p} for h, p in zip(headings, PAPER["fig2_heuristic_values"], strict=True)]
    notes = ("The four heuristics of Fig. 2 at its robots (speed 0.5 m/s, the headings as rows), in seconds to the "
             "goal: map TTR (one reach-avoid solve for this goal), general TTR (dynamics, no obstacles), map Dist "
             "(shortest free path / v_max on a 0.1 m raster) and general Dist (straight line / v_max). The paper's "
             "rows are the seconds Sec. VI-A prints for its robot heading upward and reversed; its robot's position "
             "and speed are blank in its text, and our room, robot and goal are our own, so the seconds differ and "
             "only the orderings compare. Our car reverses, as the paper's (v_min < 0, hj.grids.robot). Rows "
             "'forward-only car (ours)': the same robots under the old default (v >= 0, its own TTR grids at the "
             "same spacing); Dist does not depend on the car.")
    return Table("fig2_heuristic_values", "HJ-search Fig. 2", FIG2_COLUMNS, rows + forward, paper, notes,
                 [*fig2_claims(rows, slack_s), *([fig2_forward_only_check(rows, forward)] if forward else [])])


def fig3_table(speeds: Sequence[float], unsafe: Sequence[float]) -> Table:
    """Fig. 3: the share of (x, y, θ) inside the static BRT at each speed, and whether it grows with speed."""
    rows = [{"speed": f"{v:.2f} m/s", "unsafe_fraction": float(u)} for v, u in zip(speeds, unsafe, strict=True)]
    notes = ("Share of the room's (x, y, θ) grid inside the static BRT ({V < 0}) at each speed: at higher speed "
             "the robot needs more room to brake or turn. The paper shows slices and prints no numbers.")
    return Table("fig3_brt_growth", "HJ-search Fig. 3", FIG3_COLUMNS, rows, [], notes, fig3_claims(speeds, unsafe))
