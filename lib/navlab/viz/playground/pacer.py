"""The PACER playground (issue 28, item 2): "what costmap does PACER give if I prefer gravel to grass?"

A person picks one of the rendered aerial maps of notebook 02 (seen or unseen group), writes a
preference context as pairs "A over B" by clicking terrain thumbnails (reorders, removes, inverts
them, or leaves the context uninformative) and sees, for PACER, STERLING-style and the window oracle,
the costmap, the A* path from the map's start to its goal and the path's low / medium / high tier
shares. Everything is computed by the functions notebook 02 uses (``navlab.pacer.experiments``'
methods, ``plan_on_costmap``, ``cost_tier_proportions``); this module only keeps the choices, checks
them, and caches what they give.

How a person's pairs become the three methods' input:

- the context: each pair's two patches are drawn by ``pair_context`` exactly as the datasets draw
  them, seeded by the pair, so a pair always shows the same patches; the trained network reads
  ``pacer.data.n_pairs`` pairs, so fewer pairs are repeated in turn (as ``preference_pairs`` repeats
  when an ordering has too few). No pair at all is the uninformative context of notebook 02 (patches of
  the other terrain group only, ``map_context(..., informative=False)``).
- the tiers and the window oracle: the map's terrains ordered as the pairs say (transitively, also
  through terrains not on the map), and where the pairs leave a choice, by the realistic ordering
  (:func:`ordering_from_pairs`). So no pair scores by the realistic ordering, as notebook 02 does, and
  a chain of pairs over every terrain of the map, inverted, reverses it.
"""

from __future__ import annotations

import html
from collections import defaultdict
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import ipywidgets as widgets
import numpy as np
import torch
from matplotlib.figure import Figure
from torch.nn import functional as F

from navlab.core.params import Params, load_params
from navlab.core.seeding import rng
from navlab.maps.dataset import load_maps
from navlab.metrics.cost_tiers import TIER_NAMES, cost_tier_proportions
from navlab.pacer.aerial import AerialMap, aerial_map
from navlab.pacer.artifacts import phase_dir
from navlab.pacer.baselines.sterling import SterlingEncoder, load_sterling
from navlab.pacer.bev import fov_mask
from navlab.pacer.context import context_patch, pair_context
from navlab.pacer.evaluate import plan_on_costmap, stitch_windows
from navlab.pacer.experiments import map_context, sterling_method, window_oracle_method
from navlab.pacer.preferences import environment_tiers
from navlab.pacer.terrain import TerrainBank, load_terrain_bank
from navlab.pacer.train import PHASES, load_model
from navlab.viz.pacer import context_strip, show_costmap, show_paths
from navlab.viz.playground.common import (
    Memo,
    PlaygroundView,
    UserError,
    array_png,
    figure_bytes,
    require_built,
)

GROUPS = ("seen", "unseen")
COLOURS = {"PACER": "tab:blue", "STERLING-style": "tab:orange", "Window oracle": "tab:green"}
CONTEXT_WORDS = ("operator", "inverted", "uninformative")
Pair = tuple[int, int]


def find_cycle(pairs: Iterable[Pair], preferred: int, other: int) -> list[int] | None:
    """The terrains ``preferred > other > ... > preferred`` if adding that pair to ``pairs`` closes a
    cycle (then no ordering agrees with the context), else None."""
    after = defaultdict(list)
    for a, b in pairs:
        after[a].append(b)
    stack, seen = [[other]], set()
    while stack:
        path = stack.pop()
        if path[-1] == preferred:
            return [preferred, *path]
        if path[-1] not in seen:
            seen.add(path[-1])
            stack += [[*path, nxt] for nxt in after[path[-1]]]
    return None


def ordering_from_pairs(terrains: Sequence[int], pairs: Iterable[Pair], rank: np.ndarray) -> np.ndarray:
    """``terrains`` most preferred first: as ``pairs`` say (also through terrains not in ``terrains``:
    a > x > b orders a before b), and where they leave a choice, by ``rank`` (lower first; the bank's
    realistic rank). Greedy topological order: at each step the best-ranked terrain nothing still
    outranks."""
    pairs = [(int(a), int(b)) for a, b in pairs]
    before: dict[int, set[int]] = {int(t): set() for t in terrains}
    for a, b in pairs:
        before.setdefault(a, set())
        before.setdefault(b, set()).add(a)
    order = []
    while before:
        free = [t for t, above in before.items() if not above]
        if not free:
            raise UserError("the pairs contradict each other: no ordering agrees with them")
        best = min(free, key=lambda t: (int(rank[t]), t))
        order.append(best)
        del before[best]
        for above in before.values():
            above.discard(best)
    keep = {int(t) for t in terrains}
    return np.asarray([t for t in order if t in keep], dtype=np.int64)


@torch.no_grad()
def pacer_costmap(model: torch.nn.Module, image: np.ndarray, context: np.ndarray, fov_mask: np.ndarray) -> np.ndarray:
    """The costmap ``costmap_over_map`` gives (its windows, masks and stitching), less the network runs on
    windows whose field of view lies wholly in the reflect padding around the map: they add nothing to
    the map's own pixels, and on a 256-px map they are a third of all windows: skipping them is part of
    what brings a redraw under a second on two cores. Windows go in channels-last (``PacerPlayground.load``).
    ``tests/test_playground_pacer.py`` checks both agree."""
    model.eval()
    window = fov_mask.shape[0]
    size = image.shape[1:]
    padded = F.pad(torch.as_tensor(image, dtype=torch.float32)[None], (window,) * 4, mode="reflect")[0]
    weight = torch.as_tensor(fov_mask, dtype=torch.float32)
    ctx = torch.as_tensor(context, dtype=torch.float32)[None]

    def live(r: int, c: int) -> bool:
        inner = np.zeros((window, window), dtype=bool)
        inner[max(0, window - r):size[0] + window - r, max(0, window - c):size[1] + window - c] = True
        return bool((inner & fov_mask).any())

    def costs(corners):
        out = torch.zeros(len(corners), window, window)
        keep = [k for k, (r, c) in enumerate(corners) if live(r, c)]
        if keep:
            windows = torch.stack([padded[:, r:r + window, c:c + window] * weight for r, c in
                                   (corners[k] for k in keep)]).contiguous(memory_format=torch.channels_last)
            out[keep] = torch.sigmoid(model(windows, ctx.expand(len(keep), -1, -1, -1)))
        return out

    return stitch_windows(costs, tuple(size), fov_mask).numpy()


@dataclass(frozen=True, eq=False)
class PacerOutcome:
    """What one (map, context) gives: the context the network read, the ordering the tiers come from,
    and per method its costmap, A* path (None: unreachable) and tier shares {"low", "medium", "high"}."""

    amap: AerialMap
    context: np.ndarray
    ordering: np.ndarray
    costmaps: dict[str, np.ndarray]
    paths: dict[str, np.ndarray | None]
    shares: dict[str, dict[str, float]]


class PacerPlayground:
    """The playground's state and rules, without widgets: the chosen map, the context pairs, a pending
    thumbnail pick, and outcomes cached per (map, pairs). Every mutator checks its input first and
    raises :class:`UserError` (one line) without changing anything when it is refused."""

    def __init__(self, params: Params, data_dir: str | Path, bank: TerrainBank, model: torch.nn.Module,
                 encoder: SterlingEncoder):
        self.params, self.data, self.bank = params, params.pacer.data, bank
        self.semantic_maps = load_maps(data_dir, "test") if self.data.aerial.layout == "surenav" else ()
        pacer = params.pacer
        mask = fov_mask(self.data.image_size, self.data.camera.near_width)
        self.methods = {"PACER": lambda amap, ordering, context, pairs: pacer_costmap(model, amap.image, context, mask),
                        "STERLING-style": sterling_method(encoder, pacer.baselines.sterling.utility_steps),
                        "Window oracle": window_oracle_method(self.data)}
        self.choice: tuple[str, int] | None = None
        self.pairs: tuple[Pair, ...] = ()
        self.pending: int | None = None
        self.maps = Memo(lambda group, index: aerial_map(bank, self.data, group, index, pacer.seed,
                                                         self.semantic_maps), size=64)
        self.outcomes = Memo(self._outcome)

    @classmethod
    def load(cls, profile: str, data_dir: str | Path, artifacts_dir: str | Path) -> PacerPlayground:
        """The playground on ``profile``'s trained phase-3 model and STERLING encoder; a missing one stops
        with one line naming the command that builds it. It runs on the CPU (its 1 s budget is the 2-core
        machine's) at the profile's torch thread count, as the PACER notebooks do."""
        params = load_params(profile)
        require_built([*((f"pacer_{phase}", phase_dir(artifacts_dir, phase) / "model.pt") for phase in PHASES),
                       ("pacer_sterling", phase_dir(artifacts_dir, "sterling") / "encoder.pt")],
                      params.profile, data_dir, artifacts_dir)
        torch.set_num_threads(params.pacer.train.threads)
        artifacts = Path(artifacts_dir) / "pacer"
        # channels-last weights: oneDNN's convolutions then run in 60 % of the CPU time (costs equal to ~1e-5)
        model = load_model(artifacts / "phase3" / "model.pt").to(
            memory_format=torch.channels_last)
        encoder = load_sterling(artifacts / "sterling" / "encoder.pt")
        return cls(params, data_dir, load_terrain_bank(data_dir, params.pacer.data), model, encoder)

    # --- what can be chosen -------------------------------------------------------------------------
    def map_options(self) -> list[str]:
        return [f"{group} {k}" for group in GROUPS for k in range(self.data.aerial.maps)]

    @property
    def amap(self) -> AerialMap:
        return self.maps(*self._chosen())

    def candidates(self) -> np.ndarray:
        """The terrains a pair may name: those of the chosen map's group (seen or unseen)."""
        return self.bank.ids(self._chosen()[0])

    def name(self, terrain: int) -> str:
        return self.bank.terrains[int(terrain)].name

    def thumbnail(self, terrain: int, size: int = 56) -> np.ndarray:
        """(size, size, 3): a patch of the terrain's context photographs, the part contexts come from."""
        return context_patch(self.bank, int(terrain), rng(self.params.pacer.seed, "playground.thumbnail", int(terrain)),
                             size, 2.0)

    # --- choices ------------------------------------------------------------------------------------
    def choose_map(self, choice: str | None) -> None:
        """``"seen k"`` or ``"unseen k"``. The pairs stay when the group does (to compare maps under one
        preference); another group's terrains cannot be named, so there the context starts uninformative."""
        words = str(choice or "").split()
        maps = self.data.aerial.maps
        if len(words) != 2 or words[0] not in GROUPS or not words[1].isdigit() or int(words[1]) >= maps:
            raise UserError(f"choose a map: 'seen k' or 'unseen k' with k in 0..{maps - 1} (got {choice!r})")
        group = words[0]
        if self.choice is None or self.choice[0] != group:
            self.pairs = ()
        self.choice, self.pending = (group, int(words[1])), None

    def pick(self, terrain: int) -> None:
        """A thumbnail click: the first names the preferred terrain, the second the other one and adds
        the pair (a refused pair clears the pick, so the next click starts a new pair)."""
        self._check_terrain(terrain)
        if self.pending is None:
            self.pending = int(terrain)
            return
        preferred, self.pending = self.pending, None
        self.add_pair(preferred, terrain)

    def add_pair(self, preferred: int, other: int) -> None:
        self.pairs = self._checked([*self.pairs, (int(preferred), int(other))])

    def remove_pair(self, k: int) -> None:
        self._check_index(k)
        self.pairs = self.pairs[:k] + self.pairs[k + 1:]

    def move_pair(self, k: int, step: int) -> None:
        """Reorder: pair ``k`` moves ``step`` places (the network reads the pairs in order)."""
        self._check_index(k)
        pairs = list(self.pairs)
        pairs.insert(min(max(k + step, 0), len(pairs) - 1), pairs.pop(k))
        self.pairs = tuple(pairs)

    def invert(self) -> None:
        if not self.pairs:
            raise UserError("nothing to invert: the context is uninformative; add a pair first")
        self.pairs = tuple((b, a) for a, b in self.pairs)

    def clear(self) -> None:
        """The uninformative context: no pair about this map's group."""
        self.pairs, self.pending = (), None

    def use_operator(self) -> None:
        """The pairs notebook 02 gives PACER on this map (realistic preference, every terrain named)."""
        index = self._chosen()[1]
        _, _, pairs = map_context(self.bank, self.data, self.amap, "realistic", True, self.params.pacer.seed, index)
        self.pairs, self.pending = tuple(dict.fromkeys((int(a), int(b)) for a, b in pairs)), None

    def set_context(self, text: str) -> None:
        """``operator``, ``inverted`` (the operator's pairs inverted), ``uninformative``, or pairs written
        ``"grass > gravel, pavers > grass"`` (terrain names, preferred first): the notebook's scenario."""
        word = str(text).strip()
        if word in ("operator", "inverted"):
            self.use_operator()
            if word == "inverted":
                self.invert()
        elif word in ("uninformative", ""):
            self.clear()
        else:
            self.pairs, self.pending = self._checked(self._parse(word)), None

    # --- what they give -----------------------------------------------------------------------------
    def context(self) -> np.ndarray:
        return self.outcome().context

    def outcome(self) -> PacerOutcome:
        return self.outcomes(*self._chosen(), self.pairs)

    def describe(self) -> str:
        """The context in words: its pairs, or what the uninformative context is made of."""
        if not self.pairs:
            other = GROUPS[1 - GROUPS.index(self._chosen()[0])]
            return f"uninformative (patches of {other} terrains only)"
        return ", ".join(f"{self.name(a)} over {self.name(b)}" for a, b in self.pairs)

    def _outcome(self, group: str, index: int, pairs: tuple[Pair, ...]) -> PacerOutcome:
        amap = self.maps(group, index)
        context = self._context(group, index, pairs)
        ordering = ordering_from_pairs(amap.terrains, pairs, self.bank.realistic_rank)
        tiers = environment_tiers(ordering, len(self.bank))
        costmaps, paths, shares = {}, {}, {}
        for name, method in self.methods.items():
            costmaps[name] = np.asarray(method(amap, ordering, context, np.asarray(pairs).reshape(-1, 2)))
            path = plan_on_costmap(costmaps[name], amap.start, amap.goal, self.params.pacer.evaluation.cost_scale)
            paths[name] = path.cells
            shares[name] = (cost_tier_proportions(path.cells, amap.labels, tiers) if path.cells is not None
                            else dict.fromkeys(TIER_NAMES, float("nan")))
        return PacerOutcome(amap, context, ordering, costmaps, paths, shares)

    def _context(self, group: str, index: int, pairs: tuple[Pair, ...]) -> np.ndarray:
        seed = self.params.pacer.seed
        if not pairs:
            return map_context(self.bank, self.data, self.maps(group, index), "realistic", False, seed, index)[1]
        drawn = [pair_context(self.bank, np.asarray([pair]), rng(seed, "playground.pair", *pair), self.data)
                 for pair in pairs]
        return np.concatenate([drawn[k % len(drawn)] for k in range(self.data.n_pairs)])

    def _checked(self, pairs: Sequence[Pair]) -> tuple[Pair, ...]:
        """``pairs`` if the network can read them and some ordering agrees with them, else one UserError."""
        if len(pairs) > self.data.n_pairs:
            raise UserError(f"the network reads {self.data.n_pairs} pairs: remove one (✕) before adding another")
        kept: list[Pair] = []
        for a, b in pairs:
            self._check_terrain(a)
            self._check_terrain(b)
            if a == b:
                raise UserError(f"'{self.name(a)} over {self.name(a)}' names one terrain twice; "
                                "a pair compares two different terrains")
            if (a, b) in kept:
                raise UserError(f"'{self.name(a)} over {self.name(b)}' is already in the context")
            cycle = find_cycle(kept, a, b)
            if cycle:
                raise UserError(f"'{self.name(a)} over {self.name(b)}' closes the cycle "
                                f"{' > '.join(map(self.name, cycle))}: no ordering agrees; invert or remove a pair")
            kept.append((a, b))
        return tuple(kept)

    def _parse(self, text: str) -> list[Pair]:
        pairs = []
        for item in text.split(","):
            names = [n.strip() for n in item.replace(" over ", ">").split(">")]
            if len(names) != 2 or not all(names):
                raise UserError(f"context {text!r}: write pairs as 'A > B, C > D' or one of {', '.join(CONTEXT_WORDS)}")
            pairs.append(tuple(self._terrain_id(n) for n in names))
        return pairs

    def _terrain_id(self, name: str) -> int:
        known = {self.name(t): int(t) for t in self.candidates()}
        if name not in known:
            raise UserError(f"terrain {name!r} is not a {self._chosen()[0]} terrain; choose from {', '.join(known)}")
        return known[name]

    def _chosen(self) -> tuple[str, int]:
        if self.choice is None:
            raise UserError("choose a map first (seen or unseen)")
        return self.choice

    def _check_terrain(self, terrain: int) -> None:
        if int(terrain) not in set(self.candidates().tolist()):
            raise UserError(f"terrain {terrain} is not a {self._chosen()[0]} terrain of this map's group")

    def _check_index(self, k: int) -> None:
        if not 0 <= k < len(self.pairs):
            raise UserError(f"there is no pair {k + 1}: the context has {len(self.pairs)}")


def outcome_figure(outcome: PacerOutcome, title: str) -> Figure:
    """The map with every method's path, then each method's costmap (dark = cheap) with its path."""
    fig = Figure(figsize=(13, 3.6))
    axes = fig.subplots(1, 1 + len(outcome.costmaps))
    amap = outcome.amap
    show_paths(axes[0], amap.image, [(outcome.paths[m], COLOURS[m], m) for m in outcome.costmaps],
               amap.start, amap.goal, title)
    for ax, (name, costmap) in zip(axes[1:], outcome.costmaps.items()):
        image = show_costmap(ax, costmap, f"{name} costmap", [(outcome.paths[name], COLOURS[name])])
    fig.subplots_adjust(left=0.01, right=0.95, bottom=0.02, top=0.92, wspace=0.04)  # tight_layout: +60 ms
    bar = fig.colorbar(image, cax=fig.add_axes((0.955, 0.1, 0.01, 0.75)))
    bar.set_label("cost (0 cheap, 1 avoided)", fontsize=8)
    bar.ax.tick_params(labelsize=7)
    return fig


def shares_html(outcome: PacerOutcome, name) -> str:
    """Each method's tier shares as a small table, under the ordering the tiers come from."""
    tiers = environment_tiers(outcome.ordering, int(outcome.ordering.max()) + 1)
    groups = {t: [name(x) for x in outcome.ordering if tiers[x] == k] for k, t in enumerate(TIER_NAMES)}
    head = "".join(f"<th>{t}</th>" for t in TIER_NAMES)
    rows = "".join(f"<tr><td>{m}</td>" + "".join(f"<td>{s[t]:.0%}</td>" for t in TIER_NAMES) + "</tr>"
                   for m, s in outcome.shares.items())
    order = " · ".join(f"{t}: {html.escape(', '.join(g))}" for t, g in groups.items() if g)
    return (f"<div>tiers (your pairs, the realistic ordering where they are silent): {order}</div>"
            f"<table><tr><th>path share on</th>{head}</tr>{rows}</table>")


class PacerView(PlaygroundView):
    """The widgets of the PACER playground: map menu, terrain thumbnails, the context's pairs with their
    buttons, what the network reads, and the result (figure and tier shares)."""

    def __init__(self, playground: PacerPlayground, map_choice: str | None = None, context: str = "operator"):
        super().__init__()
        self.playground = playground
        self.maps = widgets.Dropdown(options=[("choose a map", ""), *[(o, o) for o in playground.map_options()]],
                                     description="map")
        self.maps.add_class("navlab-map")
        self._syncing = False  # True while the code, not a person, sets the menu
        self.maps.observe(self._on_map, names="value")
        self.gallery, self.pair_rows = widgets.HBox(), widgets.VBox()
        self.strip, self.result = widgets.Image(format="png"), widgets.Image(format="jpeg")
        self.result.add_class("navlab-result")
        self.shares = widgets.HTML()
        self.shares.add_class("navlab-shares")
        self._gallery_group: str | None = None
        self._thumbs = Memo(lambda terrain, size: array_png(playground.thumbnail(terrain, size)), size=64)
        self._figures = Memo(lambda group, index, pairs: figure_bytes(outcome_figure(
            playground.outcomes(group, index, pairs), f"{group} map {index}"), "jpeg"))
        actions = widgets.HBox([self.button("invert", playground.invert, css="navlab-invert"),
                                self.button("uninformative", playground.clear, css="navlab-clear"),
                                self.button("operator's pairs", playground.use_operator, css="navlab-operator")])
        self.widget = widgets.VBox([self.maps, widgets.HTML("<b>terrains</b>: click the preferred one, then the "
                                                            "other, to add a pair"),
                                    self.gallery, actions, self.pair_rows,
                                    widgets.HBox([widgets.HTML("the network reads:"), self.strip]),
                                    self.message.widget, self.result, self.shares])
        if map_choice is not None:
            self.start(map_choice, context)

    def snapshot(self):
        """The current result as a PNG image output: what an executed notebook (papermill) keeps of the
        scenario, where no widget is live."""
        from IPython.display import Image

        p = self.playground
        return Image(figure_bytes(outcome_figure(p.outcome(), f"{p.choice[0]} map {p.choice[1]}"), "png"))

    def start(self, map_choice: str, context: str) -> None:
        """The notebook's scenario: the map (the menu shows it too), then the context; a refused one is a
        ParamsError naming the parameter."""
        if map_choice in self.playground.map_options():
            self._syncing = True
            try:
                self.maps.value = map_choice
            finally:
                self._syncing = False
        self.start_scenario(f"map_choice = {map_choice!r}", self.playground.choose_map, map_choice)
        self.start_scenario(f"context = {context!r}", self.playground.set_context, context)

    def _on_map(self, change) -> None:
        if not self._syncing:
            dropped = self.playground.pairs
            if self.act(self.playground.choose_map, change["new"]) and dropped and not self.playground.pairs:
                self.message.show(f"{self.message.text}; your {len(dropped)} pair(s) named the other group's "
                                  "terrains and were cleared")

    def act(self, action, *args) -> bool:
        """As every view's, and a refused pair leaves no terrain highlighted as if still picked (the refusal
        cleared the pick)."""
        done = super().act(action, *args)
        if not done and self.playground.choice is not None:
            self._draw_gallery()
        return done

    def status(self) -> str:
        p = self.playground
        low = " / ".join(f"{m} {s['low']:.0%}" for m, s in p.outcome().shares.items())
        pick = f"; {p.name(p.pending)} over …? click the other terrain" if p.pending is not None else ""
        return f"{' '.join(map(str, p.choice))}: {p.describe()}; low-tier share {low}{pick}"

    def draw(self) -> None:
        p = self.playground
        outcome = p.outcome()
        self._draw_gallery()
        self.pair_rows.children = [self._pair_row(k, a, b) for k, (a, b) in enumerate(p.pairs)]
        self.strip.value = array_png(context_strip(outcome.context), scale=3)
        self.result.value = self._figures(*p.choice, p.pairs)
        self.shares.value = shares_html(outcome, p.name)

    def _draw_gallery(self) -> None:
        p = self.playground
        group = p.choice[0]
        if group != self._gallery_group:
            self.gallery.children = [self._thumb_card(t) for t in p.candidates()]
            self._gallery_group = group
        on_map = set(p.amap.terrains.tolist())
        for card, terrain in zip(self.gallery.children, p.candidates()):
            button = card.children[1]
            button.button_style = "warning" if terrain == p.pending else ("info" if terrain in on_map else "")
            button.tooltip = "on this map" if terrain in on_map else "not on this map"

    def _thumb_card(self, terrain: int) -> widgets.VBox:
        image = widgets.Image(value=self._thumbs(int(terrain), 56), format="png", layout=widgets.Layout(width="56px"))
        name = self.playground.name(terrain)  # wide enough for the whole name ("mono_gravel", not "mono_…")
        return widgets.VBox([image, self.button(name, self.playground.pick, int(terrain), css="navlab-terrain",
                                                width=f"{max(80, 8 * len(name) + 24)}px")])

    def _pair_row(self, k: int, a: int, b: int) -> widgets.HBox:
        p = self.playground

        def thumb(t):
            return widgets.Image(value=self._thumbs(int(t), 56), format="png", layout=widgets.Layout(width="32px"))

        return widgets.HBox([widgets.HTML(f"{k + 1}."), thumb(a), widgets.HTML("over"), thumb(b),
                             widgets.HTML(f"{p.name(a)} over {p.name(b)}", layout=widgets.Layout(width="220px")),
                             self.button("↑", p.move_pair, k, -1, tooltip="earlier"),
                             self.button("↓", p.move_pair, k, 1, tooltip="later"),
                             self.button("✕", p.remove_pair, k, css="navlab-remove", tooltip="remove")])
