"""SuReNav playground: wall time of each interaction, from the click to the redrawn result (issue 28: median
under 1 s on the 2-core machine).

Drives the playground's own view (``SuReNavView``: map clicks delivered as matplotlib button presses,
widgets set) on the trained artefacts of ``--profile``, through a scripted session per test tile: choose
the tile, close the superpixel halfway along the expert's path, show Psi, hide it, move the goal to
three quarters of the expert's path, move the start to a quarter of it, reopen the superpixel, close it
again, reopen all (refused or done), and one refused click (the goal on the start). Each time is
``SuReNavView.last_ms``: the action, the seven walks (SuReNav, D* Lite, COA*, RCR, the expert with each
persona) and their metrics when the scenario is new, the estimator's Psi when shown, and the redraw:
the map rendered as PNG by Agg (under ipympl the browser asks for that image after the kernel answers)
and the seven panels as JPEG. "new" rows compute a scenario for the first time; "cached" ones revisit one.

CPU time is measured beside wall time: on these two cores shared with other jobs, it is what the wall
time would be on an idle machine. Measured here, `default` profile (500 m tiles at 1 m, GPS estimator
seed 0, 1 torch thread), 5 tiles (50 interactions), 1-min load average 3.2 at the start (map figure 5.6 in):

    all interactions           median  315 ms wall (207 ms CPU)   p90  873 ms wall   max 1,456 ms
    new scenario               median  760 ms wall (496 ms CPU)   p90 1,273 ms wall  (22)
    cached / no walk           median  137 ms wall  (98 ms CPU)   p90  326 ms wall   (28)

    per interaction (median wall / CPU ms): choose tile 515 / 341, close a superpixel 802 / 549, show Psi
    304 / 201, hide Psi 134 / 90, move the goal 832 / 566, move the start 815 / 550, reopen the superpixel
    564 / 375, close it again (cached) 154 / 109, reopen all (cached) 132 / 98, refused click 0 / 0.

The same on the final code (map figure 5.2 in), 1-min load average 1.3 (wall = CPU within 1 ms):

    all interactions           median  194 ms wall   p90  537 ms   max 931 ms   (50)
    new scenario               median  459 ms wall   p90  740 ms   max 931 ms   (22)
    cached / no walk           median   89 ms wall   p90  195 ms   max 279 ms   (28)

A cached scenario's ~90 ms is the map's Agg rendering; a new one adds the seven walks (~0.3-0.4 s CPU).

Usage: python benchmarks/playground_surenav.py [--profile default] [--tiles 5] [--data-dir data]
       [--artifacts-dir artifacts]
"""

from __future__ import annotations

import argparse
import os
import statistics

from navlab.viz.playground.common import latency_line
from navlab.viz.playground.surenav import EXPERTS, MODES, SuReNavPlayground, SuReNavView


def session(view: SuReNavView, tile: str) -> list[tuple[str, float, float, bool]]:
    """One person's session on ``tile``: (interaction, wall ms, CPU ms, new scenario?) per click."""
    p = view.playground
    rows = []

    def timed(name, click, refused=False):
        misses = p.outcomes.misses
        click()
        assert (view.message.kind == "error") == refused, f"{name}: {view.message.text}"
        rows.append((name, view.last_ms, view.last_cpu_ms, p.outcomes.misses > misses))

    def along(share):
        cells = p.outcome().runs[EXPERTS[0]].cells
        return p.xy(tuple(cells[int(share * (len(cells) - 1))]))

    def mode(name):
        view.modes.value = name

    timed("choose tile", lambda: setattr(view.tiles, "value", tile))
    mode(MODES[2])
    middle = p.xy(p.midway())
    timed("close a superpixel (map click)", lambda: view.press_at(*middle))
    timed("show Psi", lambda: setattr(view.costs, "value", True))
    timed("hide Psi", lambda: setattr(view.costs, "value", False))
    mode("goal")
    goal = along(0.75)
    timed("move the goal (map click)", lambda: view.press_at(*goal))
    mode("start")
    start = along(0.25)
    timed("move the start (map click)", lambda: view.press_at(*start))
    mode(MODES[2])
    timed("reopen the superpixel (map click)", lambda: view.press_at(*middle))
    timed("close it again (map click)", lambda: view.press_at(*middle))
    timed("reopen all", view.widget.children[0].children[2].click)
    mode("goal")
    timed("refused: goal on the start", lambda: view.press_at(*p.xy(p.start)), refused=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--tiles", type=int, default=5, help="test tiles to run a session on")
    parser.add_argument("--data-dir", default="data")
    parser.add_argument("--artifacts-dir", default="artifacts")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    playground = SuReNavPlayground.load(args.profile, args.data_dir, args.artifacts_dir)
    view = SuReNavView(playground)
    view.start()  # warm-up: numba compilation, torch's first call
    tiles = playground.tiles()[:args.tiles]
    view.tiles.value = tiles[-1]  # each session's "choose tile" then changes the tile
    rows = [row for tile in tiles for row in session(view, tile)]
    print(f"{args.profile} profile, {len(tiles)} tiles, load average 1-min at start {load:.1f} "
          f"on {os.cpu_count()} cores")
    for name in dict.fromkeys(r[0] for r in rows):
        wall, cpu = ([r[k] for r in rows if r[0] == name] for k in (1, 2))
        print(f"  {name:36s} median {statistics.median(wall):5.0f} ms wall, {statistics.median(cpu):5.0f} ms CPU")
    for label, keep in (("all interactions", lambda new: True), ("new scenario", lambda new: new),
                        ("cached / no walk", lambda new: not new)):
        print(latency_line(f"{label}, wall", [r[1] for r in rows if keep(r[3])], 32))
        print(latency_line(f"{label}, CPU", [r[2] for r in rows if keep(r[3])], 32))


if __name__ == "__main__":
    main()
