"""HJ-search Figs. 2 and 3 as report tables: the four heuristics' values at the figure's robots, the static
BRT's unsafe share by speed, and the orderings the paper reads off them (Sec. VI) as claim verdicts.

Why here: the figures only show contours; what a reader checks is the ordering the paper states
(dynamics-aware >= distance-based, map-based >= general, the BRT growing with speed). Those values and
verdicts are recorded (reports/hj/fig2_heuristic_values, fig3_brt_growth), not printed and lost.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.metrics.tables import Claim, Table
from navlab.reach.heuristics import euclidean_time

FIG2_COLUMNS = ["heading", "map_ttr_s", "general_ttr_s", "map_dist_s", "general_dist_s"]
FIG3_COLUMNS = ["speed", "unsafe_fraction"]  # speed as text ("0.33 m/s"): the row's key
HEURISTICS = {"map TTR": "map_ttr_s", "general TTR": "general_ttr_s", "map Dist": "map_dist_s",
              "general Dist": "general_dist_s"}
TTR_ALLOWANCE_S = 0.1  # the stored TTR grids' interpolation error: a map TTR this far below the general one counts


def heuristic_values(robots: Sequence[tuple[float, float, float, float]], goal_xy, ttr: Callable, map_ttr: Callable,
                     geodesic: tuple[np.ndarray, RasterFrame], v_max: float) -> dict[tuple[int, str], float]:
    """{(robot index, heuristic): seconds to the goal} for the four heuristics of Fig. 2: map TTR (``map_ttr``,
    for this goal), general TTR (``ttr``), map Dist (``geodesic``: ``reach.heuristics.geodesic_time_field``'s
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


def fig2_table(values: Mapping[tuple[int, str], float], headings: Sequence[str], slack_s: float) -> Table:
    """Fig. 2's values, one row per robot heading, and Sec. VI-A's orderings at every robot. ``slack_s``: the
    goal disc's radius / v_max (the TTR is the time to the disc, Dist to its centre)."""
    rows = [{"heading": h, **{col: values[(r, name)] for name, col in HEURISTICS.items()}}
            for r, h in enumerate(headings)]
    pairs = [(r["general_ttr_s"], r["general_dist_s"], r["map_ttr_s"], r["map_dist_s"]) for r in rows]
    fmt = "; ".join
    claims = [
        Claim.of("general TTR >= general Dist less the goal disc at every heading",
               all(t >= d - slack_s for t, d, _, _ in pairs),
               fmt(f"{t:.2f} vs {d:.2f} - {slack_s:.2f} s" for t, d, _, _ in pairs)),
        Claim.of("map Dist >= general Dist at every heading", all(md >= d for _, d, _, md in pairs),
               fmt(f"{md:.2f} vs {d:.2f} s" for _, d, _, md in pairs)),
        Claim.of(f"map TTR >= general TTR at every heading (within {TTR_ALLOWANCE_S} s)",
               all(mt >= t - TTR_ALLOWANCE_S for t, _, mt, _ in pairs),
               fmt(f"{mt:.2f} vs {t:.2f} s" for t, _, mt, _ in pairs)),
        Claim.of("the TTR depends on the heading (Dist does not)",
               max(t for t, *_ in pairs) - min(t for t, *_ in pairs) > TTR_ALLOWANCE_S,
               fmt(f"{h}: {t:.2f} s" for h, (t, *_) in zip(headings, pairs))),
    ]
    notes = ("The four heuristics of Fig. 2 at its robots (speed 0.5 m/s, the headings as rows), in seconds to the "
             "goal: map TTR (one reach-avoid solve for this goal), general TTR (dynamics, no obstacles), map Dist "
             "(shortest free path / v_max on a 0.1 m raster) and general Dist (straight line / v_max). The paper "
             "prints no numbers for this figure. Claims: " + "; ".join(map(str, claims)) + ".")
    return Table("fig2_heuristic_values", "HJ-search Fig. 2", FIG2_COLUMNS, rows, [], notes, claims)


def fig3_table(speeds: Sequence[float], unsafe: Sequence[float]) -> Table:
    """Fig. 3: the share of (x, y, θ) inside the static BRT at each speed, and whether it grows with speed."""
    rows = [{"speed": f"{v:.2f} m/s", "unsafe_fraction": float(u)} for v, u in zip(speeds, unsafe, strict=True)]
    grows = all(a <= b + 1e-9 for a, b in itertools.pairwise(unsafe))
    claims = [Claim.of("the static BRT grows with speed", grows,
                     ", ".join(f"{v:.2f} m/s: {u:.3f}" for v, u in zip(speeds, unsafe)))]
    notes = ("Share of the room's (x, y, θ) grid inside the static BRT ({V < 0}) at each speed: at higher speed "
             "the robot needs more room to brake or turn. The paper shows slices and prints no numbers. Claims: "
             + "; ".join(map(str, claims)) + ".")
    return Table("fig3_brt_growth", "HJ-search Fig. 3", FIG3_COLUMNS, rows, [], notes, claims)
