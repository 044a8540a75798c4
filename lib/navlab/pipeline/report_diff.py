"""Regenerated reports against the committed ones: which numbers moved outside their interval.

Why: data/ rebuilds bit for bit on any machine, but trained models and compiled solves differ in the
last float bits across CPUs, and training amplifies that (issue 13: Table I PACER low 0.3336 -> 0.33 on
a second machine). Bitwise identity is not promised there; a moved number must be visible instead.
A number with a 95% interval (``<column>_ci`` in the same row) is flagged when the other run's value
falls outside it (either way round); a number without one is flagged when it changed at all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from navlab.pipeline.reports import key_columns


@dataclass(frozen=True)
class Moved:
    """One number that differs between the committed and the regenerated report."""

    table_id: str
    row: str
    column: str
    committed: Any
    regenerated: Any
    interval: tuple[float, float] | None  # the interval it left; None when the column has none

    def __str__(self) -> str:
        where = f"{self.table_id} [{self.row}] {self.column}"
        if self.interval is None:
            return f"{where}: {self.committed} -> {self.regenerated} (changed; no interval)"
        lo, hi = self.interval
        return f"{where}: {self.committed} -> {self.regenerated} (outside [{lo:.4g}, {hi:.4g}])"


def _inside(value: Any, interval: Any) -> bool:
    return (isinstance(interval, list | tuple) and len(interval) == 2 and None not in interval
            and isinstance(value, int | float) and interval[0] <= value <= interval[1])


def diff_reports(committed: dict[str, Any], regenerated: dict[str, Any], rel_tol: float = 1e-9) -> list[Moved]:
    """Every number of ``committed`` that moved in ``regenerated`` beyond its interval (or at all)."""
    keys = key_columns(committed)
    old = {tuple(r.get(k) for k in keys): r for r in committed["rows"]}
    new = {tuple(r.get(k) for k in keys): r for r in regenerated["rows"]}
    metrics = [c for c in committed["columns"] if c not in keys and not c.endswith("_ci")]
    moved = []
    for key in sorted(set(old) | set(new), key=str):
        a, b = old.get(key, {}), new.get(key, {})
        name = "/".join(str(k) for k in key) or "all"
        for col in metrics:
            x, y = a.get(col), b.get(col)
            if x == y or (isinstance(x, int | float) and isinstance(y, int | float)
                          and math.isclose(x, y, rel_tol=rel_tol, abs_tol=1e-12)):
                continue
            ci_a, ci_b = a.get(f"{col}_ci"), b.get(f"{col}_ci")
            if ci_a is None and ci_b is None:
                moved.append(Moved(committed["table_id"], name, col, x, y, None))
            elif not (_inside(y, ci_a) and _inside(x, ci_b)):
                bad = ci_a if not _inside(y, ci_a) and ci_a is not None else ci_b
                interval = tuple(bad) if isinstance(bad, list | tuple) and None not in bad else None
                moved.append(Moved(committed["table_id"], name, col, x, y, interval))
    return moved
