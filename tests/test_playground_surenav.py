"""The SuReNav playground without a browser: what a click changes, that its numbers are the benchmark's,
and one-line refusals for bad clicks.

The methods are the context benchmark's, trained on the smoke profile's artefacts (the session's
``smoke_artifacts``, which the notebook smoke runs and the browser test load too): every rule here holds
for any weights.
"""

from __future__ import annotations

import numpy as np
import pytest
import torch
from matplotlib.backend_bases import MouseEvent
from scipy import ndimage

from navlab.core.io import DataError
from navlab.core.labels import HARD_IDS
from navlab.core.params import ParamsError
from navlab.maps.perturb import OBSTACLE, adjacent_superpixels
from navlab.metrics.navigation import path_length, risk_table, total_risk
from navlab.metrics.relaxation import relaxed_regions
from navlab.surenav.benchmark import run_episode, seed_run
from navlab.surenav.context.benchmark import EXPERT
from navlab.surenav.episodes import Environment
from navlab.viz.playground.common import ERROR_MARK, UserError
from navlab.viz.playground.surenav import EXPERTS, METHODS, MODES, SuReNavPlayground, SuReNavView

CLOSE = MODES[2]


@pytest.fixture(scope="module")
def loaded(smoke_data, smoke_artifacts):
    return SuReNavPlayground.load("smoke", smoke_data, smoke_artifacts)


@pytest.fixture
def playground(loaded):
    torch.set_num_threads(loaded.params.surenav.train.threads)  # as load does (conftest resets it)
    loaded.choose_tile(loaded.tiles()[0])
    loaded.set_mode(MODES[0])
    loaded.set_costs(False)
    return loaded


def closable(playground) -> tuple[int, int]:
    """A cell halfway along the expert's path whose superpixel may be closed."""
    return playground.midway()


def test_closing_a_superpixel_changes_the_walk_and_reopening_restores_it(playground):
    before = playground.outcome()
    cell = closable(playground)
    region = int(playground.superpixels[playground.tile][cell])
    playground.set_mode(CLOSE)
    playground.click(*playground.xy(cell))
    assert playground.closed == {region}
    after = playground.outcome()
    inside = playground.superpixels[playground.tile] == region
    assert (after.truth[inside] == OBSTACLE).all() and (after.truth[~inside] == playground.smap.labels[~inside]).all()
    for method, run in after.runs.items():  # nobody walks through the new obstacle
        assert not inside[run.cells[:, 0], run.cells[:, 1]].any(), method
    expert = EXPERTS[0]
    assert not np.array_equal(after.runs[expert].cells, before.runs[expert].cells)  # it was on the expert's way
    playground.click(*playground.xy(cell))  # the same click reopens it: the cached outcome, not a recomputation
    hits = playground.outcomes.hits
    assert playground.closed == frozenset() and playground.outcome() is before and playground.outcomes.hits == hits + 1


def test_numbers_are_the_benchmark_s(playground, smoke_artifacts):
    """Each method's walk and metrics are what the benchmark's ``run_episode`` gives on the same episode with
    Fig. 4's own methods (``context.safety.fig4_methods``: SuReNav's first seed, D* Lite, the Expert)."""
    from navlab.surenav.context.safety import fig4_methods

    runs, _ = fig4_methods(playground.params, smoke_artifacts)
    playground.toggle(closable(playground))
    outcome = playground.outcome()
    smap, bench = playground.smap, playground.bench
    first = seed_run("SuReNav", playground.params.surenav.train.seeds[0])
    for method, run, persona in (("D* Lite", "D* Lite", 0), ("SuReNav", first, 0), (EXPERTS[1], EXPERT, 1)):
        env = Environment("check", playground.tile, smap, outcome.truth, np.asarray(outcome.start),
                          np.asarray(outcome.goal), persona)
        ours = outcome.runs[method]
        theirs = run_episode(env, run, lambda w, r=run, env=env: runs[r](env, w),
                             bench, playground.params.surenav.graph, risk_table(bench.unit_risk))
        assert ours.status == theirs.status
        np.testing.assert_allclose(smap.frame.cell_to_world(ours.cells), theirs.trajectory)
        assert ours.length_m == pytest.approx(theirs.length_m) and ours.risk == pytest.approx(theirs.total_risk)
    res = smap.frame.resolution
    for method, run in outcome.runs.items():
        assert run.length_m == path_length(run.cells, res)
        assert run.risk == total_risk(run.cells, outcome.truth, playground.risk, res)
        assert np.array_equal(run.relaxed, relaxed_regions(run.cells, outcome.truth, playground.superpixels[playground.tile]))
        sp = playground.superpixels[playground.tile]
        assert run.relaxed_m2 == pytest.approx(np.isin(sp, run.relaxed).sum() * res * res)
        assert set(run.frechet) == {e.split("(")[1][:-1] for e in EXPERTS}
    for k, expert in enumerate(EXPERTS):  # each persona's expert is at Fréchet distance 0 from itself
        assert outcome.runs[expert].frechet[expert.split("(")[1][:-1]] == 0.0
    assert list(outcome.runs) == list(METHODS)


def test_relaxation_costs_are_the_estimator_s_on_the_tile_as_it_is(playground):
    playground.toggle(closable(playground))
    costs = playground.costs()
    graph = costs.graph
    closed = next(iter(playground.closed))
    assert closed not in graph.region_ids  # a closed superpixel is a building: no node
    assert {graph.start_node, graph.goal_node} <= set(costs.nodes.tolist())
    assert len(costs.psi) == len(costs.nodes) and (costs.psi >= 0).all()
    assert costs.route is not None and costs.route[0] == graph.start_node and costs.route[-1] == graph.goal_node


def isolated_cell(playground) -> tuple[int, int] | None:
    """A free or soft cell of the tile from which no route leads to the start (a courtyard), if any."""
    parts, _ = ndimage.label(~np.isin(playground.truth(), HARD_IDS), structure=np.ones((3, 3), bool))
    other = np.argwhere((parts > 0) & (parts != parts[playground.start]))
    return None if len(other) == 0 else tuple(int(v) for v in other[0])


def surround_start(playground) -> None:
    """Close the superpixels around the start's until the one that would cut every route is refused."""
    sp = playground.superpixels[playground.tile]
    for region in adjacent_superpixels(sp, np.array([sp[playground.start]])):
        playground.toggle(tuple(np.argwhere(sp == region)[0]))


def hard_cell(playground) -> tuple[int, int]:
    return tuple(int(v) for v in np.argwhere(np.isin(playground.smap.labels, HARD_IDS))[0])


def on_closed(playground) -> None:
    cell = closable(playground)
    playground.toggle(cell)
    playground.set_start(cell)


@pytest.mark.parametrize(("action", "message"), [
    (lambda p: p.set_start(hard_cell(p)), "pick free or soft ground"),
    (lambda p: (p.set_mode("goal"), p.click(*p.xy(hard_cell(p)))), "pick free or soft ground"),
    (lambda p: p.click(-50.0, 10.0), "off the map"),
    (lambda p: p.click(None, None), "click inside the map"),
    (lambda p: p.set_goal(p.start), "start and goal are the same cell"),
    (lambda p: p.toggle(p.start), "move the start before closing it"),
    (lambda p: p.toggle(p.goal), "move the goal before closing it"),
    (lambda p: p.toggle(hard_cell(p)), "only free or soft superpixels can be closed"),
    (on_closed, "in a closed superpixel"),
    (lambda p: p.set_goal(isolated_cell(p)) if isolated_cell(p) else surround_start(p), "no route from start to goal"),
    (lambda p: p.reopen_all(), "no superpixel is closed"),
    (lambda p: p.choose_tile("atlantis"), "choose a test tile"),
    (lambda p: p.set_mode("teleport"), "click mode"),
])
def test_bad_input_is_one_line_in_the_widget(playground, action, message):
    """What the view shows for a refused click: one line (marked), no traceback, drawing and state unchanged
    (a refused action changes nothing; the setup steps before it may have)."""
    view = SuReNavView(playground)
    view.start(playground.tile, None, None, [])
    drawn, table = view.result.value, view.table.value
    assert not view.act(action, playground)
    assert view.message.kind == "error" and message in view.message.text, view.message.text
    assert "\n" not in view.message.text and "Traceback" not in view.message.widget.value
    assert view.message.widget.value.count(ERROR_MARK) == 1
    if not playground.closed:
        assert view.result.value == drawn and view.table.value == table


def test_map_clicks_and_widgets_drive_the_playground(playground):
    """Clicks on the map (matplotlib button presses, as ipympl delivers them) and on the view's widgets, as
    the browser test makes them in JupyterLab."""
    view = SuReNavView(playground)
    view.start()
    assert view.message.kind == "info" and len(playground.closed) == 1
    shown, canvas = view.result.value, view.canvas.value
    view.modes.value = CLOSE
    region = next(iter(playground.closed))
    view.press_at(*playground.xy(tuple(np.argwhere(playground.superpixels[playground.tile] == region)[0])))
    assert playground.closed == frozenset() and view.result.value != shown and view.message.kind == "info"
    view.modes.value = "goal"
    goal = playground.goal
    cells = playground.outcome().runs[EXPERTS[0]].cells
    view.press_at(*playground.xy(tuple(cells[len(cells) // 2])))  # the goal moves halfway along the old path
    assert playground.goal != goal and playground.goal == tuple(cells[len(cells) // 2])
    fx, fy = view.figure_fraction(*playground.xy(playground.goal))
    assert 0 < fx < 1 and 0 < fy < 1
    view.figure.canvas.callbacks.process("button_press_event",
                                         MouseEvent("button_press_event", view.figure.canvas, 1, 1, button=1))
    assert view.message.kind == "error" and "click inside the map" in view.message.text  # the figure's margin
    plain = view.canvas.value
    assert not view._psi_bar.ax.get_visible()
    view.costs.value = True
    assert playground.show_costs and view.canvas.value != plain and "Ψ shown" in view.message.text
    assert view._psi_bar.ax.get_visible() and view._psi_bar.mappable.norm.vmax > 0  # Ψ's colour bar, with it
    assert view.canvas.value != canvas
    last = playground.tiles()[-1]
    view.tiles.value = last
    assert playground.tile == last and playground.closed == frozenset() and view.message.kind == "info"
    buttons = {b.description: b for b in view.widget.children[0].children if hasattr(b, "on_click")}
    buttons["reopen all"].click()
    assert view.message.kind == "error" and "no superpixel is closed" in view.message.text


def test_notebook_scenario_points(playground):
    """The parameters cell's scenario: ends and closed superpixels given as world points."""
    tile = playground.tiles()[-1]
    playground.choose_tile(tile)
    cell = playground.midway()
    start, goal = (tuple(playground.xy(c)) for c in playground.defaults[tile])
    playground.set_scenario(tile, start, goal, [tuple(playground.xy(cell))])
    assert playground.tile == tile and playground.closed == {int(playground.superpixels[tile][cell])}
    playground.set_scenario(None, None, None, "midway")
    assert playground.tile == playground.tiles()[0] and len(playground.closed) == 1
    state = playground.tile, playground.start, playground.goal, playground.closed
    with pytest.raises(UserError, match="off the map"):  # a bad scenario changes nothing, not even the tile
        playground.set_scenario(tile, start, (-5.0, -5.0), [])
    assert (playground.tile, playground.start, playground.goal, playground.closed) == state


def test_missing_model_names_the_command(smoke_data, tmp_path):
    with pytest.raises(DataError, match=rf"--profile smoke --data-dir {smoke_data} --artifacts-dir {tmp_path} "
                                        r"--only surenav_context_demos --only surenav_context_estimator`"):
        SuReNavPlayground.load("smoke", smoke_data, tmp_path)


@pytest.mark.parametrize("start, message", [
    ("[1e9, 1e9]", r"start = '\[1e9, 1e9\]'.*: \(1000000000, 1000000000\) m is off the map"),
    ("[1, 2, 3]", r"start = \[1, 2, 3\]: give \(x, y\) metres"),
    ("here", r"start = 'here' is not a literal; give \(x, y\) metres"),
])
def test_a_bad_notebook_scenario_stops_with_one_line_naming_the_parameter(playground, start, message):
    """papermill passes ``-p start "[1e9, 1e9]"`` as a string: it is read as the point it spells, and a
    point off the map (or no point) stops the run with one line naming the parameters."""
    with pytest.raises(ParamsError, match=message):
        SuReNavView(playground).start(None, start, None, [])


def test_closed_and_relaxed_superpixels_are_told_apart():
    from navlab.viz.playground.surenav import CLOSED_RGBA, RELAXED_RGBA

    assert np.abs(np.subtract(CLOSED_RGBA[:3], RELAXED_RGBA[:3])).max() > 0.4  # dark red vs amber, not red twice

