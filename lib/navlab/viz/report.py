"""What a table notebook shows last: its report (the table beside the paper's, the notes, the paper's claims
and, apart, our checks: ``pipeline.reports.to_markdown``) and the figures it saved, read back from disk.

Why from disk: the reader sees exactly what the stage wrote and the results page links, not a second
rendering that could differ from it.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path


def show(report: Path | None = None, figures: Sequence[Path] = ()) -> None:
    """Display ``report``'s Markdown twin (``report`` is its .json or .md path) and each figure PNG."""
    from IPython.display import Image, Markdown, display

    if report is not None:
        display(Markdown(Path(report).with_suffix(".md").read_text(encoding="utf8")))
    for figure in figures:
        display(Markdown(f"*{Path(figure).name}*"), Image(filename=str(figure)))
