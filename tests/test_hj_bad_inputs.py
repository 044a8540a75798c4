"""Bad input to the lattice search and its pruners (issue 26, item 4): each stops with one clear ValueError.

Measured before: a NaN heading hung the compiled look-up, a NaN x or v was reported safe by every static
and human pruner, a negative goal tolerance acted as a positive one, a costmap with negative cells returned
a plan of negative cost, and a goal inside a wall spent the whole expansion budget. The pruners here are
built on small synthetic fields (no HJ solve), so the file runs in seconds once numba's cache is warm.
"""

from __future__ import annotations

import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.hj.guidance import dist_heuristic
from navlab.hj.lattice_policy import LatticePolicy
from navlab.hj.pruners import FIParams, human_pruner, obs_pruner, static_brt_pruner
from navlab.hj.receding_horizon import Observation
from navlab.maps.rooms import Disc, Room
from navlab.reach.grid import Grid
from navlab.reach.lookup import HumanBRTLookup, StaticBRTLookup
from navlab.reach.store import StoredGrid
from navlab.search.dubins_lattice import LatticeSpec, primitive_table, successor_samples
from navlab.search.lattice_fields import GridField
from navlab.search.lattice_reference import astar_reference
from navlab.search.lattice_search import Budget, Costmap, Goal, Pruners, StaticPruner, search

ROOM = Room("test", 3.0, 2.0, obstacles=(Disc(1.5, 1.0, 0.25),))
SPEC = LatticeSpec(0.5, (-0.5, 0.0, 0.5), (-1.0, 0.0, 1.0), 0.5, 3, 3, 0.25, 8)
GOAL = Goal((2.6, 1.0), 0.3, 0.25)
START = np.array([0.4, 1.0, 0.0, 0.0])
RADIUS = 0.1
BAD = (math.nan, math.inf, -math.inf)


def _brt_lookup() -> StaticBRTLookup:
    """A stand-in static BRT on (x, y, v, θ): the clearance less a speed- and heading-dependent stopping
    distance (any smooth field would do; this one is unsafe inside the inflated disc, as a BRT is)."""
    grid = Grid((0.0, 0.0, 0.0, -math.pi), (3.0, 2.0, 0.5, math.pi), (31, 21, 3, 8), (False, False, False, True))
    x, y, v, th = np.meshgrid(*(grid.axis(d) for d in range(4)), indexing="ij")
    values = ROOM.obstacle_distance(x, y) - RADIUS - 0.2 * v * (1 + 0.5 * np.cos(th))
    return StaticBRTLookup(StoredGrid(values.astype(np.float32), grid, {}))


def _human_lookup() -> HumanBRTLookup:
    """A stand-in human-robot BRT on (p_x, p_y, v): distance less the collision radius and a speed term."""
    grid = Grid((-2.0, -2.0, 0.0), (2.0, 2.0, 0.5), (21, 21, 3), (False, False, False))
    px, py, v = np.meshgrid(*(grid.axis(d) for d in range(3)), indexing="ij")
    values = (np.hypot(px, py) - 0.4 - 0.3 * v).astype(np.float32)
    inputs = {"robot": {"radius_m": 0.1, "v_max": 0.5}, "human": {"radius_m": 0.3, "speed": 0.5},
              "human_brt": {"horizon_s": 1.0}}
    return HumanBRTLookup(StoredGrid(values, grid, {"inputs": inputs}))


OBS, BRT, HUMAN = obs_pruner(ROOM, RADIUS), static_brt_pruner(_brt_lookup(), 0.0), _human_lookup()
HEURISTIC = dist_heuristic(GOAL.xy, SPEC.v_max, GOAL.tolerance)
SAMPLES = successor_samples(SPEC, primitive_table(SPEC), START)  # (P, S, 4), all in free space
PARENTS = np.broadcast_to(START, (len(SAMPLES), 4))


def _entries():
    """Every public Python entry that takes states: (name, call(states (N, 4), segments (N, S, 4)), the
    arguments it reads)."""
    fs, fi = (human_pruner(HUMAN, np.array([[1.0, 1.6]]), kind) for kind in ("fs", "fi"))
    states, segments, both = ("states",), ("segments",), ("states", "segments")
    return [
        ("OBS", lambda s, seg: OBS(seg), segments), ("OBS values", lambda s, seg: OBS.values(s), states),
        ("BRT", lambda s, seg: BRT(seg), segments), ("BRT values", lambda s, seg: BRT.values(s), states),
        ("FS", lambda s, seg: fs(s, seg), both), ("FI", lambda s, seg: fi(s, seg), both),
        ("heuristic", lambda s, seg: HEURISTIC(s), states),
    ]


def test_compiled_lookup_returns_for_any_heading():
    """The compiled periodic wrap, called without the Python checks: a NaN or inf heading once floored to
    INT64_MIN and `while i0 < 0: i0 += n` ran ~10^18 times; a finite 1e15 rad took ~10^15 rounds. Run in a
    child process so that a regression fails on the timeout instead of hanging the test run."""
    code = textwrap.dedent("""
        import math, numpy as np
        from navlab.search.lattice_fields import S_BRT, GridField, static_value_batch
        values = np.arange(6 * 5 * 3 * 8, dtype=np.float32).reshape(6, 5, 3, 8)
        f = GridField.from_grid(values, (0.0, 0.0, 0.0, -math.pi), (0.5, 0.5, 0.25, math.pi / 4),
                                (False, False, False, True))
        states = np.array([[1.0, 1.0, 0.2, th] for th in (math.nan, math.inf, -math.inf, 1e15, -1e15)])
        out = static_value_batch(S_BRT, f, np.array([0.0, -1.0]), states)
        assert values.min() <= out[3] <= values.max() and values.min() <= out[4] <= values.max(), out
        print("returned")
    """)
    done = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "returned" in done.stdout, done.stderr[-2000:]


@pytest.mark.parametrize("bad", BAD)
@pytest.mark.parametrize("axis", range(4))
def test_every_pruner_entry_refuses_a_non_finite_state(axis, bad):
    for name, call, reads in _entries():
        call(PARENTS, SAMPLES)  # finite: answered
        for which in reads:
            states, segments = PARENTS.copy(), SAMPLES.copy()
            (states[1] if which == "states" else segments[2, 1])[axis] = bad
            with pytest.raises(ValueError, match=r"holds NaN or inf \(first at index .*\); pass finite"):
                call(states, segments)
                pytest.fail(f"{name} answered for {which} with {bad} at axis {axis}")
    start = START.copy()
    start[axis] = bad
    with pytest.raises(ValueError, match="start must be a finite"):
        astar_reference(SPEC, ROOM.bounds, start, GOAL.xy, GOAL.tolerance, GOAL.max_speed, HEURISTIC, OBS)


@pytest.mark.parametrize("bad", BAD)
def test_human_pruner_refuses_non_finite_humans_velocities_and_times(bad):
    with pytest.raises(ValueError, match=r"humans \(x, y, vx, vy\) holds NaN or inf"):
        human_pruner(HUMAN, np.array([[1.0, bad]]))
    with pytest.raises(ValueError, match=r"humans \(x, y, vx, vy\) holds NaN or inf"):
        human_pruner(HUMAN, np.array([[1.0, 1.6]]), velocities=np.array([[bad, 0.0]]), prediction_s=1.0)
    fi = human_pruner(HUMAN, np.array([[1.0, 1.6]]), prediction_s=1.0)
    times = np.zeros(len(SAMPLES))
    times[3] = bad
    with pytest.raises(ValueError, match="t0 holds NaN or inf"):
        fi(PARENTS, SAMPLES, t0=times)
    with pytest.raises(ValueError, match="durations holds NaN or inf"):
        fi(PARENTS, SAMPLES, durations=times)
    with pytest.raises(ValueError, match="FIParams margin"):
        FIParams(margin=bad)
    with pytest.raises(ValueError, match="8 parents for 9 segments"):
        fi(PARENTS[:8], SAMPLES)


@pytest.mark.parametrize("bad", BAD)
def test_pruner_thresholds_must_be_finite(bad):
    with pytest.raises(ValueError, match="OBS robot_radius"):
        obs_pruner(ROOM, bad)
    with pytest.raises(ValueError, match="static BRT margin"):
        static_brt_pruner(_brt_lookup(), bad)
    with pytest.raises(ValueError, match="threshold"):
        OBS.with_threshold(bad)


@pytest.mark.parametrize("kwargs, message", [
    ({"tolerance": -0.3}, "goal tolerance -0.3: must be a finite number >= 0"),
    ({"tolerance": math.nan}, "goal tolerance nan"),
    ({"max_speed": -0.1}, "goal max_speed -0.1"),
    ({"max_speed": math.nan}, "goal max_speed nan"),
    ({"xy": (math.nan, 1.0)}, r"goal xy \(nan, 1.0\): must be two finite numbers"),
])
def test_goal_refuses_negative_and_nan_tolerance_and_speed(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Goal(**{"xy": (2.6, 1.0), "tolerance": 0.3, "max_speed": 0.25, **kwargs})


def test_costmap_refuses_nan_and_negative_weights_and_cells():
    raster = np.ones((4, 3), np.float32)
    field = GridField.from_grid(raster, (0.0, 0.0), (1.0, 1.0), (False, False))
    Costmap(field, 1.0)  # valid
    for weight in (-1.0, math.nan, math.inf):
        with pytest.raises(ValueError, match="costmap weight .*: must be a finite number >= 0"):
            Costmap(field, weight)
    for cell in (-3.0, math.nan):
        bad = raster.copy()
        bad[2, 1] = cell
        with pytest.raises(ValueError, match="costmap field: every cell cost must be finite and >= 0"):
            Costmap(field._replace(values=bad.reshape(-1)), 1.0)


@pytest.mark.parametrize("pruner", [OBS, BRT], ids=["OBS", "BRT"])
def test_a_goal_inside_an_obstacle_is_refused_before_searching(pruner):
    """Before: the search spent its whole budget and said "expansion limit"."""
    with pytest.raises(ValueError, match=rf"goal \(1.5, 1.0\) .* wholly pruned by the {pruner.name} pruner"):
        search(SPEC, ROOM.bounds, START, Goal((1.5, 1.0), 0.1, 0.25), HEURISTIC,
               pruners=Pruners(static=pruner), budget=Budget(max_expansions=3000))


def test_a_goal_whose_centre_is_pruned_but_whose_disc_is_not_is_still_searched():
    """The refusal must never drop a reachable goal: a centre inside the inflated disc is fine as long as
    the tolerance reaches free space."""
    goal = Goal((1.5, 1.0), 0.45, 0.25)
    assert OBS.values(np.array([[1.5, 1.0, 0.0, 0.0]]))[0] < 0
    assert search(SPEC, ROOM.bounds, START, goal, dist_heuristic(goal.xy, SPEC.v_max, 0.45),
                  pruners=Pruners(static=OBS)).found


@pytest.mark.parametrize("pruner", [OBS, BRT], ids=["OBS", "BRT"])
def test_goal_clearance_bounds_the_pruner_over_the_goal_disc(pruner):
    """The refusal is sound: no state within the tolerance, at any speed or heading, scores above it."""
    rng = np.random.default_rng(0)
    for _ in range(60):
        goal = Goal(tuple(rng.uniform((-0.2, -0.2), (3.2, 2.2))), float(rng.uniform(0.0, 0.5)), 0.5)
        r, a = goal.tolerance * np.sqrt(rng.uniform(size=400)), rng.uniform(-math.pi, math.pi, 400)
        states = np.stack([goal.xy[0] + r * np.cos(a), goal.xy[1] + r * np.sin(a), rng.uniform(0, 0.5, 400),
                           rng.uniform(-4, 4, 400)], axis=1)
        assert pruner.values(states).max() <= pruner.goal_clearance(goal) + 1e-9


def test_the_obs_policy_waits_for_a_human_standing_on_the_goal():
    """A human's disc may cover the whole goal ("obs" mode): that goal is reachable once they move, so the
    policy plans (and fails, and brakes) as before instead of refusing it; a goal inside the map's own
    obstacle is still refused, and a non-finite observation is named."""
    policy = LatticePolicy(SPEC, ROOM, lambda g: dist_heuristic(g, SPEC.v_max, 0.2), obs_pruner(ROOM, RADIUS),
                           goal_tolerance=0.2, goal_max_speed=0.25, max_expansions=2000, human_mode="obs")
    on_goal = Observation(0.0, START, GOAL.xy, np.array([GOAL.xy]), np.zeros((1, 2)))
    covered = policy._static_for(on_goal.humans)
    assert StaticPruner.goal_clearance(covered, Goal(GOAL.xy, 0.2, 0.25)) <= 0  # the disc covers the goal
    assert len(policy(on_goal)) == 0
    with pytest.raises(ValueError, match="wholly pruned"):
        policy(Observation(0.0, START, (1.5, 1.0), np.zeros((0, 2)), np.zeros((0, 2))))
    with pytest.raises(ValueError, match=r"observation.humans holds NaN or inf"):
        policy(Observation(0.0, START, GOAL.xy, np.array([[math.nan, 1.0]]), np.zeros((1, 2))))
    with pytest.raises(ValueError, match=r"observation.robot holds NaN or inf"):
        policy(Observation(0.0, np.array([0.4, 1.0, 0.0, math.nan]), GOAL.xy, np.zeros((0, 2)), np.zeros((0, 2))))


finite = st.floats(-5.0, 5.0, allow_nan=False, allow_infinity=False)
poison = st.sampled_from(BAD)


@settings(max_examples=50, deadline=None)
@given(data=st.data(), n=st.integers(1, 4), s=st.integers(1, 4))
def test_non_finite_values_anywhere_raise_from_every_entry(data, n, s):
    """NaN/inf sprinkled at random positions of the states, segments, humans, start and goal: a ValueError
    from every pruner entry and from ``search`` (never a hang, never a "safe" answer)."""

    def sprinkled(shape, base=None):
        size = math.prod(shape)
        array = np.array(data.draw(st.lists(finite, min_size=size, max_size=size)) if base is None else base,
                         np.float64).reshape(shape)
        for _ in range(data.draw(st.integers(1, 3))):
            array.flat[data.draw(st.integers(0, array.size - 1))] = data.draw(poison)
        return array

    states, segments = sprinkled((n, 4)), sprinkled((n, s, 4))
    for name, call, _ in _entries():
        with pytest.raises(ValueError, match="NaN or inf"):
            call(states, segments)
            pytest.fail(f"{name} answered")
    with pytest.raises(ValueError, match="NaN or inf"):
        human_pruner(HUMAN, sprinkled((data.draw(st.integers(1, 3)), 2)))
    task = sprinkled((6,), base=np.r_[START, GOAL.xy])  # start (x, y, v, θ) and goal (x, y)
    with pytest.raises(ValueError, match="finite"):
        search(SPEC, ROOM.bounds, task[:4], Goal((task[4], task[5]), GOAL.tolerance, GOAL.max_speed),
               HEURISTIC, pruners=Pruners(static=data.draw(st.sampled_from([OBS, BRT]))),
               budget=Budget(max_expansions=200))
