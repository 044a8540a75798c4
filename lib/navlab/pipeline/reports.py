"""Report files: the contract between notebooks, the README, DVC metrics and reviewers (docs/design.md, "The
report contract").

Each reproduced table is ``reports/<paper>/<table_id>.json`` (our numbers beside the paper's) and a
Markdown twin (the claims as a table); ``pipeline.results.write_index`` gathers them into the results
page. Beyond the contract's keys, the JSON carries the typed ``claims`` and ``metrics``: our rows again,
keyed by row, because `dvc metrics show/diff` only read numbers out of mappings, not out of ``rows``.
"""

from __future__ import annotations

import json
import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any

from navlab.core.io import write_json, write_text
from navlab.metrics.tables import Table

REQUIRED = ("table_id", "paper_ref", "profile", "seeds", "columns", "rows", "paper", "notes")
TABLE_IDS = {  # every paper table the report contract promises; the index lists the ones without a report yet
    "surenav": ("table1_human_likeness", "fig4_safety_efficiency"),
    "hj": ("table1_heuristics_astar", "table2_heuristics_anastar", "table3_pruning_astar",
           "table4_pruning_anastar", "table5_static_general", "table6_dynamic", "table7_compute", "table8_rooms",
           "table9_humans"),
    "pacer": ("table1_seen", "table2_unseen", "table3_phases_seen", "table4_phases_unseen",
              "table5_margin_ranking", "context_following"),
}


def write_table(reports_dir: str | Path, table: Table, *, track: str, profile: str, seeds: Sequence[int]) -> Path:
    """Write the JSON and Markdown twin of ``table`` under ``reports_dir/track``; returns the JSON path.

    Our rows beside the paper's printed numbers for the same columns, and the claims as typed data (the
    results page and `dvc metrics` read them, not the notes). Non-finite numbers become ``null`` (a method
    that failed), never a made-up figure.
    """
    table_id, columns, rows, paper_rows = table.table_id, table.columns, table.rows, table.paper_rows
    for r in (*rows, *paper_rows):
        extra = set(r) - set(columns)
        if extra:
            raise ValueError(f"{table_id}: row has keys {sorted(extra)} not in columns {list(columns)}")
    report = {
        "table_id": table_id,
        "paper_ref": table.paper_ref,
        "profile": profile,
        "seeds": [int(s) for s in seeds],
        "columns": list(columns),
        "rows": [_clean(r) for r in rows],
        "paper": [_clean(r) for r in paper_rows],
        "notes": table.notes,
        "claims": [asdict(c) for c in table.claims],
    }
    keys = key_columns(report)
    for which in ("rows", "paper"):  # the Markdown and `metrics` pair rows by key: a repeat would vanish
        counts = Counter(tuple(r.get(c) for c in keys) for r in report[which])
        repeated = next((k for k, n in counts.items() if n > 1), None)
        if repeated is not None:
            raise ValueError(f"{table_id}: two {which} share the key {dict(zip(keys, repeated, strict=True))}; "
                             "add a text column that tells them apart (e.g. the map or the setting)")
    report["metrics"] = _metrics_by_row(report)
    out = Path(reports_dir) / track
    write_json(out / f"{table_id}.json", report)
    write_text(out / f"{table_id}.md", to_markdown(report))
    return out / f"{table_id}.json"


def read_table(path: str | Path) -> dict[str, Any]:
    report = json.loads(Path(path).read_text())
    missing = [k for k in REQUIRED if k not in report]
    if missing:
        raise ValueError(f"{path}: report lacks {', '.join(missing)} (docs/design.md, 'The report contract')")
    return report


def _clean(row: dict[str, Any]) -> dict[str, Any]:
    out = {}
    for k, v in row.items():
        if hasattr(v, "item"):  # numpy / torch scalars
            v = v.item()
        if isinstance(v, float) and not math.isfinite(v):
            v = None
        out[k] = v
    return out


def _metrics_by_row(report: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Our numbers keyed by row ("SuReNav/milan": {"sr": 0.9}): lists are opaque to `dvc metrics show`."""
    keys = key_columns(report)
    return {
        "/".join(str(r.get(k)) for k in keys) or "all": {c: v for c, v in r.items() if c not in keys}
        for r in report["rows"]
    }


def _fmt(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def key_columns(report: dict[str, Any]) -> list[str]:
    rows = report["rows"] + report["paper"]
    return [c for c in report["columns"] if any(isinstance(r.get(c), str) for r in rows)]


def to_markdown(report: dict[str, Any]) -> str:
    """Ours beside the paper's: one line per row key, each metric as ``ours / paper``."""
    keys = key_columns(report)
    metrics = [c for c in report["columns"] if c not in keys]
    ours = {tuple(r.get(k) for k in keys): r for r in report["rows"]}
    theirs = {tuple(r.get(k) for k in keys): r for r in report["paper"]}
    order = list(ours) + [k for k in theirs if k not in ours]
    lines = [
        f"# {report['table_id']} — {report['paper_ref']}",
        "",
        f"Profile `{report['profile']}`, seeds {report['seeds']}. Each cell: **ours** / paper.",
        "",
        "| " + " | ".join(keys + metrics) + " |",
        "|" + "---|" * (len(keys) + len(metrics)),
    ]
    for key in order:
        mine, paper = ours.get(key, {}), theirs.get(key, {})
        cells = [_fmt(k) for k in key]
        for m in metrics:
            a = _fmt(mine.get(m)) if key in ours else "not run"
            b = _fmt(paper.get(m)) if key in theirs else "—"
            cells.append(f"**{a}** / {b}")
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", report["notes"], ""]
    if report.get("claims"):
        lines += ["| claim | paper | ours | verdict | why |", "|---|---|---|---|---|"]
        lines += [f"| {c['claim']} | {c['paper'] or '—'} | {c['ours']} | **{c['verdict']}** | {c['why'] or '—'} |"
                  for c in report["claims"]]
        lines.append("")
    return "\n".join(lines)

