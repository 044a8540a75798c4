"""The SuReNav playground (issue 28, item 1): "where does each method relax if *this* passage is closed?"

A person picks a held-out test tile, clicks a start and a goal on the map and clicks superpixels to
close them (a new obstacle, the semi-static change of the benchmark) or to reopen them. For SuReNav,
D* Lite, COA*, RCR and the context demonstrator (each persona) they see the executed path and the
relaxed superpixels side by side, with path length, relaxed area, total risk and the normalised Fréchet
distance to each persona's path; a toggle paints the estimator's relaxation cost Psi on the superpixels.
The methods are those of the reported benchmark, the context demonstrator's (issue 60), built by its own
entry points (``surenav.context.benchmark``: SuReNav's main run, the paper's training, first seed, as
notebook 03; the baselines with their priors from the context training demonstrations; the context
walker per persona), walked by ``windows.walk`` (Algorithm 1's walker in the planning window, widened
when a method finds no plan), and measured by the metric functions of Tables I and Fig. 4
(``path_length``, ``total_risk``, ``relaxed_regions``, ``normalised_frechet``); this module keeps the
choices, checks them and caches what they give.

As in the benchmark, every method plans on the tile as mapped (the prior) and walks the tile with the
closed superpixels turned into buildings (the truth): it learns of a closure only when its sensor sees
it. Superpixels are the tile's stored partition (the one the demonstrations' relaxed regions and the
estimator's training graphs refer to).
"""

from __future__ import annotations

import ast
import html
from dataclasses import dataclass
from pathlib import Path

import ipywidgets as widgets
import numpy as np
import torch
from matplotlib import colormaps
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from skimage.segmentation import find_boundaries

from navlab.core.labels import HARD_IDS, LABELS, SOFT_IDS, colorize
from navlab.core.params import Params, load_params
from navlab.graphs.region_graph import RegionGraph, build_region_graph
from navlab.graphs.superpixels import HARD
from navlab.maps.dataset import load_maps
from navlab.maps.perturb import OBSTACLE
from navlab.maps.semantic_map import SemanticMap
from navlab.metrics.frechet import normalised_frechet
from navlab.metrics.navigation import path_length, risk_table, total_risk
from navlab.metrics.relaxation import relaxed_regions
from navlab.surenav.benchmark import BASELINES, SURENAV
from navlab.surenav.context.benchmark import EXPERT, Factory, baselines, estimator_factory
from navlab.surenav.context.dataset import FOLDER as CONTEXT_DEMOS
from navlab.surenav.context.personas import CONTEXT_PERSONAS
from navlab.surenav.context.training import context_cost, context_model_path, main_run
from navlab.surenav.episodes import Environment, connected
from navlab.surenav.estimator_report import relax_on_prior
from navlab.surenav.experts.store import load_demos
from navlab.surenav.windows import walk
from navlab.viz.playground.common import Memo, PlaygroundView, UserError, figure_bytes, require_built
from navlab.viz.surenav_benchmark import COLOURS as METHOD_COLOURS

MODES = ("start", "goal", "close / open superpixel")
EXPERTS = tuple(f"Expert ({p.name})" for p in CONTEXT_PERSONAS)
METHODS = (SURENAV, *BASELINES, *EXPERTS)  # the panels, in order
COLOURS = {**{m: METHOD_COLOURS[m] for m in (SURENAV, *BASELINES)},
           **dict(zip(EXPERTS, ("black", "0.35", "0.6"), strict=True))}
CLOSED_RGBA = (0.55, 0.0, 0.0, 0.85)  # a closed superpixel: the new obstacle
RELAXED_RGBA = (1.0, 0.65, 0.0, 0.5)  # a relaxed superpixel (soft ground the method walked on): amber, not red
Cell = tuple[int, int]


@dataclass(frozen=True, eq=False)
class MethodRun:
    """One method walked once: its status, the cells walked (start first), the relaxed superpixel ids and
    the metrics (Fréchet to each persona's expert path, by persona name)."""

    status: str
    cells: np.ndarray
    relaxed: np.ndarray
    length_m: float
    relaxed_m2: float
    risk: float
    frechet: dict[str, float]


@dataclass(frozen=True, eq=False)
class SuReNavOutcome:
    """What one scenario (tile, start, goal, closed superpixels) gives: the true map walked, every method's run."""

    tile: str
    start: Cell
    goal: Cell
    closed: frozenset[int]
    truth: np.ndarray
    runs: dict[str, MethodRun]


@dataclass(frozen=True, eq=False)
class Costs:
    """The estimator's view of a scenario (on the true map): the region graph, its window nodes, their
    relaxation cost Psi (metres) and the graph plan X_G (None: no route)."""

    graph: RegionGraph
    nodes: np.ndarray
    psi: np.ndarray
    route: np.ndarray | None


class SuReNavPlayground:
    """The playground's state and rules, without widgets: the tile, start, goal, closed superpixels and the
    click mode; outcomes cached per scenario. Every mutator checks its input first and raises
    :class:`UserError` (one line) without changing anything when it is refused."""

    def __init__(self, params: Params, maps: list[SemanticMap], superpixels: dict[str, np.ndarray],
                 defaults: dict[str, tuple[Cell, Cell]], factories: dict[str, Factory], estimator):
        """``factories``: a fresh policy per environment and planning window for every panel of ``METHODS`` (an
        Expert panel's environment carries its persona); ``estimator``: SuReNav's relaxation cost maker
        (``context.training.context_cost``), for the Psi view."""
        self.params, self.factories, self.estimator = params, factories, estimator
        self.bench = params.surenav.benchmark
        self.maps = {m.name: m for m in maps}
        self.superpixels = superpixels
        self.sizes = {name: np.bincount(sp[sp != HARD]) for name, sp in superpixels.items()}  # cells per id
        self.defaults = defaults
        self.risk = risk_table(self.bench.unit_risk)
        self.tile = next(iter(self.maps))
        self.start, self.goal = defaults[self.tile]
        self.closed: frozenset[int] = frozenset()
        self.mode = MODES[0]
        self.show_costs = False  # paint the estimator's Psi on the map
        self.outcomes = Memo(self._outcome)
        self.costs_of = Memo(self._costs)
        self.truths = Memo(self._truth, size=8)

    @classmethod
    def load(cls, profile: str, data_dir: str | Path, artifacts_dir: str | Path) -> SuReNavPlayground:
        """The playground on ``profile``'s test tiles and trained estimator (first seed); a missing input stops
        with one line naming the command that builds it. Torch runs on the profile's thread count."""
        params = load_params(profile)
        s = params.surenav
        main, seed = main_run(s.demos.context, s.train), s.train.seeds[0]
        require_built([("surenav_context_demos", Path(artifacts_dir, *CONTEXT_DEMOS, "index.json")),
                       ("surenav_context_estimator", context_model_path(artifacts_dir, main, seed))],
                      params.profile, data_dir, artifacts_dir)
        torch.set_num_threads(s.train.threads)
        maps = load_maps(data_dir, "test")
        stored = {md.map_name: md for md in load_demos(data_dir, "test")}
        estimator = context_cost(artifacts_dir, main, seed)  # loads it now, or DataError
        base = baselines(params, artifacts_dir, every_reading=False)  # the benchmark's own factories (Fig. 4)
        factories: dict[str, Factory] = {SURENAV: estimator_factory(params, artifacts_dir, main, seed),
                                         **{m: base[m] for m in BASELINES}, **dict.fromkeys(EXPERTS, base[EXPERT])}
        defaults = {}
        for smap in maps:  # each tile starts on its first test demonstration's start and goal
            demo = (stored[smap.name].semi_static or stored[smap.name].static)[0]
            defaults[smap.name] = tuple(tuple(int(v) for v in smap.frame.world_to_cell(xy))
                                        for xy in (demo.start, demo.goal))
        return cls(params, maps, {name: md.superpixels for name, md in stored.items()}, defaults, factories, estimator)

    # --- what can be chosen -------------------------------------------------------------------------
    def tiles(self) -> list[str]:
        return list(self.maps)

    @property
    def smap(self) -> SemanticMap:
        return self.maps[self.tile]

    def truth(self) -> np.ndarray:
        """The tile as it is: the closed superpixels are buildings."""
        return self.truths(self.tile, self.closed)

    def cell_at(self, x: float | None, y: float | None) -> Cell:
        """The cell under a click at world (x, y) metres."""
        if x is None or y is None or not np.isfinite([x, y]).all():
            raise UserError("click inside the map")
        cell = self.smap.frame.world_to_cell(np.array([x, y], dtype=float))
        if not self.smap.frame.contains(cell):
            raise UserError(f"({x:.0f}, {y:.0f}) m is off the map; click inside the tile")
        return int(cell[0]), int(cell[1])

    def xy(self, cell: Cell) -> np.ndarray:
        return self.smap.frame.cell_to_world(np.asarray(cell))

    # --- choices ------------------------------------------------------------------------------------
    def choose_tile(self, name: str | None) -> None:
        """A test tile; start and goal become its first test demonstration's, every superpixel is open."""
        if name not in self.maps:
            raise UserError(f"choose a test tile: one of {', '.join(self.maps)} (got {name!r})")
        self.tile, (self.start, self.goal), self.closed = name, self.defaults[name], frozenset()

    def set_mode(self, mode: str) -> None:
        if mode not in MODES:
            raise UserError(f"click mode {mode!r}: one of {', '.join(MODES)}")
        self.mode = mode

    def set_costs(self, shown: bool) -> None:
        self.show_costs = bool(shown)

    def click(self, x: float | None, y: float | None) -> None:
        """A click on the map at world (x, y): sets the start or the goal, or closes / reopens the superpixel
        there, as the mode says."""
        cell = self.cell_at(x, y)
        if self.mode == "start":
            self.set_start(cell)
        elif self.mode == "goal":
            self.set_goal(cell)
        else:
            self.toggle(cell)

    def set_start(self, cell: Cell) -> None:
        self._check_ends(tuple(cell), self.goal, self.closed)
        self.start = tuple(int(v) for v in cell)

    def set_goal(self, cell: Cell) -> None:
        self._check_ends(self.start, tuple(cell), self.closed)
        self.goal = tuple(int(v) for v in cell)

    def toggle(self, cell: Cell) -> None:
        """Close the superpixel under ``cell`` (a new obstacle), or reopen it when it is closed."""
        region = int(self.superpixels[self.tile][tuple(cell)])
        if region == HARD:
            raise UserError(f"{self._where(cell)} is a {self._label(cell)} of the map: only free or soft "
                            "superpixels can be closed")
        closed = self.closed ^ {region}
        self._check_ends(self.start, self.goal, closed)
        self.closed = closed

    def reopen_all(self) -> None:
        if not self.closed:
            raise UserError("no superpixel is closed: click one in 'close / open superpixel' mode")
        self._check_ends(self.start, self.goal, frozenset())
        self.closed = frozenset()

    def set_scenario(self, tile: str | None, start=None, goal=None, closed="midway") -> None:
        """The notebook's scenario: ``tile`` (None: the first test tile), ``start`` / ``goal`` world (x, y)
        metres (None: the tile's first test demonstration's), ``closed`` a list of world points whose
        superpixels are closed, or ``"midway"``: the superpixel halfway along the cautious expert's path."""
        before = self.tile, self.start, self.goal, self.closed
        try:
            self.choose_tile(self.tiles()[0] if tile is None else tile)
            ends = [self.defaults[self.tile][k] if xy is None else self.cell_at(*_point(name, xy))
                    for k, (name, xy) in enumerate((("start", start), ("goal", goal)))]
            self._check_ends(*ends, frozenset())
            self.start, self.goal = ends
            if closed == "midway":
                cells = [self.midway()]
            else:
                points = _literal("closed", closed) or ()
                if not isinstance(points, list | tuple):
                    raise UserError(f"closed = {closed!r}: give \"midway\" or a list of (x, y) points, e.g. [[120, 80]]")
                cells = [self.cell_at(*_point("closed", xy)) for xy in points]
            for cell in cells:
                self.toggle(cell)
        except UserError:
            self.tile, self.start, self.goal, self.closed = before  # refused as a whole
            raise

    def midway(self) -> Cell:
        """The cell halfway along the cautious expert's path whose superpixel can be closed (not the start's
        or goal's, not cutting every route), searching outward from the middle."""
        cells = self.outcome().runs[EXPERTS[0]].cells
        sp = self.superpixels[self.tile]
        order = np.argsort(np.abs(np.arange(len(cells)) - len(cells) // 2), kind="stable")
        for k in order:
            cell = (int(cells[k, 0]), int(cells[k, 1]))
            region = int(sp[cell])
            if region != HARD and region not in self.closed and self._fine(self.start, self.goal, self.closed | {region}):
                return cell
        raise UserError("no superpixel on the expert's path can be closed without cutting every route")

    # --- what they give -----------------------------------------------------------------------------
    def outcome(self) -> SuReNavOutcome:
        return self.outcomes(self.tile, self.start, self.goal, self.closed)

    def costs(self) -> Costs:
        return self.costs_of(self.tile, self.start, self.goal, self.closed)

    def describe(self) -> str:
        s, g = self.xy(self.start), self.xy(self.goal)
        return (f"{self.tile}: start ({s[0]:.0f}, {s[1]:.0f}) m, goal ({g[0]:.0f}, {g[1]:.0f}) m, "
                f"{len(self.closed)} superpixel(s) closed")

    def _truth(self, tile: str, closed: frozenset[int]) -> np.ndarray:
        labels = self.maps[tile].labels.copy()
        if closed:
            labels[np.isin(self.superpixels[tile], list(closed))] = OBSTACLE
        return labels

    def _outcome(self, tile: str, start: Cell, goal: Cell, closed: frozenset[int]) -> SuReNavOutcome:
        smap, truth = self.maps[tile], self.truths(tile, closed)
        res, sp = smap.frame.resolution, self.superpixels[tile]
        walks = {}
        for method in METHODS:
            persona = EXPERTS.index(method) if method in EXPERTS else 0  # the context walker's persona
            env = Environment(f"{tile}/playground", tile, smap, truth, np.asarray(start), np.asarray(goal), persona)
            walks[method] = walk(env, lambda w, env=env, make=self.factories[method]: make(env, w),
                                 self.bench.executor, self.params.surenav.graph)
        ends = smap.frame.cell_to_world(np.array([start, goal]))
        xy = {m: smap.frame.cell_to_world(w.trajectory) for m, w in walks.items()}
        runs = {}
        for method, done in walks.items():
            relaxed = relaxed_regions(done.trajectory, truth, sp)
            frechet = {p.name: normalised_frechet(xy[method], xy[e], *ends) for p, e in zip(CONTEXT_PERSONAS, EXPERTS, strict=True)}
            runs[method] = MethodRun(done.status, done.trajectory, relaxed, path_length(done.trajectory, res),
                                     float(self.sizes[tile][relaxed].sum() * res * res),
                                     total_risk(done.trajectory, truth, self.risk, res), frechet)
        return SuReNavOutcome(tile, start, goal, closed, truth, runs)

    def _costs(self, tile: str, start: Cell, goal: Cell, closed: frozenset[int]) -> Costs:
        smap, truth = self.maps[tile], self.truths(tile, closed)
        sp = np.where(np.isin(truth, HARD_IDS), HARD, self.superpixels[tile])
        ends = smap.frame.cell_to_world(np.array([start, goal]))
        graph = build_region_graph(sp, truth, smap.frame, self.params.surenav.graph.tau_m).with_endpoints(*ends)
        nodes, psi, route = relax_on_prior(self.estimator, smap.labels, graph, *ends, self.params)
        return Costs(graph, nodes, psi, route)

    def _check_ends(self, start: Cell, goal: Cell, closed: frozenset[int]) -> None:
        """Start and goal on free or soft ground of the tile as it would be, distinct, and joined by a route."""
        truth = self.truths(self.tile, closed)
        for name, cell in (("start", start), ("goal", goal)):
            if not np.isin(truth[cell], HARD_IDS):
                continue
            if int(self.superpixels[self.tile][cell]) not in closed:
                raise UserError(f"the {name} {self._where(cell)} would be in a {self._label(cell)}: "
                                "pick free or soft ground")
            if closed != self.closed and cell == getattr(self, name):
                raise UserError(f"the {name} {self._where(cell)} lies in this superpixel: move the {name} "
                                "before closing it")
            raise UserError(f"the {name} {self._where(cell)} would be in a closed superpixel: reopen it or "
                            "pick another cell")
        if start == goal:
            raise UserError(f"start and goal are the same cell {self._where(start)}: pick another one")
        if not connected(truth, start, goal, (slice(0, truth.shape[0]), slice(0, truth.shape[1]))):
            raise UserError(f"no route from start to goal on {self.tile} with "
                            f"{'this superpixel closed' if closed != self.closed else 'these ends'}: "
                            "every way is blocked by buildings, water or closed superpixels")

    def _fine(self, start: Cell, goal: Cell, closed: frozenset[int]) -> bool:
        try:
            self._check_ends(start, goal, closed)
        except UserError:
            return False
        return True

    def _where(self, cell: Cell) -> str:
        x, y = self.xy(cell)
        return f"({x:.0f}, {y:.0f}) m"

    def _label(self, cell: Cell) -> str:
        return LABELS[int(self.smap.labels[cell])].name


def crop_box(outcome: SuReNavOutcome, shape: tuple[int, int], pad: int) -> tuple[slice, slice]:
    """A square of cells holding every path (and both ends) grown by ``pad`` cells, inside the map: square,
    so that the panels fill their grid."""
    cells = np.concatenate([np.array([outcome.start, outcome.goal]), *(r.cells for r in outcome.runs.values())])
    lo, hi = cells.min(axis=0) - pad, cells.max(axis=0) + pad + 1
    side = min(int((hi - lo).max()), *shape)
    lo = np.clip((lo + hi) // 2 - side // 2, 0, np.asarray(shape) - side)
    return slice(int(lo[0]), int(lo[0]) + side), slice(int(lo[1]), int(lo[1]) + side)


def overlay(mask: np.ndarray, rgba: tuple[float, float, float, float]) -> np.ndarray:
    out = np.zeros((*mask.shape, 4))
    out[mask] = rgba
    return out


def outcome_figure(outcome: SuReNavOutcome, smap: SemanticMap, superpixels: np.ndarray, pad_m: float = 15.0) -> Figure:
    """Every method's panel (the true map around the paths, its relaxed superpixels amber, closed ones dark
    red, its executed path), then all paths together."""
    box = crop_box(outcome, smap.labels.shape, int(np.ceil(pad_m / smap.frame.resolution)))
    view = smap.crop(*box, labels=outcome.truth)
    sp = superpixels[box]
    image, closed = colorize(view.labels), overlay(np.isin(sp, list(outcome.closed)), CLOSED_RGBA)
    ends = smap.frame.cell_to_world(np.array([outcome.start, outcome.goal]))
    fig = Figure(figsize=(13, 6.6))
    axes = fig.subplots(2, 4).ravel()
    for ax, (name, run) in zip(axes, [*outcome.runs.items(), ("all paths", None)], strict=True):
        ax.imshow(image, extent=view.frame.extent, interpolation="nearest")
        ax.imshow(closed, extent=view.frame.extent, interpolation="nearest")
        shown = outcome.runs.items() if run is None else [(name, run)]
        if run is not None:
            ax.imshow(overlay(np.isin(sp, run.relaxed) & np.isin(view.labels, SOFT_IDS), RELAXED_RGBA),
                      extent=view.frame.extent, interpolation="nearest")
            ax.set_title(f"{name}: {run.length_m:.0f} m, {len(run.relaxed)} relaxed" +
                         ("" if run.status == "reached" else f" ({run.status})"), fontsize=9)
        else:
            ax.set_title("all paths", fontsize=9)
        for method, done in shown:
            xy = smap.frame.cell_to_world(done.cells)
            ax.plot(xy[:, 0], xy[:, 1], color=COLOURS[method], linewidth=1.6 if run is not None else 1.1, label=method)
        ax.plot(*ends[0], "o", color="tab:green", markersize=7, markeredgecolor="black")
        ax.plot(*ends[1], "*", color="gold", markersize=11, markeredgecolor="black")
        ax.set_xticks([])
        ax.set_yticks([])
    axes[-1].legend(fontsize=6, loc="lower right")
    fig.subplots_adjust(left=0.01, right=0.99, bottom=0.01, top=0.95, wspace=0.03, hspace=0.12)
    return fig


def metrics_html(outcome: SuReNavOutcome) -> str:
    """Every method's metrics as a small table: status (✓: reached), path length, relaxed superpixels and area, total
    risk (Fig. 4's unit risks) and the normalised Fréchet distance to each persona's expert path (Table I)."""
    names = [p.name for p in CONTEXT_PERSONAS]
    head = ('<tr><th rowspan="2">method</th><th rowspan="2">status</th><th rowspan="2">length<br>[m]</th>'
            '<th rowspan="2">relaxed</th><th rowspan="2">relaxed<br>area [m²]</th>'
            f'<th rowspan="2">risk<br>[risk·m]</th><th colspan="{len(names)}">Fréchet to expert</th></tr>'
            "<tr>" + "".join(f"<th>{n}</th>" for n in names) + "</tr>")
    rows = "".join(
        f'<tr><td style="color:{COLOURS[m]};white-space:nowrap">{html.escape(m)}</td>'
        f"<td>{'✓' if r.status == 'reached' else r.status}</td>"
        f"<td>{r.length_m:.0f}</td><td>{len(r.relaxed)}</td><td>{r.relaxed_m2:.0f}</td><td>{r.risk:.1f}</td>"
        + "".join(f"<td>{r.frechet[n]:.2f}</td>" for n in names) + "</tr>" for m, r in outcome.runs.items())
    return f'<table style="font-size:11px;line-height:1.3">{head}{rows}</table>'


def is_widget_backend() -> bool:
    """Is pyplot drawing into ipympl canvases (``%matplotlib widget``), whose clicks reach the kernel?"""
    import matplotlib

    backend = matplotlib.get_backend().lower()
    return "ipympl" in backend or backend == "widget"


def _literal(name: str, value):
    """A notebook parameter as papermill may pass it: a string such as ``"[120, 80]"`` (``-p start ...``) read
    as the Python literal it spells; anything else as given."""
    if not isinstance(value, str):
        return value
    try:
        return ast.literal_eval(value)
    except (ValueError, SyntaxError):
        raise UserError(f"{name} = {value!r} is not a literal; give (x, y) metres, e.g. [120, 80]") from None


def _point(name: str, value) -> tuple[float, float]:
    """(x, y) metres from a notebook parameter, or a UserError naming it."""
    value = _literal(name, value)
    try:
        x, y = (float(v) for v in value)
    except (TypeError, ValueError):
        raise UserError(f"{name} = {value!r}: give (x, y) metres, e.g. [120, 80]") from None
    return x, y


class SuReNavView(PlaygroundView):
    """The widgets of the SuReNav playground: tile menu, click mode, the Psi toggle, the clickable map
    (an ipympl canvas under ``%matplotlib widget``, else a static image), every method's panel and the
    metrics table. Map clicks arrive as matplotlib ``button_press_event`` and go through :meth:`act`."""

    first_use = ("first use: numba compiles the planners (D* Lite, COA*, the graph search), about a minute in a "
                 "fresh clone and seconds once its cache is written")

    def __init__(self, playground: SuReNavPlayground):
        super().__init__()
        self.playground = p = playground
        self.tiles = widgets.Dropdown(options=p.tiles(), value=p.tile, description="tile")
        self.tiles.add_class("navlab-tile")
        self._syncing = False  # True while the code, not a person, sets a widget
        self.tiles.observe(lambda c: self._forward(p.choose_tile, c["new"]), names="value")
        self.modes = widgets.ToggleButtons(options=MODES, value=p.mode, description="click sets",
                                           style={"button_width": "auto"})
        self.modes.add_class("navlab-mode")
        self.modes.observe(lambda c: self._forward(p.set_mode, c["new"]), names="value")
        self.costs = widgets.ToggleButton(value=p.show_costs, description="show relaxation cost Ψ",
                                          layout=widgets.Layout(width="auto"),
                                          tooltip="the estimator's cost of relaxing each superpixel (bright = cheap)")
        self.costs.add_class("navlab-costs")
        self.costs.observe(lambda c: self._forward(p.set_costs, c["new"]), names="value")
        reopen = self.button("reopen all", p.reopen_all, css="navlab-reopen")
        self.figure, self.ax = self._map_figure()
        self.figure.canvas.mpl_connect("button_press_event", self._on_press)
        self.canvas = self.figure.canvas if isinstance(self.figure.canvas, widgets.DOMWidget) else widgets.Image(format="png")
        self.canvas.add_class("navlab-map")
        self.result = widgets.Image(format="jpeg")
        self.result.add_class("navlab-result")
        self.table = widgets.HTML()
        self.table.add_class("navlab-metrics")
        self._figures = Memo(lambda tile, start, goal, closed: figure_bytes(outcome_figure(
            p.outcomes(tile, start, goal, closed), p.maps[tile], p.superpixels[tile]), "jpeg"))
        self._tile_drawn: str | None = None
        self.widget = widgets.VBox([widgets.HBox([self.tiles, self.costs, reopen]), self.modes, self.message.widget,
                                    self.canvas, self.table, self.result])  # the table under the map: never clipped

    def start(self, tile: str | None = None, start=None, goal=None, closed="midway") -> None:
        """The notebook's scenario (see ``SuReNavPlayground.set_scenario``); the menu follows. A refused one
        is a ParamsError naming the parameters."""
        try:
            self.start_scenario(f"tile = {tile!r}, start = {start!r}, goal = {goal!r}, closed = {closed!r}",
                                self.playground.set_scenario, tile, start, goal, closed)
        finally:
            self._sync(self.tiles, self.playground.tile)

    def snapshot(self):
        """The scenario's panels as a PNG image output: what an executed notebook (papermill) keeps."""
        from IPython.display import Image

        p = self.playground
        return Image(figure_bytes(outcome_figure(p.outcome(), p.smap, p.superpixels[p.tile]), "png"))

    def status(self) -> str:
        p = self.playground
        lengths = ", ".join(f"{m} {r.length_m:.0f} m" for m, r in p.outcome().runs.items() if m in (SURENAV, *BASELINES))
        return (f"{p.describe()}; {lengths}{'; Ψ shown' if p.show_costs else ''}; "
                f"next click on the map sets: {p.mode}")

    def figure_fraction(self, x: float, y: float) -> tuple[float, float]:
        """Figure fraction (from the lower left) of world point (x, y): where the browser test clicks for it."""
        fx, fy = self.figure.transFigure.inverted().transform(self.ax.transData.transform((x, y)))
        return float(fx), float(fy)

    def press_at(self, x: float, y: float) -> None:
        """A mouse click on the map at world (x, y), delivered as the canvas delivers one."""
        from matplotlib.backend_bases import MouseEvent

        px, py = self.ax.transData.transform((x, y))
        self.figure.canvas.callbacks.process("button_press_event",
                                             MouseEvent("button_press_event", self.figure.canvas, px, py, button=1))

    def draw(self) -> None:
        p = self.playground
        outcome = p.outcome()
        self._sync(self.modes, p.mode)
        self._sync(self.costs, p.show_costs)
        self._draw_map(outcome)
        self.result.value = self._figures(p.tile, p.start, p.goal, p.closed)
        self.table.value = metrics_html(outcome)

    def _forward(self, action, value) -> None:
        if not self._syncing:
            self.act(action, value)

    def _sync(self, widget, value) -> None:
        if widget.value != value:
            self._syncing = True
            try:
                widget.value = value
            finally:
                self._syncing = False

    def _on_press(self, event) -> None:
        inside = event.inaxes is self.ax
        self.act(self.playground.click, event.xdata if inside else None, event.ydata if inside else None)

    def _map_figure(self):
        """The clickable map: pyplot's figure under ipympl (its canvas is the widget), else an Agg one."""
        if is_widget_backend():
            import matplotlib.pyplot as plt

            with plt.ioff():
                fig = plt.figure(figsize=(5.2, 5.2), dpi=100)
            fig.canvas.header_visible = fig.canvas.footer_visible = fig.canvas.toolbar_visible = False
            fig.canvas.resizable = False
        else:
            fig = Figure(figsize=(5.2, 5.2), dpi=100)
            figure_bytes(fig)  # attaches an Agg canvas
        ax = fig.add_axes((0.1, 0.07, 0.88, 0.88))
        ax.tick_params(labelsize=7)
        self._base = ax.imshow(np.zeros((1, 1, 3)), interpolation="nearest")
        self._edges = ax.imshow(np.zeros((1, 1, 4)), interpolation="nearest")
        self._psi = ax.imshow(np.zeros((1, 1, 4)), interpolation="nearest")
        self._psi_bar = fig.colorbar(ScalarMappable(Normalize(0.0, 1.0), "magma_r"),
                                     cax=fig.add_axes((0.9, 0.12, 0.02, 0.3)))
        self._psi_bar.set_label("Ψ (bright: cheap to relax)", fontsize=7)
        self._psi_bar.ax.tick_params(labelsize=6)
        self._lines = {m: ax.plot([], [], color=COLOURS[m], linewidth=1.2, label=m)[0] for m in METHODS}
        self._ends = [ax.plot([], [], "o", color="tab:green", markersize=8, markeredgecolor="black")[0],
                      ax.plot([], [], "*", color="gold", markersize=13, markeredgecolor="black")[0]]
        ax.legend(fontsize=6, loc="lower right")
        return fig, ax

    def _draw_map(self, outcome: SuReNavOutcome) -> None:
        p = self.playground
        frame, sp = p.smap.frame, p.superpixels[p.tile]
        if p.tile != self._tile_drawn:
            for image in (self._base, self._edges, self._psi):
                image.set_extent(frame.extent)
            self._edges.set_data(overlay(find_boundaries(sp, mode="inner") & (sp != HARD), (0.2, 0.2, 0.2, 0.25)))
            self.ax.set_xlim(*frame.extent[:2])
            self.ax.set_ylim(*frame.extent[2:])
            self._tile_drawn = p.tile
        image = colorize(outcome.truth).astype(float) / 255
        closed = np.isin(sp, list(outcome.closed))
        image[closed] = CLOSED_RGBA[:3]
        self._base.set_data(image)
        self._psi.set_visible(p.show_costs)
        self._psi_bar.ax.set_visible(p.show_costs)
        if p.show_costs:
            rgba, top = psi_overlay(p.costs())
            self._psi.set_data(rgba)
            self._psi_bar.mappable.set_norm(Normalize(0.0, top))
        for method, line in self._lines.items():
            xy = frame.cell_to_world(outcome.runs[method].cells)
            line.set_data(xy[:, 0], xy[:, 1])
        for marker, cell in zip(self._ends, (outcome.start, outcome.goal), strict=True):
            marker.set_data(*([v] for v in p.xy(cell)))
        self.ax.set_title(f"{p.tile}: click sets {p.mode}", fontsize=9)
        if isinstance(self.canvas, widgets.Image):
            self.canvas.value = figure_bytes(self.figure, "png", dpi=100)
        else:
            self.figure.canvas.draw_idle()


def psi_overlay(costs: Costs) -> tuple[np.ndarray, float]:
    """(RGBA raster of Psi on the window's soft superpixels, the Psi its colour scale ends at): ``magma_r``,
    bright = cheap to relax, as Fig. 6."""
    graph = costs.graph
    soft = np.isin(graph.node_label[costs.nodes], SOFT_IDS)
    value = np.full(graph.num_nodes, np.nan)
    value[costs.nodes[soft]] = costs.psi[soft]
    raster = np.where(graph.node_raster >= 0, value[np.maximum(graph.node_raster, 0)], np.nan)
    top = float(np.nanmax(value)) if soft.any() else 1.0
    top = max(top, 1e-9)
    rgba = colormaps["magma_r"](Normalize(0.0, top)(np.nan_to_num(raster)))
    rgba[..., 3] = np.where(np.isnan(raster), 0.0, 0.85)
    return rgba, top
