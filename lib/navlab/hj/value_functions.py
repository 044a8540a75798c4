"""HJ-search Figs. 2 and 3 as report tables: the four heuristics' values at the figure's robots beside the
seconds Sec. VI-A prints, and the static BRT's unsafe share by speed.

Why here: the figures only show contours; what a reader checks is what the paper states about them
(dynamics-aware above distance-based, map-based above general, the TTR rising when the robot faces away,
the BRT growing with speed). The values and the verdicts (``hj.claims``) are recorded
(reports/hj/fig2_heuristic_values, fig3_brt_growth), not printed and lost.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.core.params import Params
from navlab.hj.claims import FORWARD_ONLY, fig2_claims, fig2_forward_only_check, fig3_claims
from navlab.hj.grids import forward_only, forward_only_root, load_map_ttr, load_static_brt, load_ttr
from navlab.hj.guidance import euclidean_time, geodesic_time_field
from navlab.hj.paper import PAPER
from navlab.maps.rooms import Room, load_room
from navlab.metrics.tables import Table
from navlab.reach.grid import Grid
from navlab.reach.lookup import StaticBRTLookup

FIG2_COLUMNS = ["heading", "map_ttr_s", "general_ttr_s", "map_dist_s", "general_dist_s"]
FIG3_COLUMNS = ["speed", "unsafe_fraction"]  # speed as text ("0.33 m/s"): the row's key
HEURISTICS = {"map TTR": "map_ttr_s", "general TTR": "general_ttr_s", "map Dist": "map_dist_s",
              "general Dist": "general_dist_s"}
# Fig. 2's robots (x, y, v, θ): at 0.5 m/s heading up, then reversed, as the paper's two rows
FIG2_ROBOTS = ((1.0, 1.0, 0.5, np.pi / 2), (1.0, 1.0, 0.5, -np.pi / 2))
FIG2_HEADINGS = ("heading up (+y)", "heading down (-y)")
ROOM = "simulation"  # the room of Figs. 2-3 (and of hj.grids.map_ttr's goal)
GEODESIC_RESOLUTION_M = 0.1  # map Dist's raster
FIG3_SPEEDS = 4  # Fig. 3's BRT slices: this many speeds from 0 to v_max


@dataclass(frozen=True)
class Fig2:
    """What Fig. 2 draws and its table reports: the four heuristics at ``FIG2_ROBOTS`` and the lookups
    and field they come from (``viz.hj_figures.draw_fig2`` contours the same ones over the room)."""
    room: Room
    goal: np.ndarray
    ttr: Callable
    map_ttr: Callable
    geodesic: tuple[np.ndarray, RasterFrame]
    values: dict[tuple[int, str], float]
    table: Table


@dataclass(frozen=True)
class Fig3:
    """What Fig. 3 draws and its table reports: the static BRT of ``ROOM`` sliced at ``speeds``."""
    room: Room
    brt: StaticBRTLookup
    speeds: np.ndarray
    table: Table


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


def fig2(params: Params, artifacts_dir: str | Path) -> Fig2:
    """Fig. 2 from the ``hj_grids`` artefacts: the heuristics at its robots, with the forward-only car's rows
    (its own TTR grids) where the default car reverses."""
    g = params.hj.grids
    room, goal = load_room(ROOM), np.asarray(g.map_ttr.goal_xy)
    ttr, map_ttr = load_ttr(params, artifacts_dir), load_map_ttr(params, artifacts_dir)
    geodesic = geodesic_time_field(room, goal, g.robot.v_max, g.robot.radius_m, resolution=GEODESIC_RESOLUTION_M)
    values = heuristic_values(FIG2_ROBOTS, goal, ttr, map_ttr, geodesic, g.robot.v_max)
    forward_values = None
    if g.robot.v_min < 0:
        forward, root = forward_only(params), forward_only_root(artifacts_dir)
        forward_values = heuristic_values(FIG2_ROBOTS, goal, load_ttr(forward, root), load_map_ttr(forward, root),
                                          geodesic, g.robot.v_max)
    table = fig2_table(values, FIG2_HEADINGS, g.ttr.goal_radius_m / g.robot.v_max, forward_values)
    return Fig2(room, goal, ttr, map_ttr, geodesic, values, table)


def speed_slice(values: np.ndarray, grid: Grid, v: float, v_axis: int = 2) -> np.ndarray:
    """Values at speed ``v`` (linear between the two nearest speed nodes): an (x, y, θ) array."""
    idx = np.clip((v - grid.lo[v_axis]) / grid.spacing[v_axis], 0.0, grid.shape[v_axis] - 1.0)
    i0 = min(int(idx), grid.shape[v_axis] - 2)
    w = idx - i0
    a, b = np.take(values, i0, axis=v_axis), np.take(values, i0 + 1, axis=v_axis)
    return (1.0 - w) * np.asarray(a, dtype=np.float32) + w * np.asarray(b, dtype=np.float32)


def fig3(params: Params, artifacts_dir: str | Path) -> Fig3:
    """Fig. 3 from the ``hj_grids`` artefacts: the static BRT's unsafe share at ``FIG3_SPEEDS`` speeds."""
    g = params.hj.grids
    room = load_room(ROOM)
    brt = load_static_brt(params, artifacts_dir, room.name)
    speeds = np.linspace(0.0, g.robot.v_max, FIG3_SPEEDS)
    unsafe = [float((speed_slice(brt.stored.values, brt.grid, v) < 0).mean()) for v in speeds]
    return Fig3(room, brt, speeds, fig3_table(speeds, unsafe))


def fig3_table(speeds: Sequence[float], unsafe: Sequence[float]) -> Table:
    """Fig. 3: the share of (x, y, θ) inside the static BRT at each speed, and whether it grows with speed."""
    rows = [{"speed": f"{v:.2f} m/s", "unsafe_fraction": float(u)} for v, u in zip(speeds, unsafe, strict=True)]
    notes = ("Share of the room's (x, y, θ) grid inside the static BRT ({V < 0}) at each speed: at higher speed "
             "the robot needs more room to brake or turn. The paper shows slices and prints no numbers.")
    return Table("fig3_brt_growth", "HJ-search Fig. 3", FIG3_COLUMNS, rows, [], notes, fig3_claims(speeds, unsafe))
