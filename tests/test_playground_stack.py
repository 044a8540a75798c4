"""The stack playground without a browser: the choices change the episode as asked (and nothing else), a refused
choice is one line, a drive is the ablation's and the time slider shows where everything was, a revisit is
answered from the cache, missing artefacts name the command.

The world's choices run on the smoke data (conftest's ``smoke_data``); the playground on the smoke artefacts
(``smoke_artifacts``, as the other playgrounds' tests and the notebook smoke runs): the smoke maps are too
coarse for the robot to reach its goal (``stack.timeout_s``), so these tests check the plumbing, not the
result. One full-stack drive (seconds), the others on the cheaper grid-A* row.
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from navlab.core.io import DataError
from navlab.core.labels import FREE_IDS, HARD_IDS
from navlab.core.params import ParamsError
from navlab.maps.dataset import load_maps
from navlab.pacer.terrain import load_terrain_bank
from navlab.stack import world
from navlab.stack.ablation import NO_HJ, STACK
from navlab.stack.world import BLOCKAGE_CLEARANCE_M, EpisodeChoices, stack_episode
from navlab.viz.playground.common import ERROR_MARK
from navlab.viz.playground.stack import FRAME_S, StackPlayground, StackView

pytestmark = pytest.mark.usefixtures("single_thread")

ARRAYS = ("truth", "superpixels", "terrain", "aerial", "ordering", "context", "walkway")


# ------------------------------------------------------------------------------------- the world's choices


@pytest.fixture(scope="module")
def drawn(smoke_params, smoke_data):
    """(params, tiles, bank) of the smoke data."""
    return smoke_params, load_maps(smoke_data, "test"), load_terrain_bank(smoke_data, smoke_params.pacer.data)


def build(drawn, index: int = 0, **choices) -> world.StackEpisode:
    params, tiles, bank = drawn
    return stack_episode(index, tiles, params, bank, EpisodeChoices(**choices) if choices else None)


def same_walkers(a, b) -> bool:
    return len(a) == len(b) and all(np.array_equal(u.path, w.path) and (u.offset_m, u.speed) == (w.offset_m, w.speed)
                                    for u, w in zip(a, b, strict=True))


def assert_same(a, b, fields=ARRAYS) -> None:
    assert (a.name, a.start, a.goal, a.preference, a.persona) == (b.name, b.start, b.goal, b.preference, b.persona)
    assert np.array_equal(a.prior.labels, b.prior.labels) and a.prior.frame == b.prior.frame
    for field in fields:
        assert np.array_equal(getattr(a, field), getattr(b, field)), field


@pytest.mark.parametrize("index", [0, 1, 3])
def test_no_choices_is_the_ablation_s_episode_whichever_way_it_is_asked(drawn, index):
    """No choices, the default choices and choices spelling out the parameters' values are one episode (the
    same draws in the same order: the committed ablation's episodes stay what they were)."""
    params = drawn[0]
    plain = build(drawn, index)
    spelled = build(drawn, index, preference=params.stack.preferences[index % len(params.stack.preferences)],
                    blockage=True, pedestrians=params.stack.pedestrians, speed=params.hj.grids.human.speed)
    for other in (stack_episode(index, drawn[1], params, drawn[2], EpisodeChoices()), spelled):
        assert_same(plain, other)
        assert same_walkers(plain.walkers, other.walkers)
    assert len(plain.walkers) == params.stack.pedestrians and (plain.truth != plain.prior.labels).any()


def test_the_inverted_preference_reverses_the_order_and_changes_nothing_else(drawn):
    realistic, inverted = build(drawn, preference="realistic"), build(drawn, preference="inverted")
    assert (realistic.preference, inverted.preference) == ("realistic", "inverted")
    assert inverted.ordering.tolist() == realistic.ordering[::-1].tolist() and len(realistic.ordering) > 1
    assert not np.array_equal(inverted.context, realistic.context)
    assert_same(dataclasses.replace(inverted, preference="realistic"), realistic,
                fields=("truth", "terrain", "aerial", "walkway"))
    assert same_walkers(inverted.walkers, realistic.walkers)


def test_a_custom_order_puts_the_named_terrains_first(drawn):
    bank = drawn[2]
    base = build(drawn)
    last, first = (int(t) for t in base.ordering[[-1, 0]])
    away = next(t.id for t in bank.terrains if t.id not in base.ordering)  # a terrain not in view
    custom = build(drawn, order=tuple(bank.terrains[t].name for t in (last, away, first)))
    assert custom.preference == "custom"
    rest = [t for t in base.ordering.tolist() if t not in (last, first)]  # in the realistic order
    assert custom.ordering.tolist() == [last, first, *rest]  # the one not in view left out
    with pytest.raises(ValueError, match="order names 'moon dust': not a terrain"):
        build(drawn, order=("grass", "moon dust"))


def usable_route_cells(ep: world.StackEpisode, clearance: int) -> np.ndarray:
    """Route indices the blockage rules allow (the test's own reading of ``obstruct_route``'s rules): in a region
    no route cell within ``clearance`` cells (Chebyshev) of either end lies in, on free ground where the route
    has any such cell."""
    route = ep.walkway
    regions = ep.superpixels[route[:, 0], route[:, 1]]
    protected = {int(regions[k]) for k in range(len(route))
                 if min(np.abs(route[k] - route[0]).max(), np.abs(route[k] - route[-1]).max()) <= clearance}
    usable = [k for k in range(len(route)) if regions[k] >= 0 and int(regions[k]) not in protected]
    free = [k for k in usable if ep.prior.labels[tuple(route[k])] in FREE_IDS]
    return np.array(free or usable, dtype=np.int64)


@pytest.mark.parametrize("index", [0, 2])
def test_a_blockage_at_a_fraction_cuts_the_route_nearest_there(drawn, index):
    res = drawn[1][index % len(drawn[1])].frame.resolution
    clearance = round(BLOCKAGE_CLEARANCE_M / res)
    route = build(drawn, index).walkway
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(route, axis=0), axis=1))])
    lo = BLOCKAGE_CLEARANCE_M / (arc[-1] * res)
    placed = []
    for fraction in (lo, 0.5, 1 - lo):
        ep = build(drawn, index, blockage_at=fraction)
        assert np.array_equal(ep.walkway, route)
        blocked = ep.truth != ep.prior.labels
        assert np.isin(ep.truth[blocked], HARD_IDS).all()
        on = np.flatnonzero(blocked[route[:, 0], route[:, 1]])
        assert len(on), fraction  # the walkway route is cut
        ends = np.minimum(np.abs(route[on] - route[0]).max(axis=1), np.abs(route[on] - route[-1]).max(axis=1))
        assert ends.min() > clearance  # clear of the start and the goal
        usable = usable_route_cells(ep, clearance)
        target = fraction * arc[-1]
        assert np.abs(arc[on] - target).min() <= np.abs(arc[usable] - target).min() + 1e-9  # nearest there
        placed.append(arc[on].mean())
        assert ep.truth[ep.start] not in HARD_IDS and ep.truth[ep.goal] not in HARD_IDS
    assert placed[0] <= placed[-1]  # from the start's end to the goal's
    with pytest.raises(ValueError, match=rf"blockage_at = 0\.01: choose {lo:.2f} to {1 - lo:.2f} of this "):
        build(drawn, index, blockage_at=0.01)


def test_no_blockage_leaves_the_map_as_mapped(drawn):
    ep = build(drawn, blockage=False)
    assert np.array_equal(ep.truth, ep.prior.labels)
    assert len(ep.walkers) == drawn[0].stack.pedestrians


def test_pedestrians_count_speed_and_the_standing_ones(drawn):
    base = build(drawn)
    ep = build(drawn, pedestrians=5, speed=1.3, standing=(0.3, 0.7))
    walking, standing = ep.walkers[:5], ep.walkers[5:]
    assert len(ep.walkers) == 7 and all(w.speed == 1.3 for w in walking)
    assert np.array_equal(walking[0].path, base.walkers[0].path)
    path = walking[0].path
    arc = walking[0].arc
    for walker, fraction in zip(standing, (0.3, 0.7), strict=True):
        here = walker.position(0.0)
        assert np.array_equal(here, walker.position(50.0)) and np.allclose(walker.velocity(3.0), 0.0)  # it stands
        # on the pedestrians' path (which runs from the goal to the start), that far from the start's end
        s = (1 - fraction) * arc[-1]
        assert np.allclose(here, [np.interp(s, arc, path[:, 0]), np.interp(s, arc, path[:, 1])])
    faster = build(drawn, speed=1.3)
    assert [w.offset_m for w in faster.walkers] == [w.offset_m for w in base.walkers]  # the speed alone changes
    assert build(drawn, pedestrians=0).walkers == ()


@pytest.mark.parametrize(("choices", "message"), [
    ({"pedestrians": 9}, r"pedestrians = 9: choose 0 to 8"),
    ({"pedestrians": 2.5}, r"pedestrians = 2.5: choose 0 to 8"),
    ({"speed": -0.1}, r"speed = -0.1: choose 0 to 2 m/s"),
    ({"speed": math.nan}, r"speed = nan: choose 0 to 2 m/s"),
    ({"preference": "random"}, r"preference = 'random': choose realistic or inverted"),
    ({"blockage_at": 1.0}, r"blockage_at = 1.0: choose a fraction between 0 and 1"),
    ({"blockage": False, "blockage_at": 0.5}, r"blockage_at = 0.5: .*\(with a blockage\)"),
    ({"standing": (0.5, 1.2)}, r"standing = \(0.5, 1.2\): at most 4 fractions between 0 and 1"),
    ({"order": ("grass", "grass")}, r"order = \('grass', 'grass'\): name distinct terrains"),
    ({"order": ("grass",), "preference": "inverted"}, r"leave preference unset"),
])
def test_bad_choices_are_refused_naming_the_field(choices, message):
    with pytest.raises(ValueError, match=message) as refused:
        EpisodeChoices(**choices)
    assert "\n" not in str(refused.value)


def test_a_standing_pedestrian_on_the_start_is_refused(drawn):
    with pytest.raises(ValueError, match=r"standing = 0: choose 0\.\d\d to 0\.\d\d of this \d+ m pedestrian path"):
        build(drawn, standing=(0.0,))


def test_walker_arc_is_computed_once():
    walker = world.Walker(np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]]), 1.0, 0.5)
    assert walker.arc is walker.arc and np.allclose(walker.arc, [0.0, 3.0, 7.0])
    times = np.linspace(0.0, 20.0, 41)
    assert np.array_equal(walker.track(times), np.array([walker.position(t) for t in times]))


# ------------------------------------------------------------------------------------------ the playground


@pytest.fixture(scope="module")
def loaded(smoke_data, smoke_artifacts):
    return StackPlayground.load("smoke", smoke_data, smoke_artifacts)


@pytest.fixture
def view(loaded):
    view = StackView(loaded)
    view.start(0, drive=False)
    return view


@pytest.fixture(scope="module")
def stack_drive(loaded):
    """The full stack driven once on episode 0 with a pedestrian standing mid-way (seconds)."""
    view = StackView(loaded)
    view.start(0, standing="0.5", row="stack")
    return view, loaded.shown()


def test_the_widgets_change_the_episode_as_asked(view):
    p = view.playground
    realistic = p.episode()
    view.preference.value = "inverted"
    assert view.message.kind == "info", view.message.text
    assert p.episode().ordering.tolist() == realistic.ordering[::-1].tolist()
    shown = view.result.value
    view.blockage.value = "none"
    assert np.array_equal(p.episode().truth, p.episode().prior.labels) and view.result.value != shown
    view.blockage_at.value = 0.6  # the slider places one there (and the toggle follows)
    assert p.choices.blockage_at == 0.6 and view.blockage.value == "at"
    view.pedestrians.value = 4
    view.standing.value = "0.4, 0.6"
    assert len(p.episode().walkers) == 6 and p.choices.standing == (0.4, 0.6)
    view.speed.value = 1.5
    assert {w.speed for w in p.episode().walkers} == {1.5, 0.0}
    view.order.value = "grass > pavers"
    assert p.episode().preference == "custom" and view.message.kind == "info"
    view.order.value = ""
    assert p.choices.order is None and p.episode().preference in ("realistic", "inverted")


@pytest.mark.parametrize(("action", "message"), [
    (lambda p: p.set_blockage("at", 0.01), r"blockage_at = 0.01: choose 0\.\d\d to 0\.\d\d of this \d+ m walkway"),
    (lambda p: p.set_pedestrians(12), "pedestrians = 12: choose 0 to 8"),
    (lambda p: p.set_speed(math.nan), "speed = nan: choose 0 to 2 m/s"),
    (lambda p: p.set_standing("half"), "standing = 'half': give fractions of the pedestrians' path"),
    (lambda p: p.set_standing("0.01"), r"standing = 0.01: choose"),
    (lambda p: p.set_order("grass > moon dust"), "order names 'moon dust': not a terrain"),
    (lambda p: p.set_preference("random"), "preference = 'random': choose realistic or inverted"),
    (lambda p: p.choose_episode(500), "episode 500: choose 0 to 99"),
    (lambda p: p.choose_row("no_stack"), "row 'no_stack': choose one of stack, no_pacer"),
    (lambda p: p.set_time(3.0), "no drive yet: press drive"),
])
def test_a_bad_choice_is_one_line_in_the_widget(view, action, message):
    """What the view shows for a refused choice: one line (marked), no traceback, the state and drawing as they were."""
    p = view.playground
    key, drawn_before = p.key(), view.result.value
    assert not view.act(action, p)
    assert view.message.kind == "error"
    assert re.search(message, view.message.text), view.message.text
    assert "\n" not in view.message.text and "Traceback" not in view.message.widget.value
    assert view.message.widget.value.count(ERROR_MARK) == 1
    assert p.key() == key and view.result.value == drawn_before


def test_a_refused_slider_goes_back_to_the_state(view):
    p = view.playground
    view.blockage_at.value = 0.02  # too near the start: refused, and the toggle and the slider show the state
    assert view.message.kind == "error" and p.choices.blockage_at is None and view.blockage.value == "drawn"


def test_a_drive_starts_at_the_start_and_the_time_slider_shows_where_everything_was(stack_drive, loaded):
    view, drive = stack_drive
    p = loaded
    traj, episode = drive.outcome.trajectory, drive.episode
    assert drive.outcome.row == STACK and len(traj) > 1 and drive.seconds > 0
    assert np.allclose(traj[0, 1:3], episode.prior.frame.cell_to_world(np.array(episode.start)))
    assert np.all(np.diff(traj[:, 0]) > 0)
    assert "contact(s), low-tier share" in view.message.text and "SPL" in view.summary.value
    assert view.frame.max == math.ceil(traj[-1, 0] / FRAME_S - 1e-9) and view.moment.layout.display is None
    pictures = set()
    for frame in (0, view.frame.max // 2, view.frame.max):
        view.frame.value = frame
        assert view.message.kind == "info", view.message.text
        moment = p.moment()
        t = min(frame * FRAME_S, traj[-1, 0])
        assert math.isclose(moment.t, t) and view.clock.value.startswith(f"t = {t:.1f}")
        j = int(np.argmin(np.abs(traj[:, 0] - t)))  # the re-plan nearest t: the robot is at most a step from it
        assert np.linalg.norm(moment.robot[:2] - traj[j, 1:3]) <= p.params.hj.grids.robot.v_max * abs(traj[j, 0] - t) + 1e-9
        if frame in (0, view.frame.max):
            assert np.array_equal(moment.robot[:2], traj[0 if frame == 0 else -1, 1:3])
        assert np.array_equal(moment.pedestrians, np.array([w.position(t) for w in episode.walkers]))
        assert np.array_equal(moment.pedestrians[-1], episode.walkers[-1].position(0.0))  # the standing one stands
        pictures.add(view.moment.value)
    assert len(pictures) == 3  # the walkers moved between the frames drawn


def test_a_revisited_choice_is_answered_from_the_cache(view):
    p = view.playground
    view.row.value = NO_HJ
    assert view.act(view.drive) and p.shown() is not None
    drawn, misses = view.result.value, p.drives.misses
    view.pedestrians.value = 3
    assert p.shown() is None and "press drive" in view.message.text  # a new choice: not driven yet
    view.pedestrians.value = p.params.stack.pedestrians  # back: its drive shown at once, nothing re-driven
    assert p.shown() is not None and view.result.value == drawn and p.drives.misses == misses
    hits = p.drives.hits
    assert view.act(view.drive) and p.drives.misses == misses and p.drives.hits > hits


def test_the_notebook_scenario_sets_the_controls(loaded):
    view = StackView(loaded)
    view.start(1, preference="inverted", blockage=0.5, pedestrians=3, speed=1.0, standing=[0.5], row="no_hj",
               drive=False)
    assert (view.index.value, view.row.value, view.preference.value) == (1, NO_HJ, "inverted")
    assert (view.blockage.value, view.blockage_at.value) == ("at", 0.5)
    assert (view.pedestrians.value, view.speed.value, view.standing.value) == (3, 1.0, "0.5")
    assert len(loaded.episode().walkers) == 4 and view.message.kind == "info"


def test_a_bad_notebook_scenario_stops_with_one_line_naming_the_parameters(loaded):
    with pytest.raises(ParamsError, match=r"notebook parameter episode = 0, .*blockage = 0.01.*: blockage_at = 0.01: "
                                          r"choose"):
        StackView(loaded).start(0, blockage=0.01, drive=False)


def test_missing_artefacts_are_named_at_once_with_one_command(smoke_data, tmp_path):
    with pytest.raises(DataError, match=(
            rf"needs pacer_phase1, pacer_phase2, pacer_phase3, surenav_context_demos, surenav_context_estimator, "
            rf"hj_grids \(profile smoke, not in {tmp_path}\): build them with `python -m navlab artifacts build "
            rf"--profile smoke --data-dir {smoke_data} --artifacts-dir {tmp_path} --only pacer_phase1 --only "
            rf"pacer_phase2 --only pacer_phase3 --only surenav_context_demos --only surenav_context_estimator "
            rf"--only hj_grids`")) as refused:
        StackPlayground.load("smoke", smoke_data, tmp_path)
    assert "\n" not in str(refused.value)
