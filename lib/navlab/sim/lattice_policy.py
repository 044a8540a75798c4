"""The HJ-guided lattice planner as a receding-horizon policy (HJ-search paper Sec. VII-D, VIII).

At every re-plan the policy searches from the observed state to the current goal with a deterministic
expansion budget and returns the plan's (a, ω) commands; the simulator executes the first of them.
With ``anytime`` the search is ANA* (the paper's real-robot planner, Sec. VIII): greedy until a first
plan, then improving it until the budget is spent, so a budget far below what optimal A* needs over a
long trip still gives a plan; without, A* (the plan is optimal or there is none).
The observed speed is put on the nearest lattice speed level (the lattice starts from levels only;
the commanded accelerations then act on the true speed, as on the robot).

Human handling, the three rows of Tables VI and IX:

- ``"fi"`` / ``"fs"``: the human-robot BRT pruner (``reach.pruners.human_pruner``) with the observed
  human positions, forward-invariant (Eq. 14-18) or feasible-set;
- ``"obs"``: the paper's OBS baseline, "the human as a static obstacle at its instantaneous position":
  the humans are discs added to the clearance field of the OBS static pruner, re-built per re-plan.

A plan that cannot start (the observed state already pruned) or is not found within the budget is an
empty command list: the simulator then brakes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from navlab.maps.rooms import Room
from navlab.reach.lookup import HumanBRTLookup
from navlab.reach.pruners import FIParams, clearance_field, human_pruner
from navlab.search.dubins_lattice import LatticeSpec, primitive_table
from navlab.search.lattice_fields import GridField
from navlab.search.lattice_search import NO_HUMAN, Goal, Heuristic, StaticPruner, search

HUMAN_MODES = ("fi", "fs", "obs", "none")


@dataclass
class LatticePolicy:
    spec: LatticeSpec
    room: Room
    heuristic_for: Callable[[tuple[float, float]], Heuristic]  # goal -> heuristic (cached per goal)
    static: StaticPruner
    goal_tolerance: float
    goal_max_speed: float
    max_expansions: int
    human_mode: str = "none"
    human_brt: HumanBRTLookup | None = None
    human_radius: float = 0.3
    fi: FIParams = field(default_factory=FIParams)
    anytime: bool = False
    expansions: list[int] = field(default_factory=list)
    _table: np.ndarray = field(init=False, repr=False)
    _heuristics: dict = field(init=False, repr=False, default_factory=dict)
    _clearance: GridField | None = field(init=False, repr=False, default=None)
    _points: tuple[np.ndarray, np.ndarray] | None = field(init=False, repr=False, default=None)

    def __post_init__(self):
        if self.human_mode not in HUMAN_MODES:
            raise ValueError(f"human_mode {self.human_mode!r}: use one of {', '.join(HUMAN_MODES)}")
        if self.human_mode in ("fi", "fs") and self.human_brt is None:
            raise ValueError(f"human_mode {self.human_mode!r} needs the human-robot BRT: load it with "
                             f"reach.precompute.load_human_brt (built by `dvc repro hj_grids`)")
        if self.human_mode == "obs" and self.static.name != "OBS":
            raise ValueError("human_mode 'obs' adds the humans to the OBS clearance field: pass an OBS static "
                             "pruner (reach.pruners.obs_pruner)")
        self._table = primitive_table(self.spec)
        if self.human_mode == "obs":
            self._clearance = clearance_field(self.room)
            n = self._clearance.shape
            h = 1.0 / self._clearance.inv_spacing
            self._points = np.meshgrid(np.arange(n[0]) * h[0], np.arange(n[1]) * h[1], indexing="ij")

    @property
    def dt(self) -> float:
        return self.spec.dt

    def _static_for(self, humans: np.ndarray) -> StaticPruner:
        if self.human_mode != "obs" or len(humans) == 0:
            return self.static
        x, y = self._points
        gap = np.min([np.hypot(x - hx, y - hy) - self.human_radius for hx, hy in humans], axis=0)
        values = np.minimum(self._clearance.values, gap.reshape(-1).astype(self._clearance.values.dtype))
        return StaticPruner(self.static.kind, self._clearance._replace(values=values), self.static.par, "OBS")

    def __call__(self, observation) -> np.ndarray:
        state = np.asarray(observation.robot, dtype=float).copy()
        state[2] = np.clip(np.round(state[2] / self.spec.dv), 0, self.spec.speed_levels - 1) * self.spec.dv
        humans = np.asarray(observation.humans, dtype=float).reshape(-1, 2)
        static = self._static_for(humans)
        (x0, x1), (y0, y1) = self.room.bounds
        if not (x0 <= state[0] < x1 and y0 <= state[1] < y1) or static.values(state[None])[0] <= 0.0:
            return np.zeros((0, 2))
        goal = tuple(observation.goal)
        if goal not in self._heuristics:
            self._heuristics[goal] = self.heuristic_for(goal)
        human = NO_HUMAN
        if self.human_mode in ("fi", "fs") and len(humans):
            human = human_pruner(self.human_brt, humans, self.human_mode, self.fi)
        result = search(self.spec, self.room.bounds, state, Goal(goal, self.goal_tolerance, self.goal_max_speed),
                        self._heuristics[goal], static=static, human=human, max_expansions=self.max_expansions,
                        anytime=self.anytime, table=self._table)
        self.expansions.append(result.expansions)
        return result.controls if result.found else np.zeros((0, 2))
