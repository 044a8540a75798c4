"""The two properties that make the context demonstrator a benchmark for SuReNav's claim (issue 25).

Every method walks Table I's executor (``benchmark.run_episode``: ``surenav.semi_static.execute`` in the
episode window, relaxation IoU on the demonstration's superpixels) on the context environments:

- *context share*: the Expert (the demonstrator's own planner, true persona) minus the best
  per-label cost field, in relaxation IoU: what no per-label per-metre cost explains;
- *region-expressible*: ``SuReNavPolicy`` with the *rule Psi* (the rules at the personas' mean
  tolerances, read from the believed map alone, no demonstration) minus the best per-label field:
  how much of that context a per-superpixel Psi can carry.

Differences are paired over environments with a 95% percentile bootstrap. The per-label fields are
non-learned: the rules' per-metre surface costs; the rules' Psi of each label averaged over the
personas and every region of that label on the TRAINING tiles, spread over the region's diameter; and
the per-label demonstrator's personas' mean costs (issue 25's 0.541 field). The best of them is chosen
on validation demonstrations (``select_field``), never on the test environments the properties are
measured on: choosing on the test set would pick the field that happens to fit it, and overstate the
field (understating both properties).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from navlab.core.labels import LABELS, SOFT_IDS
from navlab.core.params.surenav_benchmark import BenchmarkParams
from navlab.core.params.surenav_demos import ContextDemosParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.core.seeding import rng
from navlab.maps.semantic_map import SemanticMap
from navlab.metrics.intervals import bootstrap_mean_ci
from navlab.metrics.navigation import risk_table
from navlab.surenav.baselines.cost_field import CostFieldPolicy
from navlab.surenav.benchmark import Outcome, reference_superpixels, run_episode
from navlab.surenav.context.personas import CONTEXT_PERSONAS, mean_persona
from navlab.surenav.context.regions import region_context
from navlab.surenav.context.rules import SURFACE_TABLE, relaxation_costs
from navlab.surenav.context.walker import ContextWalker, RuleCost
from navlab.surenav.episodes import Environment
from navlab.surenav.experts.personas import PERSONAS
from navlab.surenav.experts.store import MapDemos
from navlab.surenav.policy import SuReNavPolicy
from navlab.surenav.semi_static import Policy
from navlab.surenav.windows import PlanningWindow, prior_hard

EXPERT = "Expert (context demonstrator's planner)"
RULE_PSI = "SuReNav executor, rule Psi"
FIELD = "per-label field: "


def per_label_fields(maps: dict[str, tuple[np.ndarray, np.ndarray, float]]) -> dict[str, np.ndarray]:
    """Per-label cost per metre of each non-learned field; ``maps``: name -> (labels, superpixels,
    resolution) of the training maps (for the rules' mean Psi per label)."""
    spread = np.zeros(len(LABELS))
    count = np.zeros(len(LABELS))
    for labels, superpixels, res in maps.values():
        ids, regions = np.unique(superpixels, return_inverse=True)
        regions = regions.reshape(superpixels.shape) - (ids[0] < 0)
        ctx = region_context(labels, regions, len(ids) - (ids[0] < 0), res)
        for persona in CONTEXT_PERSONAS:
            per_metre = relaxation_costs(ctx, persona) / np.sqrt(ctx.area_m2)
            spread += np.bincount(ctx.label, per_metre, minlength=len(LABELS))
            count += np.bincount(ctx.label, minlength=len(LABELS))
    rules_mean = SURFACE_TABLE.copy()
    rules_mean[SOFT_IDS] = 1.0 + spread[SOFT_IDS] / np.maximum(count[SOFT_IDS], 1)
    mean = {name: float(np.mean([getattr(p, name) for p in PERSONAS]))
            for name in ("road_cost", "living_street_cost", "parking_cost", "rough_cost", "grass_edge_cost")}
    old = {"sidewalk": 1.0, "crosswalk": 1.0, "road": mean["road_cost"], "living_street": mean["living_street_cost"],
           "parking": mean["parking_cost"], "grass": mean["grass_edge_cost"], "rough_terrain": mean["rough_cost"]}
    return {"the rules' surface costs": SURFACE_TABLE, "the rules' mean Psi per metre": rules_mean,
            "the per-label demonstrator's personas' mean costs": np.array([old.get(lab.name, np.inf) for lab in LABELS])}


def demo_environments(pairs: list[tuple[SemanticMap, MapDemos]]) -> tuple[list[Environment], dict[str, np.ndarray]]:
    """Environments (one per semi-static demonstration) of any split's (tile, demonstrations), as
    ``dataset.stored_environments`` builds the test ones, and each tile's stored superpixels."""
    envs, stored = [], {}
    for smap, md in pairs:
        stored[smap.name] = md.superpixels
        envs += [Environment(f"{smap.name}/{i}", smap.name, smap, demo.labels_on(smap.labels),
                             smap.frame.world_to_cell(demo.start), smap.frame.world_to_cell(demo.goal), demo.persona,
                             demo) for i, demo in enumerate(md.semi_static)]
    return envs, stored


@dataclass(frozen=True)
class FieldChoice:
    name: str  # the chosen field (a key of ``costs``)
    costs: dict[str, np.ndarray]  # every candidate field: cost per metre per label id
    val_iou: dict[str, float]  # each candidate's mean relaxation IoU on the validation demonstrations

    @property
    def table(self) -> np.ndarray:
        return self.costs[self.name]

    def note(self) -> str:
        scores = "; ".join(f"{name} {iou:.3f}" for name, iou in self.val_iou.items())
        return (f"Best per-label field: {self.name}, the highest mean relaxation IoU on the validation "
                f"demonstrations (never the test ones) among the non-learned fields ({scores}).")


def select_field(train: list[tuple[SemanticMap, MapDemos]], val: list[tuple[SemanticMap, MapDemos]],
                 settings: BenchmarkParams, graph: GraphParams) -> FieldChoice:
    """The best per-label field: candidates from the training tiles (``per_label_fields``), each run through
    Table I's executor on the validation demonstrations, the highest mean IoU chosen (ties: the first)."""
    for split, pairs in (("train", train), ("val", val)):
        wrong = sorted({md.split for _, md in pairs} - {split})
        if wrong or not pairs:
            raise ValueError(f"select_field: the {split} argument must hold {split} demonstrations only, got splits "
                             f"{wrong or 'none'}; the best field is never chosen on the test set")
    fields = per_label_fields({smap.name: (smap.labels, md.superpixels, smap.frame.resolution) for smap, md in train})
    envs, stored = demo_environments(val)
    scores = {}
    for name, table in fields.items():
        found = run_method(envs, stored, lambda env, w, t=table: CostFieldPolicy(t), settings, graph)
        scores[name] = round(float(np.mean([o.relaxation_iou for o in found])), 4)
    return FieldChoice(max(scores, key=scores.get), fields, scores)


def run_method(envs: list[Environment], stored: dict[str, np.ndarray],
               policy: Callable[[Environment, PlanningWindow], Policy], settings: BenchmarkParams,
               graph: GraphParams) -> list[Outcome]:
    """One method (a fresh policy per environment and planning window) on every environment, through Table
    I's executor."""
    risk = risk_table(settings.unit_risk)
    return [run_episode(env, "", lambda w, env=env: policy(env, w), settings, graph, risk,
                        reference_superpixels(env, graph, stored[env.group]))
            for env in envs]


def _row(method: str, outcomes: list[Outcome], settings: BenchmarkParams) -> dict:
    row = {"method": method, "sr": float(np.mean([o.success for o in outcomes]))}
    for col in ("frechet", "relaxation_iou"):
        values = np.array([getattr(o, col) for o in outcomes])
        lo, hi = bootstrap_mean_ci(values, rng(settings.seed, "context", method, col), settings.bootstrap_samples)
        row[col], row[f"{col}_ci"] = float(values.mean()), [round(lo, 4), round(hi, 4)]
    return row


def _paired(a: list[Outcome], b: list[Outcome], threshold: float, settings: BenchmarkParams, key: str) -> dict:
    diff = np.array([x.relaxation_iou - y.relaxation_iou for x, y in zip(a, b, strict=True)])
    lo, hi = bootstrap_mean_ci(diff, rng(settings.seed, "context", key), settings.bootstrap_samples)
    return {"delta_iou": float(diff.mean()), "delta_iou_ci": [round(lo, 4), round(hi, 4)], "at_least": threshold,
            "holds": bool(diff.mean() >= threshold)}


def measure(envs: list[Environment], stored: dict[str, np.ndarray], field: FieldChoice, settings: BenchmarkParams,
            graph: GraphParams, context: ContextDemosParams, planner_mode: str, margin_m: float) -> dict:
    """Rows (Fréchet, IoU, SR with 95% intervals) of the Expert, every per-label field and the rule-Psi
    SuReNav, and the two properties against ``field``'s choice (made on validation demonstrations), paired."""
    fields = field.costs
    runs = {EXPERT: lambda env, w: ContextWalker(CONTEXT_PERSONAS[env.persona], margin_m * w.scale,
                                                 prior_hard(env, w)),
            RULE_PSI: lambda env, w: SuReNavPolicy(RuleCost(mean_persona(), prior_hard(env, w)), planner_mode,
                                                   margin_m * w.scale),
            **{FIELD + name: (lambda env, w, t=table: CostFieldPolicy(t)) for name, table in fields.items()}}
    outcomes = {name: run_method(envs, stored, make, settings, graph) for name, make in runs.items()}
    rows = [_row(name, found, settings) for name, found in outcomes.items()]
    best = FIELD + field.name
    return {"environments": len(envs), "rows": rows, "best_field": best, "field_val_iou": field.val_iou,
            "field_costs": {name: [round(float(c), 3) for c in t] for name, t in fields.items()},
            "context_share": _paired(outcomes[EXPERT], outcomes[best], context.min_context_share, settings, "share"),
            "region_expressible": _paired(outcomes[RULE_PSI], outcomes[best], context.min_region_gain, settings,
                                          "region")}
