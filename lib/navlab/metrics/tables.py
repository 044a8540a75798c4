"""A paper table as the track code hands it to the report writer: our rows, the paper's, notes and claims.

Why one type: a notebook only runs an experiment and passes its results to the track's ``tables``
module, which decides what goes beside what, the notes and the claim verdicts; the notebook then writes
each ``Table`` with ``pipeline.reports.write_table`` and displays it, assembling no prose itself. A
``Claim`` is one of the paper's claims checked on our numbers, with a typed verdict; the results page
(``pipeline.results.claims_of``) reads the same fields back from a report.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

VERDICTS = ("holds", "does not hold", "inconclusive")


@dataclass(frozen=True)
class Claim:
    """One of a paper's claims checked on our numbers."""

    claim: str  # the paper's claim, in our words
    verdict: str  # one of VERDICTS
    ours: str  # the measured numbers behind the verdict
    paper: str = ""  # the paper's number, where it states one
    why: str = ""  # what in our set-up explains a claim that does not hold

    def __post_init__(self):
        if self.verdict not in VERDICTS:
            raise ValueError(f"claim {self.claim!r}: verdict {self.verdict!r}; use one of {', '.join(VERDICTS)}")

    @classmethod
    def of(cls, claim: str, ok: bool | None, ours: str, why: str = "", paper: str = "") -> Claim:
        """The verdict of a yes/no test (None: inconclusive); ``why`` is kept only where it does not hold."""
        verdict = "inconclusive" if ok is None else "holds" if ok else "does not hold"
        return cls(claim, verdict, ours, paper=paper, why=why if verdict == "does not hold" else "")

    def line(self) -> str:
        """As notes list it: ``claim: verdict (ours[; paper P][; why: W])``, the form ``claims_of`` parses."""
        paper = f"; paper {self.paper}" if self.paper else ""
        why = f"; why: {self.why}" if self.why else ""
        return f"{self.claim}: {self.verdict} ({self.ours}{paper}{why})"

    def __str__(self) -> str:
        return self.line()


@dataclass(frozen=True)
class Table:
    table_id: str  # the report's file stem, e.g. "table1_seen"
    paper_ref: str  # which table of which paper, e.g. "PACER Table I"
    columns: list[str]
    rows: list[dict]  # what we measured
    paper_rows: list[dict]  # the paper's printed numbers, same columns
    notes: str  # set-up, differences from the paper, the claims with their numbers
    claims: Sequence[Claim] = field(default_factory=tuple)  # the claim verdicts, as ``notes`` states them
