"""Regenerated reports against the committed ones: which numbers moved outside their interval.

Why: data/ rebuilds bit for bit on any machine, but trained models and compiled solves differ in the
last float bits across CPUs, and training amplifies that (issue 13: Table I PACER low 0.3336 -> 0.33 on
a second machine). Bitwise identity is not promised there; a moved number must be visible instead.
A number with a 95% interval (``<column>_ci`` in the same row) is flagged when the other run's value
falls outside it (either way round); a number without one is flagged when it changed at all.
A committed report with no regenerated twin, or a report that is not readable JSON, is a difference
too (``Unusable``): a run that failed to write a table must not read as "0 numbers moved".
"""

from __future__ import annotations

import json
import math
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from navlab.core.io import DataError
from navlab.pipeline.reports import REQUIRED, key_columns


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


@dataclass(frozen=True)
class Unusable:
    """A report that could not be compared: missing on one side, or not a readable report."""

    path: str
    why: str

    def __str__(self) -> str:
        return f"{self.path}: {self.why}"


@dataclass
class FolderDiff:
    """What ``diff_folder`` found; any ``moved`` or ``unusable`` entry is a difference."""

    compared: int = 0
    moved: list[Moved] = field(default_factory=list)
    unusable: list[Unusable] = field(default_factory=list)
    new: list[str] = field(default_factory=list)  # regenerated tables the revision lacks (not a difference)


def committed_reports(root: str | Path, rev: str) -> dict[str, str]:
    """The text of every ``reports/<paper>/<table>.json`` committed at ``rev``, by that path."""
    listed = _git(root, "ls-tree", "-r", "--name-only", rev, "--", "reports")
    names = [n for n in listed.splitlines() if n.endswith(".json") and n.count("/") == 2]
    return {name: _git(root, "show", f"{rev}:{name}") for name in names}


def _git(root: str | Path, *args: str) -> str:
    proc = subprocess.run(["git", *args], cwd=root, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        last = (proc.stderr.strip().splitlines() or ["failed"])[-1]
        raise DataError(f"git {' '.join(args[:2])} in {root}: {last}; pass a revision that exists with --rev")
    return proc.stdout


def _parse(text: str) -> dict[str, Any] | str:
    """The report in ``text``, or why it cannot be compared."""
    try:
        report = json.loads(text)
    except ValueError as err:
        return f"not readable JSON ({err})"
    missing = [k for k in REQUIRED if k not in report] if isinstance(report, dict) else list(REQUIRED)
    return f"not a report (lacks {', '.join(missing)})" if missing else report


def _read(path: Path) -> dict[str, Any] | str:
    try:
        return _parse(path.read_text())
    except (OSError, UnicodeDecodeError) as err:
        return f"not readable JSON ({err})"


def diff_folder(reports_dir: str | Path, committed: dict[str, str]) -> FolderDiff:
    """Every regenerated ``<paper>/<table>.json`` under ``reports_dir`` against ``committed`` (by path)."""
    reports_dir, out = Path(reports_dir), FolderDiff()
    regenerated = {f"reports/{p.parent.name}/{p.name}": p for p in sorted(reports_dir.glob("*/*.json"))}
    for name in sorted(set(committed) | set(regenerated)):
        if name not in regenerated:
            out.unusable.append(Unusable(name, f"missing in {reports_dir}/"))
        elif name not in committed:
            out.new.append(name)
        else:
            _compare(name, committed[name], regenerated[name], out)
    return out


def _compare(name: str, committed: str, path: Path, out: FolderDiff) -> None:
    """Add one table's moved numbers, or why it could not be compared, to ``out``."""
    old, new = _parse(committed), _read(path)
    if isinstance(old, str):
        out.unusable.append(Unusable(f"{name} (committed)", old))
    elif isinstance(new, str):
        out.unusable.append(Unusable(str(path), new))
    else:
        out.compared += 1
        try:
            out.moved += diff_reports(old, new)
        except (AttributeError, KeyError, TypeError) as err:  # valid JSON, but rows of the wrong shape
            out.unusable.append(Unusable(str(path), f"not comparable ({type(err).__name__}: {err})"))
