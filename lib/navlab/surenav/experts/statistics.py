"""Dataset statistics of the SuReNav benchmark: what the maps are made of and what the expert relaxes."""

from __future__ import annotations

import numpy as np

from navlab.core.labels import LABELS, NUM_LABELS, SOFT_IDS
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.experts.store import KINDS, MapDemos


def label_fractions(maps: list[SemanticMap]) -> dict[str, float]:
    """Share of all cells of ``maps`` carrying each label."""
    counts = sum(np.bincount(m.labels.ravel(), minlength=NUM_LABELS) for m in maps)
    return {lab.name: float(counts[lab.id] / max(counts.sum(), 1)) for lab in LABELS}


def relaxations_per_label(map_demos: list[MapDemos], maps: list[SemanticMap]) -> dict[str, dict[str, int]]:
    """Per kind (static / semi_static): how many demonstrations relax each soft label at least once."""
    by_name = {m.name: m for m in maps}
    out = {kind: {LABELS[i].name: 0 for i in SOFT_IDS} for kind in KINDS}
    for md in map_demos:
        labels = by_name[md.map_name].labels
        for kind in KINDS:
            for demo in getattr(md, kind):
                relaxed = np.unique(demo.labels_on(labels).ravel()[demo.relaxed_cells])
                for i in relaxed:
                    out[kind][LABELS[i].name] += 1
    return out
