"""HJ playground: wall time of each interaction, from the click to the redrawn figure (issue 28: median under
1 s on the 2-core machine).

Drives the playground's own view (``HJView``: presses on the figure through matplotlib's event path, sliders
and menus set) on the `--profile` value functions, through a scripted session per set-up: start click,
goal click, a human placed and turned, the robot turned, the slice speed changed, the static pruner and the
search switched, humans cleared, and the first start back (a revisit). Each time is ``HJView.last_ms``: the
search, the slices, the pruners' census and the redraw (Agg, PNG encoded: what ipympl renders too, less
the transfer to the browser). A press refused as a bad click (e.g. a start the BRT already prunes) counts
like any other. The closed loop (seconds, with a progress line) is timed once per set-up, separately.

CPU time is measured beside wall time: on these two cores shared with other jobs, it is what the wall
time would be on an idle machine. Measured here, `default` profile, `--loop-s 4`, 88 interactions over the
8 set-ups (3 refused), 1-min load average 3.2 at the start:

    all interactions   median 310 ms wall (274 ms CPU)   p90 641 ms   max 2,043 ms

    per interaction (median wall / CPU ms): choose set-up 343 / 322, click start 297 / 286, click goal
    296 / 249, click human 340 / 312, human heading 376 / 365, robot heading 364 / 264, slice speed
    260 / 208, static pruner 226 / 184, search (A* -> ANA*) 431 / 363, clear humans 301 / 225, start back
    235 / 228. The slowest are searches that end without a plan (A*'s 400,000-expansion budget, ~1-2 s).
    Closed loop, 4 s simulated: 2.7-4.9 s wall to simulate and render the playback.

Usage: python benchmarks/playground_hj.py [--profile default] [--artifacts-dir artifacts] [--loop-s 4]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

from matplotlib.backend_bases import MouseEvent

from navlab.viz.playground.common import latency_line
from navlab.viz.playground.hj import HJPlayground, HJView

CLICKS = {  # per set-up: start, goal, human (room coordinates, free in every room)
    "simulation": ((1.0, 1.0), (8.0, 1.6), (6.0, 1.2)),
    "long_hallway": ((0.8, 3.5), (8.8, 3.5), (4.5, 2.7)),
    "dense_room": ((1.2, 2.0), (6.4, 2.4), (4.0, 4.5)),
    "open": ((1.0, 4.0), (8.5, 1.0), (5.0, 2.7)),
}


def press(view: HJView, x: float, y: float) -> None:
    ax = next(a for a in view.fig.axes if a.get_label() == "room")
    px, py = ax.transData.transform((x, y))
    event = MouseEvent("button_press_event", view.fig.canvas, px, py, button=1)
    view.fig.canvas.callbacks.process(event.name, event)


def session(view: HJView, key: str) -> list[tuple[str, float, float, str]]:
    """(interaction, wall ms, CPU ms, message kind) per click of one person's session on set-up ``key``."""
    rows = []

    def timed(name, click):
        click()
        rows.append((name, view.last_ms, view.last_cpu_ms, view.message.kind))

    timed("choose set-up", lambda: setattr(view.scenarios, "value", key))
    start, goal, human = CLICKS[view.playground.setup.room]
    first = view.playground.setup.start
    for mode, xy in (("start", start), ("goal", goal), ("human", human)):
        view.mode.value = mode
        timed(f"click {mode}", lambda xy=xy: press(view, *xy))
    timed("human heading", lambda: setattr(view.human_heading, "value", 90))
    timed("robot heading", lambda: setattr(view.heading, "value", 45))
    timed("slice speed", lambda: setattr(view.speed, "value", 1.0))
    static = view.options["static"]
    timed("static pruner", lambda: setattr(static, "value", "BRT" if static.value == "OBS" else "OBS"))
    timed("search", lambda: setattr(view.options["algorithm"], "value", "ANA*"))
    timed("clear humans", view.widget.children[0].children[2].click)
    view.mode.value = "start"
    timed("start back (revisit)", lambda: press(view, *first[:2]))
    view.speed.value, view.options["algorithm"].value = 0.5, "A*"
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--artifacts-dir", default="artifacts")
    parser.add_argument("--loop-s", type=int, default=4, help="simulated seconds of each closed loop (0: none)")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    playground = HJPlayground.load(args.profile, args.artifacts_dir)
    view = HJView(playground)
    for key in playground.scenarios:  # warm-up: numba's compiled look-ups load from their cache
        view.scenarios.value = key
    rows, loops = [], []
    for key in playground.scenarios:
        rows += session(view, key)
        if args.loop_s:
            view.scenarios.value = key
            view.seconds.value = args.loop_s
            began = time.perf_counter()
            view.run_loop(background=False)
            loops.append((key, time.perf_counter() - began, view.message.text))
    print(f"{args.profile} profile, {len(playground.scenarios)} set-ups, load average 1-min at start {load:.1f} "
          f"on {os.cpu_count()} cores; refused clicks: {sum(r[3] == 'error' for r in rows)} of {len(rows)}")
    for name in dict.fromkeys(r[0] for r in rows):
        wall, cpu = ([r[k] for r in rows if r[0] == name] for k in (1, 2))
        print(f"  {name:24s} median {statistics.median(wall):5.0f} ms wall, {statistics.median(cpu):5.0f} ms CPU")
    print(latency_line("all interactions, wall", [r[1] for r in rows]))
    print(latency_line("all interactions, CPU", [r[2] for r in rows]))
    for key, seconds, text in loops:
        print(f"  closed loop {key:15s} {seconds:5.1f} s wall for {args.loop_s} s simulated: {text}")


if __name__ == "__main__":
    main()
