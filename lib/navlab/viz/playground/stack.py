"""The stack playground (issue 64, item 4): "what does the stack do if *I* set the preference, the blockage and
the pedestrians?"

A person picks an episode of the ablation (a test tile, its start and goal: episode k is on test tile k mod 5),
then sets what the seeded draw would otherwise choose (``stack.world.EpisodeChoices``): the operator's
preference (realistic, inverted, or a terrain order of their own), the blockage (the drawn one, none, or one
placed at a fraction of the walkway route), the walking pedestrians' number and speed and pedestrians standing
still. Before a drive they see the episode (the map as it is, the terrain costs the route will plan on, the
aerial image with the operator's context); **drive** runs one row of the ablation on it — the full stack or one
single-layer ablation — exactly as the ablation does (``stack.ablation.run_episode`` on the layers of
``load_layers``), then shows the robot's and the pedestrians' tracks, the outcome and the metrics, and a time
slider (with a play button) that puts the robot and every pedestrian where they were at that moment.

Everything is the ablation's own code; this module keeps the choices, checks them (one line when refused) and
caches what they give: an episode per choice, the terrain costs per episode (pedestrians change no cost), a
drive per choice and row, so going back to a choice shows its drive at once.
"""

from __future__ import annotations

import dataclasses
import html
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import ipywidgets as widgets
import numpy as np
import torch

from navlab.core.params import Params, load_params
from navlab.hj.grids import grid_path
from navlab.maps.dataset import load_maps
from navlab.maps.semantic_map import SemanticMap
from navlab.pacer.artifacts import phase_dir
from navlab.pacer.terrain import TerrainBank, load_terrain_bank
from navlab.pacer.train import PHASES
from navlab.stack.ablation import NO_PACER, ROWS, STACK, Layers, Outcome, load_layers, run_episode
from navlab.stack.world import OPERATOR_PREFERENCES, EpisodeChoices, StackEpisode, stack_episode
from navlab.surenav.context.dataset import FOLDER as CONTEXT_DEMOS
from navlab.surenav.context.training import context_model_path, main_run
from navlab.viz.playground.common import Memo, PlaygroundView, UserError, figure_bytes, require_built
from navlab.viz.stack import Moment, episode_figure, moment_figure

MAX_INDEX = 99  # episodes a person may pick (the ablation runs stack.episodes of them; any index is a fair draw)
ROW_KEYS = dict(zip(("stack", "no_pacer", "no_surenav", "no_hj"), ROWS, strict=True))  # notebook parameter `row`
BLOCKAGES = ("drawn", "at", "none")  # the seeded blockage, one at the slider's fraction, none
FRAME_S = 0.5  # the time slider's step (s of the drive)
REPORT_S = 1.0  # a progress line every simulated second of a drive
Key = tuple[int, EpisodeChoices, str]


@dataclass(frozen=True, eq=False)
class StackDrive:
    """One row driven on one episode: the ablation's outcome, the terrain costs its route planned on and the
    wall time the drive took (s)."""

    episode: StackEpisode
    outcome: Outcome
    costs: np.ndarray
    seconds: float


class _Reporting:
    """A motion layer as ``run_episode`` drives it, telling ``report`` the simulated seconds so far every
    ``REPORT_S``: a drive takes seconds to tens of seconds, and the message line should show it moving."""

    def __init__(self, follower, period: float, report: Callable[[float], None]):
        self.follower, self.period, self.report, self.ticks = follower, period, report, 0

    def step(self, *args, **kwargs):
        self.ticks += 1
        if self.ticks % max(1, round(REPORT_S / self.period)) == 0:
            self.report(self.ticks * self.period)
        return self.follower.step(*args, **kwargs)

    def __getattr__(self, name: str):
        return getattr(self.follower, name)


def parse_order(text: str) -> tuple[str, ...] | None:
    """``"grass > pavers > rock"`` (most preferred first) as terrain names; empty: None (the preference)."""
    names = tuple(name.strip() for name in str(text).replace(",", ">").split(">"))
    return None if names == ("",) else names


def parse_fractions(value) -> tuple[float, ...]:
    """``"0.4, 0.7"`` or a sequence of numbers as a tuple of floats; empty: ()."""
    items = [v for v in str(value).strip("[]() ").split(",") if v.strip()] if isinstance(value, str) else list(value)
    try:
        return tuple(float(v) for v in items)
    except (TypeError, ValueError):
        raise UserError(f"standing = {value!r}: give fractions of the pedestrians' path, e.g. 0.5, 0.8") from None


class StackPlayground:
    """The playground's state and rules, without widgets: the episode index, the choices, the row to drive and
    the moment shown; episodes, costs and drives cached. Every mutator builds the episode it asks for before it
    keeps the change, and raises :class:`UserError` (one line) without changing anything when it is refused."""

    def __init__(self, params: Params, tiles: list[SemanticMap], bank: TerrainBank, layers: Layers):
        self.params, self.tiles, self.bank, self.layers = params, tiles, bank, layers
        self.index, self.choices, self.row, self.t = 0, EpisodeChoices(), STACK, 0.0
        self.episodes = Memo(self._episode, size=16)
        self.pacer_costs = Memo(self._pacer_costs, size=16)
        self.drives = Memo(self._drive, size=64)
        self.driven: set[Key] = set()  # what was driven: a revisit shows its drive (a Memo hit) at once
        self.report: Callable[[float], None] = lambda seconds: None  # told a running drive's simulated seconds

    @classmethod
    def load(cls, profile: str, data_dir: str | Path, artifacts_dir: str | Path) -> StackPlayground:
        """The playground on ``profile``'s test tiles and the ablation's layers (PACER's phase-3 model, SuReNav's
        context estimator and demonstrations, HJ-search's TTR and human BRT); a missing one stops with one line
        naming the command that builds them all. One torch thread, as the ablation's workers."""
        params = load_params(profile)
        s = params.surenav
        require_built([*((f"pacer_{phase}", phase_dir(artifacts_dir, phase) / "model.pt") for phase in PHASES),
                       ("surenav_context_demos", Path(artifacts_dir, *CONTEXT_DEMOS, "index.json")),
                       ("surenav_context_estimator",
                        context_model_path(artifacts_dir, main_run(s.demos.context, s.train), s.train.seeds[0])),
                       *(("hj_grids", grid_path(artifacts_dir, name)) for name in ("ttr", "human_brt"))],
                      params.profile, data_dir, artifacts_dir)
        torch.set_num_threads(1)
        bank = load_terrain_bank(data_dir, params.pacer.data)
        return cls(params, load_maps(data_dir, "test"), bank, load_layers(params, artifacts_dir, bank))

    # --- choices ------------------------------------------------------------------------------------
    def choose_episode(self, index) -> None:
        if not (isinstance(index, int | np.integer) and 0 <= index <= MAX_INDEX):
            raise UserError(f"episode {index!r}: choose 0 to {MAX_INDEX} (episode k is on test tile k mod "
                            f"{len(self.tiles)})")
        self._commit(int(index), self.choices)

    def set_preference(self, preference: str) -> None:
        """The operator's order of the terrains in view: realistic or inverted (clears a custom order)."""
        self._commit(self.index, self._with(preference=preference, order=None))

    def set_order(self, text: str) -> None:
        """A custom order, ``"A > B > C"`` most preferred first (terrains in view it leaves out follow, in the
        realistic order); empty: back to the preference."""
        order = parse_order(text)
        self._commit(self.index, self._with(order=order, preference=None))

    def set_blockage(self, mode: str, at: float = 0.5) -> None:
        """``drawn`` (the episode's seeded blockage), ``at`` (one at fraction ``at`` of the walkway route) or
        ``none``."""
        if mode not in BLOCKAGES:
            raise UserError(f"blockage {mode!r}: choose {', '.join(BLOCKAGES)}")
        self._commit(self.index, self._with(blockage=mode != "none", blockage_at=float(at) if mode == "at" else None))

    def set_pedestrians(self, count: int) -> None:
        self._commit(self.index, self._with(pedestrians=int(count)))

    def set_speed(self, speed: float) -> None:
        self._commit(self.index, self._with(speed=float(speed)))

    def set_standing(self, fractions) -> None:
        """Pedestrians standing still at these fractions of the pedestrians' path (from the robot's start)."""
        self._commit(self.index, self._with(standing=parse_fractions(fractions)))

    def choose_row(self, row: str) -> None:
        """The ablation's row to drive: the full stack or one single-layer ablation (a full name or ``ROW_KEYS``)."""
        row = ROW_KEYS.get(row, row)
        if row not in ROWS:
            raise UserError(f"row {row!r}: choose one of {', '.join(ROW_KEYS)} ({'; '.join(ROWS)})")
        self.row = row

    def set_scenario(self, index: int = 0, preference: str | None = None, blockage="drawn", pedestrians=None,
                     speed=None, standing=(), row: str = "stack") -> None:
        """The notebook's scenario in one step (refused as a whole): ``blockage`` is "drawn", "none" or a
        fraction of the walkway route; ``pedestrians`` / ``speed`` None keep the parameters'."""
        before = self.index, self.choices, self.row
        try:
            self.choose_row(row)
            mode = blockage if blockage in BLOCKAGES[::2] else "at"
            choices = self._with(preference=preference, order=None, blockage=mode != "none",
                                 blockage_at=None if mode != "at" else _number("blockage", blockage),
                                 pedestrians=pedestrians, speed=speed, standing=parse_fractions(standing))
            if not (isinstance(index, int | np.integer) and 0 <= index <= MAX_INDEX):
                raise UserError(f"episode {index!r}: choose 0 to {MAX_INDEX}")
            self._commit(int(index), choices)
        except UserError:
            self.index, self.choices, self.row = before
            raise

    def set_time(self, t: float) -> None:
        """The moment shown: ``t`` seconds into the drive (clipped to its end)."""
        drive = self.shown()
        if drive is None:
            raise UserError("no drive yet: press drive")
        if not (math.isfinite(t) and t >= 0):
            raise UserError(f"time {t!r}: choose 0 to {drive.outcome.trajectory[-1, 0]:.1f} s")
        self.t = min(float(t), float(drive.outcome.trajectory[-1, 0]))

    def drive(self) -> StackDrive:
        """The chosen row on the chosen episode (cached per choice), shown from its start."""
        key = self.key()
        drive = self.drives(*key)
        self.driven.add(key)
        self.t = 0.0
        return drive

    # --- what they give -----------------------------------------------------------------------------
    def key(self) -> Key:
        return self.index, self.choices, self.row

    def episode(self) -> StackEpisode:
        return self.episodes(self.index, self.choices)

    def shown(self) -> StackDrive | None:
        """The drive of the current choice, if it was driven."""
        key = self.key()
        return self.drives(*key) if key in self.driven else None

    def costs(self, index: int, choices: EpisodeChoices, row: str) -> np.ndarray:
        """The terrain costs ``row`` plans on: the label table's without PACER, else PACER's (cached)."""
        if row == NO_PACER:
            return self.layers.labels(self.episodes(index, choices))
        return self.pacer_costs(index, _costs_key(choices))

    def moment(self) -> Moment:
        """Where the robot (interpolated between its re-plans; heading of the last one) and every pedestrian
        (``Walker.position``) are at the chosen time of the drive shown."""
        drive = self.shown()
        if drive is None:
            raise UserError("no drive yet: press drive")
        traj, t = drive.outcome.trajectory, self.t
        k = int(np.clip(np.searchsorted(traj[:, 0], t, side="right") - 1, 0, len(traj) - 1))
        robot = np.array([np.interp(t, traj[:, 0], traj[:, 1]), np.interp(t, traj[:, 0], traj[:, 2]), traj[k, 4]])
        people = np.array([w.position(t) for w in drive.episode.walkers]).reshape(-1, 2)
        return Moment(t, robot, people)

    def describe(self) -> str:
        """The episode and its choices in one line."""
        ep, c = self.episode(), self.choices
        blockage = ("none" if not c.blockage else "drawn" if c.blockage_at is None else f"at {c.blockage_at:.2f}")
        walking = sum(w.speed > 0 for w in ep.walkers)
        standing = f", {len(c.standing)} standing" if c.standing else ""
        speed = self.params.hj.grids.human.speed if c.speed is None else c.speed
        return (f"episode {self.index} ({ep.name}): operator {ep.preference}, blockage {blockage}, "
                f"{walking} pedestrian(s) at {speed:g} m/s{standing}")

    def summary(self) -> str:
        """The drive shown in one line: outcome, time, contacts, low-tier share, SPL, Fréchet, relaxation IoU."""
        drive = self.shown()
        if drive is None:
            return f"{self.describe()}; press drive ({self.row})"
        v, outcome = drive.outcome.values, drive.outcome.outcome
        if outcome == "success" and not v["success"]:
            outcome = "at the goal, but after a contact: no success"
        return (f"{self.describe()}; {self.row}: {outcome} after {v['time_s']:.1f} s, {v['contacts']:.0f} contact(s), low-tier share {v['low_tier']:.0%}, "
                f"SPL {v['spl']:.2f}, Fréchet {v['frechet']:.2f}, relaxation IoU {v['relaxation_iou']:.2f} "
                f"(driven in {drive.seconds:.1f} s)")

    # --- internals ----------------------------------------------------------------------------------
    def _with(self, **changes) -> EpisodeChoices:
        """The current choices with ``changes``, the parameters' own values stored as None (one cache key per
        episode, however it was reached); refused in one line naming the field."""
        S = self.params.stack
        try:
            choices = dataclasses.replace(self.choices, **changes)
            return dataclasses.replace(
                choices, pedestrians=None if choices.pedestrians == S.pedestrians else choices.pedestrians,
                speed=None if choices.speed == self.params.hj.grids.human.speed else choices.speed)
        except ValueError as err:
            raise UserError(str(err)) from None

    def _commit(self, index: int, choices: EpisodeChoices) -> None:
        """Keep ``index`` and ``choices`` once their episode is built (what depends on the episode refused)."""
        default = self.params.stack.preferences[index % len(self.params.stack.preferences)]
        if choices.preference == default:
            choices = dataclasses.replace(choices, preference=None)
        try:
            self.episodes(index, choices)
        except ValueError as err:
            raise UserError(str(err)) from None
        self.index, self.choices = index, choices
        self.t = 0.0

    def _episode(self, index: int, choices: EpisodeChoices) -> StackEpisode:
        return stack_episode(index, self.tiles, self.params, self.bank, choices)

    def _pacer_costs(self, index: int, choices: EpisodeChoices) -> np.ndarray:
        return self.layers.pacer(self.episodes(index, choices))

    def _drive(self, index: int, choices: EpisodeChoices, row: str) -> StackDrive:
        """``run_episode`` on one row, its PACER costs the cached ones, its motion layer reporting progress."""
        episode = self.episodes(index, choices)
        pacer = self.costs(index, choices, STACK)
        period = 1.0 / self.params.stack.replan_hz
        layers = dataclasses.replace(self.layers, pacer=lambda _: pacer,
                                     hj=_Reporting(self.layers.hj, period, self.report),
                                     point=_Reporting(self.layers.point, period, self.report))
        began = time.perf_counter()
        (outcome,) = run_episode(episode, layers, self.params, rows=(row,))
        return StackDrive(episode, outcome, self.costs(index, choices, row), time.perf_counter() - began)


def _costs_key(choices: EpisodeChoices) -> EpisodeChoices:
    """The choices the terrain costs depend on: not the pedestrians (drawn after the aerial image and the
    context, they change neither)."""
    return dataclasses.replace(choices, pedestrians=None, speed=None, standing=())


def _number(name: str, value) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise UserError(f"{name} = {value!r}: give a number, \"drawn\" or \"none\"") from None


class StackView(PlaygroundView):
    """The widgets of the stack playground: the episode, the row, the preference (or an order), the blockage,
    the pedestrians, **drive**; then the episode figure with the tracks, the one-line outcome, and the time
    slider (with play) over the moment figure."""

    first_use = ("first use: numba compiles the lattice search, the pruners and the route layer's planners, "
                 "minutes in a fresh clone and seconds once its cache is written")

    def __init__(self, playground: StackPlayground):
        super().__init__()
        self.playground = p = playground
        self._syncing = False  # True while the code, not a person, sets a control
        self.index = widgets.BoundedIntText(p.index, min=0, max=MAX_INDEX, description="episode",
                                            layout=widgets.Layout(width="170px"))
        self.row = widgets.Dropdown(options=[(row, row) for row in ROWS], value=p.row, description="drive row",
                                    layout=widgets.Layout(width="420px"))
        self.preference = widgets.Dropdown(options=OPERATOR_PREFERENCES, description="operator")
        self.order = widgets.Text(placeholder="or an order: grass > pavers > rock", description="order",
                                  continuous_update=False, layout=widgets.Layout(width="380px"))
        self.blockage = widgets.ToggleButtons(options=BLOCKAGES, description="blockage",
                                              tooltips=["the episode's drawn blockage", "one at the slider's place",
                                                        "no blockage"], style={"button_width": "70px"})
        self.blockage_at = widgets.FloatSlider(0.5, min=0.01, max=0.99, step=0.01, description="at (route)",
                                               continuous_update=False)
        self.pedestrians = widgets.IntSlider(p.params.stack.pedestrians, min=0, max=8, description="pedestrians",
                                             continuous_update=False)
        self.speed = widgets.FloatSlider(p.params.hj.grids.human.speed, min=0.0, max=2.0, step=0.1,
                                         description="speed m/s", continuous_update=False)
        self.standing = widgets.Text(placeholder="e.g. 0.5, 0.7 (of their path)", description="standing",
                                     continuous_update=False, layout=widgets.Layout(width="300px"))
        self.drive_button = self.button("drive", self.drive, css="navlab-drive")
        self.result = widgets.Image(format="jpeg")
        self.summary = widgets.HTML()
        self.frame = widgets.IntSlider(0, min=0, max=0, description="t", readout=False, continuous_update=True)
        self.play = widgets.Play(0, min=0, max=0, interval=250, description="play")
        widgets.jslink((self.play, "value"), (self.frame, "value"))
        self.clock = widgets.Label("")
        self.moment = widgets.Image(format="png", layout=widgets.Layout(width="480px"))
        for widget, css in ((self.index, "navlab-episode"), (self.row, "navlab-row"), (self.result, "navlab-result"),
                            (self.frame, "navlab-time"), (self.moment, "navlab-moment"),
                            (self.summary, "navlab-summary")):
            widget.add_class(css)
        self._observe()
        self._figures = Memo(self._figure, size=32)
        self.widget = widgets.VBox([
            widgets.HBox([self.index, self.row, self.drive_button]),
            widgets.HBox([self.preference, self.order]),
            widgets.HBox([self.blockage, self.blockage_at]),
            widgets.HBox([self.pedestrians, self.speed, self.standing]),
            self.message.widget, self.summary, self.result,
            widgets.HBox([self.play, self.frame, self.clock]), self.moment])

    def _observe(self) -> None:
        p = self.playground
        self.index.observe(lambda c: self._forward(p.choose_episode, c["new"]), names="value")
        self.row.observe(lambda c: self._forward(p.choose_row, c["new"]), names="value")
        self.preference.observe(lambda c: self._forward(p.set_preference, c["new"]), names="value")
        self.order.observe(lambda c: self._forward(p.set_order, c["new"]), names="value")
        self.blockage.observe(lambda c: self._forward(p.set_blockage, c["new"], self.blockage_at.value), names="value")
        self.blockage_at.observe(lambda c: self._forward(p.set_blockage, "at", c["new"]), names="value")
        self.pedestrians.observe(lambda c: self._forward(p.set_pedestrians, c["new"]), names="value")
        self.speed.observe(lambda c: self._forward(p.set_speed, c["new"]), names="value")
        self.standing.observe(lambda c: self._forward(p.set_standing, c["new"]), names="value")
        self.frame.observe(lambda c: self._forward(p.set_time, c["new"] * FRAME_S), names="value")

    def start(self, index: int = 0, preference: str | None = None, blockage="drawn", pedestrians=None, speed=None,
              standing=(), row: str = "stack", drive: bool = True) -> None:
        """The notebook's scenario, then (``drive``) its drive; a refused one is a ParamsError naming the
        parameters."""
        self.start_scenario(f"episode = {index!r}, preference = {preference!r}, blockage = {blockage!r}, "
                            f"pedestrians = {pedestrians!r}, speed = {speed!r}, standing = {standing!r}, row = {row!r}",
                            self.playground.set_scenario, index, preference, blockage, pedestrians, speed, standing,
                            row)
        if drive:
            self.start_scenario("drive", self.drive)

    def drive(self) -> None:
        """The chosen row on the chosen episode; the message line counts the simulated seconds meanwhile."""
        p = self.playground
        timeout = p.params.stack.timeout_s
        p.report = lambda seconds: self.message.show(f"driving {p.row}: {seconds:.0f} of at most {timeout:g} s "
                                                     "simulated …", "progress")
        try:
            p.drive()
        finally:
            p.report = lambda seconds: None

    def snapshot(self):
        """The episode with the drive's tracks as a PNG image output: what an executed notebook (papermill) keeps."""
        from IPython.display import Image

        p = self.playground
        return Image(figure_bytes(self._episode_figure(*p.key(), p.key() in p.driven), "png"))

    def status(self) -> str:
        return self.playground.summary()

    def draw(self) -> None:
        p = self.playground
        drive = p.shown()
        self.result.value = self._figures(*p.key(), p.key() in p.driven)
        self.summary.value = f"<b>{html.escape(p.summary())}</b>"
        self._sync_controls()
        self.moment.layout.display = "none" if drive is None else None
        if drive is not None:
            self.moment.value = self._moment_png()
            self.clock.value = f"t = {p.t:.1f} of {drive.outcome.trajectory[-1, 0]:.1f} s"
        else:
            self.clock.value = ""

    def _sync_controls(self) -> None:
        """The controls show the state (a scenario or a refused change may leave them elsewhere), the time
        slider spans the drive shown; their observers do not act on what the code sets."""
        p, c, drive = self.playground, self.playground.choices, self.playground.shown()
        frames = 0 if drive is None else math.ceil(drive.outcome.trajectory[-1, 0] / FRAME_S - 1e-9)
        self._syncing = True
        try:
            self.index.value, self.row.value = p.index, p.row
            self.preference.value = p.episode().preference if c.order is None else self.preference.value
            self.order.value = "" if c.order is None else " > ".join(c.order)
            self.blockage.value = "none" if not c.blockage else "drawn" if c.blockage_at is None else "at"
            if c.blockage_at is not None:
                self.blockage_at.value = c.blockage_at
            self.pedestrians.value = p.params.stack.pedestrians if c.pedestrians is None else c.pedestrians
            self.speed.value = p.params.hj.grids.human.speed if c.speed is None else c.speed
            self.standing.value = ", ".join(f"{f:g}" for f in c.standing)
            self.frame.max = self.play.max = frames
            self.frame.value = min(round(p.t / FRAME_S), frames)
        finally:
            self._syncing = False

    def _figure(self, index: int, choices: EpisodeChoices, row: str, driven: bool) -> bytes:
        return figure_bytes(self._episode_figure(index, choices, row, driven), "jpeg")

    def _episode_figure(self, index: int, choices: EpisodeChoices, row: str, driven: bool):
        """The episode with the drive's tracks (``driven``), else as it is before one."""
        p = self.playground
        drive = p.drives(index, choices, row) if driven else None
        episode = p.episodes(index, choices)
        costs = drive.costs if driven else p.costs(index, choices, row)
        return episode_figure(episode, [] if drive is None else [drive.outcome], costs,
                              "label costs" if row == NO_PACER else "PACER's costs")

    def _moment_png(self) -> bytes:
        p = self.playground
        grids = p.params.hj.grids
        return figure_bytes(moment_figure(p.shown().episode, p.shown().outcome, p.moment(), grids.robot.radius_m,
                                          grids.human.radius_m), "png")

    def _forward(self, action, *args) -> None:
        if not self._syncing:
            self.act(action, *args)

    def act(self, action, *args) -> bool:
        """As every view's; a refused change puts the controls back on the state."""
        done = super().act(action, *args)
        if not done:
            self._sync_controls()
        return done
