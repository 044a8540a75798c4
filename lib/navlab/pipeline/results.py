"""The results page (``reports/README.md``) and the front door's headline block, generated from the reports.

Why generated: a number typed by hand goes stale the next time a stage runs. The page shows, per paper and
in the paper's order, only the paper's own columns with our 95% interval inline (``0.75 [0.47, 0.91]``)
and the paper's number beside ours where it prints one; diagnostics (intervals as columns, seed spreads,
failure counts, timings) stay in each table's own ``.md``/JSON. Each paper gets one claims table: every
claim in its track's registry (``navlab.<track>.claims.CLAIMS``), quoted, with the verdict its report's
typed ``claims`` records give it (or "not tested", with the reason), tallied apart from our own checks,
which get a table of their own. The reproduced figures of each track (its manifest's ``figures``) are
committed to git by the stages that draw them (``cache: false`` outputs, ``navlab.pipeline.dvc_yaml``), so
the page and README.md show them on GitHub and a fresh clone has them whichever stages it re-runs; the page
links them where they lie. What the page knows of each paper comes from its manifest (``navlab.tracks``).
"""

from __future__ import annotations

import os
import re
from importlib import import_module
from pathlib import Path
from typing import Any

import navlab.tracks
from navlab.core.io import DataError, write_text
from navlab.core.track import Figure, Paper, Track
from navlab.metrics.claims import Claim, PaperClaim, tally
from navlab.pipeline.reports import TABLE_IDS, key_columns, read_table

INDEX = "README.md"
BEGIN = "<!-- results: written by `python -m navlab reports index` from reports/; do not edit by hand -->"
END = "<!-- /results -->"


def manifests() -> dict[str, Track]:
    """{report folder: its track's manifest}, in the order the page shows them (``navlab.tracks.TRACKS``, read
    when called, so a track added there, or by a test, reaches the page)."""
    return {track.name: track for track in navlab.tracks.TRACKS}


def papers() -> dict[str, Paper]:
    """{report folder: the paper it reproduces}, in the order the page shows them."""
    return {name: track.paper for name, track in manifests().items()}


def figures_shown() -> dict[str, tuple[Figure, ...]]:
    """{track: its manifest's figures}: the first of each track is also the front door's figure. The stage
    that draws each commits it to git (navlab.pipeline.dvc_yaml.committed_outs)."""
    return {name: track.figures for name, track in manifests().items()}


OTHER = "Pipeline check"  # report folders that reproduce no paper (the quickstart)

OUT_OF = ("trips", "tasks", "runs")  # what a headline success count is out of, where the row says

# ---------------------------------------------------------------------------------------------- claims

def claims_of(report: dict[str, Any]) -> list[Claim]:
    """The claims a report decided under the strict rules: its typed ``claims`` records (the paper's and
    ours), as written."""
    return [Claim.from_dict(c) for c in report.get("claims") or []]


def claim_modules() -> dict[str, str]:
    """{track: the module holding its paper's claims registry (CLAIMS)}."""
    return {name: track.claims for name, track in manifests().items() if track.claims}


def registries() -> dict[str, dict[str, PaperClaim]]:
    """{track: its claims registry}: every claim of each paper, quoted, decided by a report or not tested.
    Imported when the page is written, not with this module (every CLI command imports it through
    ``dvc_yaml``); the index stage's deps name them (``pipeline.stages.entry_modules``)."""
    return {track: import_module(module).CLAIMS for track, module in claim_modules().items()}


def paper_claims(track: str, reports: list[tuple[str, dict[str, Any]]],
                 registry: dict[str, PaperClaim]) -> list[tuple[str, Claim]]:
    """(where it was decided, claim) for each of the paper's claims: as its reports decided them, then those
    no report tests (the registry's reason), then those a report should decide but does not (a missing report
    or an out-of-date one: "not tested", saying which)."""
    found = [(_link(track, table_id), c) for table_id, report in reports for c in claims_of(report)
             if c.source == "paper"]
    decided = {c.key for _, c in found}
    present = {table_id for table_id, _ in reports}
    for entry in registry.values():
        if entry.key in decided:
            continue
        if entry.not_tested:
            found.append(("—", entry.untested()))
        else:
            why = (f"its report `{entry.report}` does not decide it (re-run its stage)" if entry.report in present
                   else f"its report `{entry.report}` has not been made")
            found.append((_link(track, entry.report) if entry.report in present else "—", entry.untested(why)))
    return found


def our_checks(track: str, reports: list[tuple[str, dict[str, Any]]]) -> list[tuple[str, Claim]]:
    """Our own checks (diagnostics the paper does not state), counted apart from the paper's claims."""
    return [(_link(track, table_id), c) for table_id, report in reports for c in claims_of(report)
            if c.source == "ours"]


def _link(track: str, table_id: str) -> str:
    return f"[{table_id}]({track}/{table_id}.md)"


def tally_line(claims: list[Claim]) -> str:
    """"N of M of the paper's claims hold, ..." with every verdict that occurs."""
    counts = tally(claims)
    parts = [f"{counts[v]} {label}" for v, label in (("holds in direction only", "hold in direction only"),
                                                      ("does not hold", "do not hold"),
                                                      ("inconclusive", "inconclusive"),
                                                      ("not tested", "not tested")) if counts[v]]
    return f"{counts['holds']} of {len(claims)} of the paper's claims hold" + "".join(f", {p}" for p in parts)


# ---------------------------------------------------------------------------------------------- tables

def _num(v: Any) -> str:
    """Three significant figures, whole numbers from 100 up (node counts, metres), never exponents."""
    if v is None:
        return "—"
    if isinstance(v, bool) or not isinstance(v, int | float):
        return str(v)
    if isinstance(v, int) or abs(v) >= 100:
        return f"{v:,.0f}"
    return f"{v:.3g}"


def _cell(row: dict[str, Any], col: str) -> str:
    """Our value with its 95% interval inline where the report has one (``<col>_ci``)."""
    return _num(row.get(col)) + _interval(row, col)


def _interval(row: dict[str, Any], col: str) -> str:
    """`` [lo, hi]`` from the report's ``<col>_ci``, or "" where it has none."""
    ci = row.get(f"{col}_ci")
    return f" [{_num(ci[0])}, {_num(ci[1])}]" if isinstance(ci, list) and len(ci) == 2 and row.get(col) is not None else ""


def shown_columns(report: dict[str, Any], track: str) -> list[str]:
    """The paper's own columns (those its printed rows carry), else the manifest's ``shown`` choice, else ours less
    intervals and spreads."""
    keys = key_columns(report)
    manifest = manifests().get(track)
    chosen = dict(manifest.shown).get(report["table_id"]) if manifest else None
    if chosen:
        return list(chosen)
    paper_cols = {c for r in report["paper"] for c in r}
    if paper_cols:
        return [c for c in report["columns"] if c in paper_cols and c not in keys]
    return [c for c in report["columns"] if c not in keys and not c.endswith(("_ci", "_sd"))]


def table_markdown(report: dict[str, Any], track: str) -> list[str]:
    """One table: a row per method (ours, then the paper's rows we did not run); beside each column the
    paper's number where the paper prints any for it."""
    keys, cols = key_columns(report), shown_columns(report, track)
    paper = {tuple(r.get(k) for k in keys): r for r in report["paper"]}
    ours = {tuple(r.get(k) for k in keys): r for r in report["rows"]}
    printed = [c for c in cols if any(isinstance(r.get(c), int | float) for r in report["paper"])]
    both = [k for k in paper if k in ours]
    same = [c for c in printed if both and all(ours[k].get(c) == paper[k].get(c) for k in both)]
    printed = [c for c in printed if c not in same]  # a denominator both share (tasks, runs) needs one column
    header = [*keys]
    for c in cols:
        header += [c, f"{c} (paper)"] if c in printed else [c]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for key in [*ours, *(k for k in paper if k not in ours)]:
        mine, theirs = ours.get(key), paper.get(key, {})
        if mine is not None and all(mine.get(c) is None for c in cols) and not theirs:
            continue  # a diagnostic row (e.g. a validation loss): its own .md has it
        cells = [str(k) for k in key]
        for c in cols:
            cells.append(_cell(mine, c) if mine is not None else "not run")
            if c in printed:
                cells.append(_num(theirs[c]) if theirs.get(c) is not None else "")
        lines.append("| " + " | ".join(cells) + " |")
    unprinted = [c for c in cols if c not in printed and c not in same]
    if track not in manifests():
        return lines
    if not printed and not same:
        return [*lines, "", "The paper prints no number for this table."]
    notes = [f"The paper's {', '.join(same)}: the same as ours."] if same else []
    notes += [f"The paper prints no number for {', '.join(unprinted)}."] if unprinted else []
    return [*lines, "", " ".join(notes)] if notes else lines


def _markdown_table(header: tuple[str, ...], rows: list[tuple[str, ...]]) -> list[str]:
    """A Markdown table, each cell's pipes escaped and newlines flattened."""
    def line(cells):
        return "| " + " | ".join((c or "").replace("|", "\\|").replace("\n", " ") for c in cells) + " |"

    return [line(header), "|" + "---|" * len(header), *map(line, rows)]


def _verdict(c: Claim) -> str:
    return f"**{c.verdict}**" if c.verdict != "holds" else c.verdict


def _claims_table(claims: list[tuple[str, Claim]]) -> list[str]:
    return _markdown_table(("table", "claim", "where", "the paper says", "paper", "ours", "verdict", "why"),
                           [(table, c.claim, c.where, f'"{c.quote}"', c.paper, c.ours, _verdict(c), c.why)
                            for table, c in claims])


def _checks_table(checks: list[tuple[str, Claim]]) -> list[str]:
    return _markdown_table(("table", "check", "ours", "verdict", "why"),
                           [(table, c.claim, c.ours, _verdict(c), c.why) for table, c in checks])


def _figure_markdown(figure: Figure) -> str:
    """An image, or a link where the figure is an interactive HTML scene (a page cannot embed it)."""
    if figure.path.endswith(".html"):
        return f"[{figure.caption}]({figure.path}): open the file in a browser.\n"
    return f"![{figure.caption}]({figure.path})\n\n*{figure.caption}*\n"


def _anchor(heading: str) -> str:
    """GitHub's anchor for a Markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-")


def read_tracks(reports_dir: Path) -> dict[str, list[tuple[str, dict[str, Any]]]]:
    """{track: [(table id, report)]}: papers first in ``papers()`` order, each paper's tables in its order
    (``TABLE_IDS``), then our extra tables; folders of no paper last."""
    found: dict[str, list[tuple[str, dict[str, Any]]]] = {}
    for path in sorted(reports_dir.glob("*/*.json")):
        found.setdefault(path.parent.name, []).append((path.stem, read_table(path)))
    order = [*papers(), *sorted(t for t in found if t not in papers())]
    return {t: sorted(found[t], key=lambda item: (_paper_order(t) + [item[0]]).index(item[0]))
            for t in order if t in found}


def _paper_order(track: str) -> list[str]:
    """The track's reports in its paper's order: the figures it reads before its first table (``before``),
    then its tables (``TABLE_IDS``)."""
    manifest = manifests().get(track)
    before = manifest.before if manifest else ()
    return [*before, *TABLE_IDS.get(track, ())]


def shown_figures(reports_dir: Path) -> dict[str, list[Figure]]:
    """{track: [figure]} of the manifests' figures present under ``reports_dir``: the page links no
    missing file."""
    return {track: [f for f in figures if (reports_dir / f.path).is_file()] for track, figures in figures_shown().items()}


def render_page(tracks: dict[str, list[tuple[str, dict[str, Any]]]], figures: dict[str, list[Figure]],
                claim_registries: dict[str, dict[str, PaperClaim]]) -> str:
    profiles = sorted({report["profile"] for reports in tracks.values() for _, report in reports})
    parts = [
        "# Reproduced results",
        "",
        "Generated by `python -m navlab reports index` from the report JSONs (profile "
        + ", ".join(f"`{p}`" for p in profiles) + ").",
        "Each table shows the paper's own columns: ours with its 95% interval in brackets, the paper's number",
        "beside it where the paper prints one. Each table's heading links its own page, with the notes (set-up,",
        "differences from the paper) and every diagnostic column. Our data and sizes differ from the papers';",
        "the notes say how. Each paper's claims, quoted and checked on our numbers, close its section; our own",
        "checks follow, apart.",
        "",
    ]
    for track, reports in tracks.items():
        paper = papers().get(track)
        parts += [f"## {paper.name if paper else OTHER}", ""]
        if paper:
            parts += [f"[*{paper.title}*]({paper.link})", ""]
        shown = figures.get(track, [])
        parts += [_figure_markdown(f) for f in shown if f.beside not in {table_id for table_id, _ in reports}]
        for table_id, report in reports:
            parts += [f"### [{report['paper_ref']}]({track}/{table_id}.md)", "", *table_markdown(report, track), ""]
            parts += [_figure_markdown(f) for f in shown if f.beside == table_id]
        if paper and track in claim_registries:  # a track without a paper's claims (the stack) has no tally
            claims = paper_claims(track, reports, claim_registries[track])
            checks = our_checks(track, reports)
            parts += [f"### {paper.name} claims", "",
                      tally_line([c for _, c in claims]) + ". Each is the paper's sentence, quoted, decided on a paired "
                      "test over the table's units at the 5% level (`navlab.metrics.claims`): a tie or a difference "
                      "the test cannot tell from zero is inconclusive, never \"holds\".", "", *_claims_table(claims), ""]
            if checks:
                parts += [f"### {paper.name}: our own checks", "",
                          "Diagnostics of ours, not claims of the paper; counted apart.", "", *_checks_table(checks), ""]
    missing = [f"`{paper}/{t}`" for paper, ids in TABLE_IDS.items() for t in ids
               if t not in {table_id for table_id, _ in tracks.get(paper, [])}]
    if missing:
        parts += ["## Not reproduced yet", "", "No report exists yet for: " + ", ".join(missing) + ".", ""]
    return "\n".join(parts)


def headline_block(tracks: dict[str, list[tuple[str, dict[str, Any]]]], figures: dict[str, list[Figure]],
                   page: str, claim_registries: dict[str, dict[str, PaperClaim]]) -> str:
    """The front door's results: per paper its figure, a few headline numbers (ours with intervals beside
    the paper's) and the count of claim verdicts, linking ``page`` (the results page, relative)."""
    base = page.removesuffix(INDEX)
    parts = [BEGIN, ""]
    for track, paper in papers().items():
        reports = dict(tracks.get(track, []))
        if not reports:
            continue
        parts += [f"### {paper.name}", ""]
        if figures.get(track):
            first = figures[track][0]
            parts += [f"![{first.caption}]({base}{first.path})", ""]
        parts += ["| table | row | column | ours [95% interval] | paper |", "|---|---|---|---|---|"]
        for table_id, key, cols in manifests()[track].headline:
            report = reports[table_id]
            keys = key_columns(report)
            mine = next(r for r in report["rows"] if tuple(r.get(k) for k in keys) == key)
            theirs = next((r for r in report["paper"] if tuple(r.get(k) for k in keys) == key), {})
            for c in cols:
                ours, printed = _cell(mine, c), _num(theirs[c]) if theirs.get(c) is not None else ""
                out_of = next((k for k in OUT_OF if c == "success" and k in mine), None)
                if out_of:  # a count pooled over more trials than the paper's: "24/24" beside "6/6"
                    ours = f"{_num(mine[c])}/{_num(mine[out_of])}{_interval(mine, c)}"
                    printed = f"{printed}/{_num(theirs[out_of])}" if printed and theirs.get(out_of) else printed
                parts.append(f"| [{report['paper_ref']}]({base}{track}/{table_id}.md) | {', '.join(key)} | {c} | "
                             f"{ours} | {printed} |")
        listed = list(reports.items())
        if track not in claim_registries:
            parts.append("")
            continue
        link = f"{page}#{_anchor(paper.name + ' claims')}"
        claims = [c for _, c in paper_claims(track, listed, claim_registries[track])]
        checks = tally([c for _, c in our_checks(track, listed)])
        parts += ["", (f"{tally_line(claims)} ([each quoted, with its numbers and reason]({link})); our own checks, "
                  f"apart: {checks['holds']} of {sum(checks.values())} hold."), ""]
    parts.append(END)
    return "\n".join(parts)


def write_index(reports_dir: str | Path, readme: str | Path | None = None) -> Path:
    """Write ``reports/README.md``; with ``readme``, also rewrite its results block
    (between ``BEGIN`` and ``END``: the front door's numbers, which no one types by hand)."""
    reports_dir = Path(reports_dir)
    if not reports_dir.is_dir():
        raise DataError(f"{reports_dir}/ does not exist: no reports to index (--reports-dir names the folder "
                        "the notebooks wrote)")
    tracks, figures, claim_registries = read_tracks(reports_dir), shown_figures(reports_dir), registries()
    out = reports_dir / INDEX
    write_text(out, render_page(tracks, figures, claim_registries) + "\n")
    if readme is not None:
        readme = Path(readme)
        text = readme.read_text(encoding="utf8")
        if BEGIN not in text or END not in text:
            raise DataError(f"{readme} has no results block: add the lines\n{BEGIN}\n{END}\nwhere it goes")
        page = os.path.relpath(out, readme.parent).replace(os.sep, "/")
        head, rest = text.split(BEGIN, 1)
        write_text(readme, head + headline_block(tracks, figures, page, claim_registries) + rest.split(END, 1)[1])
    return out
