"""A paper table as the track code hands it to the report writer: our rows, the paper's, notes and claims.

Why one type: a notebook only runs an experiment and passes its results to the track's ``tables``
module, which decides what goes beside what, the notes and the claim verdicts; the notebook then writes
each ``Table`` with ``pipeline.reports.write_table`` and displays it, assembling no prose itself. Its
claims are ``navlab.metrics.claims.Claim`` records (the paper's, quoted, and ours, apart), decided by that
module's strict rules; the results page reads the same typed records back from a report.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from navlab.metrics.claims import Claim


@dataclass(frozen=True)
class Table:
    table_id: str  # the report's file stem, e.g. "table1_seen"
    paper_ref: str  # which table of which paper, e.g. "PACER Table I"
    columns: list[str]
    rows: list[dict]  # what we measured
    paper_rows: list[dict]  # the paper's printed numbers, same columns
    notes: str  # set-up and differences from the paper (the claims are in ``claims``, never repeated here)
    claims: Sequence[Claim] = field(default_factory=tuple)  # the paper's claims and our checks, decided
