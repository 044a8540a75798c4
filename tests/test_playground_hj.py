"""The HJ playground without a browser: clicks on its figure, its controls, one-line refusals of bad
clicks, the pruners' census, and the closed loop with its progress line and Stop.

It runs on the smoke profile's value functions and BRT margins (built once for this module: the HJ
artefact steps only); the notebook smoke run and the browser test run it on the full smoke artefacts.
"""

from __future__ import annotations

import math
import shutil
import threading

import numpy as np
import pytest
from matplotlib.backend_bases import MouseEvent

from navlab.core.io import DataError
from navlab.core.params import ParamsError
from navlab.hj.brt_margin import build_brt_margins
from navlab.hj.grids import build_hj_grids
from navlab.viz.playground.common import ERROR_MARK
from navlab.viz.playground.hj import MAX_HUMANS, HJPlayground, HJView, Human, walk_goal


@pytest.fixture(scope="module")
def hj_artifacts(tmp_path_factory, smoke_params):
    out = tmp_path_factory.mktemp("hj_artifacts")
    build_hj_grids(smoke_params, out, out, progress=False, log=lambda m: None)
    build_brt_margins(smoke_params, out, out, progress=False, log=lambda m: None)
    return out


@pytest.fixture(scope="module")
def loaded(smoke_params, hj_artifacts):
    return HJPlayground(smoke_params, hj_artifacts)


@pytest.fixture
def view(loaded):
    loaded.setup, loaded.speed = None, 0.5
    return HJView(loaded, "table3")


def press(view: HJView, x: float, y: float, panel: int = 0) -> None:
    """A mouse press on the figure at room position (x, y) of a panel, through matplotlib's event path."""
    ax = [a for a in view.fig.axes if a.get_label() == "room"][panel]
    px, py = ax.transData.transform((x, y))
    event = MouseEvent("button_press_event", view.fig.canvas, px, py, button=1)
    view.fig.canvas.callbacks.process(event.name, event)


def test_every_set_up_plans(loaded):
    for key in loaded.scenarios:
        view = HJView(loaded, key)
        assert view.message.kind == "info", f"{key}: {view.message.text}"
        assert view.result.value and "expansions" in view.summary.value


def test_clicks_set_start_goal_and_humans(view):
    p = view.playground
    drawn, plan = view.result.value, p.plan()
    assert view.replay.layout.display == "none"  # no empty image (a broken-image icon) before a closed loop
    view.mode.value = "human"
    assert view.message.text.endswith("next click sets the human")  # the line follows the toggle
    view.mode.value = "start"
    assert view.message.text.endswith("next click sets the start")
    press(view, 1.0, 1.0)
    assert view.message.kind == "info", view.message.text
    assert p.setup.start[:2] == pytest.approx((1.0, 1.0), abs=1e-3) and view.result.value != drawn
    assert p.plan() is not plan
    view.mode.value = "goal"
    press(view, 8.0, 1.6, panel=1)  # either panel takes clicks
    assert p.setup.goal == pytest.approx((8.0, 1.6), abs=1e-3)
    view.options["human_mode"].value = "FS-BRT"
    view.mode.value = "human"
    press(view, 6.5, 1.6)
    assert len(p.setup.humans) == 1 and view.message.kind == "info", view.message.text
    census = p.census()
    assert census.removed["humans"] > 0 and len(census.cells["humans"]) > 0
    view.human_heading.value = 90
    assert p.setup.humans[0].heading_deg == 90.0
    turned = view.result.value
    view.heading.value = 90
    assert p.setup.start[2] == 90.0 and view.result.value != turned
    view.widget.children[0].children[2].click()  # clear humans
    assert p.setup.humans == () and "humans" not in p.census().removed


def test_revisiting_a_set_up_is_cached(view):
    p = view.playground
    first = p.plan()
    view.scenarios.value = "table1"
    view.scenarios.value = "table3"
    assert p.plan() is first and view.message.kind == "info"


@pytest.mark.parametrize(("action", "message"), [
    (lambda v: (setattr(v.mode, "value", "start"), press(v, 2.6, 2.7)), "start (2.60, 2.70) is inside an obstacle"),
    (lambda v: v.act(v.playground.click, "start", -1.0, 2.0), "off the map"),
    (lambda v: v.act(v.playground.click, "start", float("nan"), 2.0), "is not a position"),
    (lambda v: v.act(v.playground.click, "start", "here", 2.0), "needs numbers"),
    (lambda v: (setattr(v.mode, "value", "goal"), press(v, 5.0, 1.2)), "goal (5.00, 1.20) is inside an obstacle"),
    (lambda v: v.act(v.playground.click, "goal", 12.0, 1.0), "off the map"),
    (lambda v: (setattr(v.mode, "value", "human"), press(v, 1.2, 2.8)), "stands on the robot"),
    (lambda v: v.act(v.playground.click, "human", 2.5, 2.5), "human (2.50, 2.50) is inside an obstacle"),
    (lambda v: v.act(v.playground.set_heading, float("nan")), "not a number of degrees"),
    (lambda v: v.act(v.playground.set_human_heading, 90), "no human to turn"),
    (lambda v: v.act(v.playground.set_speed, float("nan")), "slice speed"),
    (lambda v: v.act(v.playground.set_option, "static", "magic"), "choose one of OBS, BRT"),
    (lambda v: v.act(v.playground.choose_scenario, "table7"), "choose a set-up"),
])
def test_bad_clicks_are_one_line_in_the_widget(view, action, message):
    """What the view shows for a refused click: one line (marked), no traceback, state and drawing unchanged."""
    setup, drawn = view.playground.setup, view.result.value
    action(view)  # a press on the figure, or a control's call through the view
    assert view.message.kind == "error"
    assert message in view.message.text, view.message.text
    assert "\n" not in view.message.text and "Traceback" not in view.message.widget.value
    assert view.message.widget.value.count(ERROR_MARK) == 1
    assert view.playground.setup == setup and view.result.value == drawn


def test_refusals_of_the_room_and_pruner_pairing(view):
    p = view.playground
    view.scenarios.value = "table6_face"
    view.options["static"].value = "BRT"
    assert view.message.kind == "error" and "open room has no static BRT" in view.message.text
    assert p.setup.static == "OBS" and view.options["static"].value == "BRT"  # the menu as the person left it
    view.scenarios.value = "table3"
    p.add_human(6.0, 1.0)
    view.options["human_mode"].value = "OBS"
    assert "choose the OBS static pruner" in view.message.text
    for k in range(MAX_HUMANS - 1):
        p.add_human(7.5, 0.6 + 0.9 * k)
    view.mode.value = "human"
    press(view, 4.0, 0.5)
    assert f"at most {MAX_HUMANS} humans" in view.message.text
    view.mode.value = "goal"
    press(view, 0.0, 0.0)  # on the colour bar's side of the figure, not a room
    event = MouseEvent("button_press_event", view.fig.canvas, 1, 1, button=1)  # the figure's corner: no axes
    view.fig.canvas.callbacks.process(event.name, event)
    assert view.message.kind == "error" and "click inside one of the two room panels" in view.message.text


def test_census_asks_the_pruners_as_the_search_does(view):
    """The OBS census at a cell equals the OBS pruner's swept check on that cell's successors; the BRT, which
    sees further at speed, removes successors at more cells than at rest."""
    p = view.playground
    census = p.census()
    assert 0 < census.removed["OBS"] < census.total and census.plan_total > 0
    assert set(census.removed) == {"OBS", "BRT"}
    p.set_speed(0.0)
    at_rest = p.census()
    p.set_speed(1.0)
    fast = p.census()
    assert len(fast.cells["BRT"]) > len(at_rest.cells["BRT"])
    room = p.room
    for x, y in fast.cells["OBS"][:5]:
        assert room.obstacle_distance(x, y) < p.robot.radius_m + 1.5  # near a wall or obstacle


def test_human_walks_to_the_wall():
    from navlab.maps.rooms import load_room

    room = load_room("open")
    assert walk_goal(room, Human(2.0, 2.0, 0.0), 0.3) == pytest.approx((room.width - 0.3, 2.0))
    assert walk_goal(room, Human(2.0, 2.0, -90.0), 0.3) == pytest.approx((2.0, 0.3))
    x, y = walk_goal(room, Human(2.0, 2.0, 45.0), 0.3)
    assert math.isclose(x - 2.0, y - 2.0, abs_tol=1e-9) and math.isclose(y, room.height - 0.3)


def test_closed_loop_plays_back_shows_progress_and_stops(view):
    p = view.playground
    view.seconds.value = 2
    view.run_loop(background=False)
    assert view.message.kind == "info" and "closed loop:" in view.message.text, view.message.text
    assert view.replay.value[:4] == b"GIF8"
    seen, stop = [], threading.Event()

    def progress(t):
        seen.append(t)
        stop.set()  # as a Stop press during the run

    replay = p.closed_loop(5.0, progress, stop)
    assert seen == [pytest.approx(0.48, abs=0.05)] and replay.outcome.startswith("stopped at")
    assert replay.gif[:4] == b"GIF8" and len(replay.run.trajectory) == len(replay.run.humans)
    view.stop()
    assert view.message.kind == "error" and "not running" in view.message.text
    view.act(p.closed_loop, float("nan"))
    assert "choose 1 to 120 simulated seconds" in view.message.text


def test_closed_loop_in_the_background_answers_stop(view):
    view.seconds.value = 30
    view.run_loop()
    view.run_loop()  # a second press while it runs
    assert "already running" in view.message.text
    view.stop()
    view._thread.join(timeout=120)
    assert not view._thread.is_alive()
    assert view.message.kind == "info" and "stopped at" in view.message.text, view.message.text


def test_missing_artefacts_name_the_command(smoke_params, hj_artifacts, tmp_path):
    with pytest.raises(DataError, match="artifacts build --only hj_grids"):
        HJPlayground(smoke_params, tmp_path)
    with pytest.raises(DataError, match=rf"needs hj_grids, hj_margins \(profile smoke, not in {tmp_path}\).*"
                                        r"--profile smoke --data-dir data .*--only hj_grids --only hj_margins`"):
        HJPlayground.load("smoke", tmp_path)
    shutil.copytree(hj_artifacts / "hj", tmp_path / "hj")
    with pytest.raises(DataError, match="artifacts build --only hj_margins"):
        HJPlayground(smoke_params, tmp_path)
    with pytest.raises(DataError, match=r"needs hj_margins \(.*--only hj_margins`"):
        HJPlayground.load("smoke", tmp_path)


def test_snapshot_is_a_png(view):
    assert view.snapshot().data[:8] == b"\x89PNG\r\n\x1a\n"
    assert np.isfinite(view.playground.slice_fields().ttr).all()


def test_static_brt_in_3d_is_a_meshcat_scene_of_the_room(view, monkeypatch):
    """The button puts the room's static BRT at the slice speed in a meshcat page (an iframe) under it; a
    second speed gives another scene; a room without a static BRT is one line, and the scene stays."""
    [button] = [b for b in view.widget.children if "navlab-show-scene" in getattr(b, "_dom_classes", ())]
    button.click()
    assert view.message.kind == "info", view.message.text
    first = view.scene.value
    assert first.startswith("<iframe srcdoc=") and "meshcat" in first.lower()
    view.speed.value = 0.0
    button.click()
    assert view.scene.value != first
    monkeypatch.setattr(view.playground, "brt_rooms", ())
    view.speed.value = 0.25
    button.click()
    assert view.message.kind == "error" and "has no static BRT" in view.message.text
    assert view.scene.value.startswith("<iframe srcdoc=")


def test_a_bad_notebook_scenario_stops_with_one_line_naming_the_parameter(loaded):
    with pytest.raises(ParamsError, match=r"notebook parameter scenario = 'nope': .*table3"):
        HJView(loaded, "nope")


def test_the_first_action_says_it_compiles_and_later_ones_do_not(loaded, capsys):
    """A fresh clone's first plan waits on numba for minutes: the notebook's run prints why, the message line
    says so while it waits; once warm, neither."""
    view = HJView(loaded, "table3")
    assert "numba compiles the lattice search" in capsys.readouterr().out and view.warm
    shown = []
    view.message.show = lambda text, kind="info": shown.append(text)
    view.act(loaded.choose_scenario, "table1")
    assert shown[0] == "working …"
    view.warm = False
    view.act(loaded.choose_scenario, "table3")
    assert shown[-2].startswith("working … (first use: numba compiles") and view.warm

