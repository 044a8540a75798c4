"""PACER playground: wall time of each interaction, from the click to the redrawn result (issue 28: median
under 1 s on the 2-core machine).

Drives the playground's own widgets (``PacerView``: buttons clicked, menu set) on the trained artefacts
of ``--profile``, through a scripted session per map: uninformative, two thumbnail clicks (a pair),
invert, invert back, a second pair, reorder, remove, the operator's pairs, the next map and back.
Each time is ``PacerView.last_ms``: the action, the three costmaps (PACER, STERLING-style, window
oracle), the three A* paths and tier shares when the (map, context) is new, and the redraw (figure
encoded as JPEG, thumbnails, tier table); it leaves out only the transfer to the browser. "new" rows
compute a (map, context) for the first time; "cached" ones revisit one.

CPU time is measured beside wall time: on these two cores shared with other jobs, it is what the wall
time would be on an idle machine. Measured here, `default` profile (256-px maps, phase-3 model in
channels-last, 1 torch thread), `--maps 4` (90 interactions), 1-min load average 3.1 at the start:

    all interactions           median  559 ms wall (478 ms CPU)   p90  906 ms wall   max 1,580 ms
    new (map, context)         median  682 ms wall (534 ms CPU)   p90  997 ms wall   (64)
    cached / no compute        median    4 ms wall                 max     13 ms     (26)

    per interaction (median wall / CPU ms): choose map 687 / 480, uninformative 545 / 454, first
    thumbnail 4 / 3, second thumbnail (adds the pair) 687 / 521, invert 671 / 512, invert back 4 / 4,
    reorder 531 / 494, remove 670 / 545, operator's pairs 795 / 580, next map 835 / 558.

Without channels-last convolutions a new (map, context) took 665 ms CPU median (1,127 ms wall at load
6.4); skipping the network on windows wholly in the padding (``pacer_costmap``) had cut PACER's costmap
from ~1.3 to ~0.8 s wall at load 4 before that.

Usage: python benchmarks/playground_pacer.py [--profile default] [--maps 4] [--data-dir data]
       [--artifacts-dir artifacts]
"""

from __future__ import annotations

import argparse
import os
import statistics

from navlab.viz.playground.common import latency_line
from navlab.viz.playground.pacer import PacerPlayground, PacerView


def session(view: PacerView, choice: str, next_choice: str) -> list[tuple[str, float, bool]]:
    """One person's session on map ``choice``: (interaction, wall ms, CPU ms, new (map, context)?) per click."""
    p = view.playground
    buttons = {b.description: b for b in view.widget.children[3].children}
    rows = []

    def timed(name, click):
        misses = p.outcomes.misses
        click()
        assert view.message.kind == "info", f"{name}: {view.message.text}"
        rows.append((name, view.last_ms, view.last_cpu_ms, p.outcomes.misses > misses))

    def card(k):
        return view.gallery.children[k].children[1]

    if view.maps.value != choice:  # else the previous session's "next map" chose it already
        timed("choose map", lambda: setattr(view.maps, "value", choice))
    timed("uninformative", buttons["uninformative"].click)
    timed("thumbnail (preferred)", card(0).click)
    timed("thumbnail (other): add pair", card(2).click)
    timed("invert", buttons["invert"].click)
    timed("invert back", buttons["invert"].click)
    timed("thumbnail (preferred)", card(1).click)
    timed("thumbnail (other): add pair", card(3).click)
    timed("reorder (↓ on pair 1)", view.pair_rows.children[0].children[6].click)
    timed("remove (✕ on pair 2)", view.pair_rows.children[1].children[7].click)
    timed("operator's pairs", buttons["operator's pairs"].click)
    timed("next map", lambda: setattr(view.maps, "value", next_choice))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--maps", type=int, default=4, help="maps per group (seen, unseen) to run a session on")
    parser.add_argument("--data-dir", default="data")
    parser.add_argument("--artifacts-dir", default="artifacts")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    playground = PacerPlayground.load(args.profile, args.data_dir, args.artifacts_dir)
    count = min(args.maps, playground.data.aerial.maps - 1)
    view = PacerView(playground, "unseen 0", "operator")  # warm-up: lazy torch / numba initialisation
    rows = []
    for group in ("seen", "unseen"):
        for k in range(count):
            rows += session(view, f"{group} {k}", f"{group} {k + 1}")
    print(f"{args.profile} profile, {count} maps per group, load average 1-min at start {load:.1f} "
          f"on {os.cpu_count()} cores")
    for name in dict.fromkeys(r[0] for r in rows):
        wall, cpu = ([r[k] for r in rows if r[0] == name] for k in (1, 2))
        print(f"  {name:30s} median {statistics.median(wall):5.0f} ms wall, {statistics.median(cpu):5.0f} ms CPU")
    for label, keep in (("all interactions", lambda new: True), ("new (map, context)", lambda new: new),
                        ("cached / no compute", lambda new: not new)):
        print(latency_line(f"{label}, wall", [r[1] for r in rows if keep(r[3])], 25))
        print(latency_line(f"{label}, CPU", [r[2] for r in rows if keep(r[3])], 25))

if __name__ == "__main__":
    main()
