"""The results page and the front door's results block: generated, current, and readable (issue 27)."""

import re
from pathlib import Path

from navlab.metrics.tables import Table
from navlab.pipeline.reports import write_table
from navlab.pipeline.results import (
    BEGIN,
    END,
    PAPERS,
    claims_of,
    headline_block,
    read_tracks,
    render_page,
    shown_figures,
    write_index,
)

REPORTS = Path("reports")


def test_the_committed_results_page_is_current():
    page = render_page(read_tracks(REPORTS), shown_figures(REPORTS)) + "\n"
    assert (REPORTS / "README.md").read_text(encoding="utf8") == page, \
        "reports/README.md is stale: run `python -m navlab reports index`"


def test_the_front_door_block_is_current():
    readme = Path("README.md").read_text(encoding="utf8")
    block = readme[readme.index(BEGIN):readme.index(END) + len(END)]
    assert block == headline_block(read_tracks(REPORTS), shown_figures(REPORTS), "reports/README.md"), \
        "README.md's results block is stale: run `python -m navlab reports index`"


def test_the_page_has_a_claims_table_per_paper_no_empty_pairs_and_only_existing_figures():
    page = (REPORTS / "README.md").read_text(encoding="utf8")
    for paper in PAPERS.values():
        section = page.split(f"## {paper.name}\n", 1)[1].split("\n## ", 1)[0]
        assert f"### {paper.name} claims\n\n| table | claim | paper | ours | verdict | why |" in section
    assert "/ —" not in page and "/ —" not in Path("README.md").read_text(encoding="utf8")
    for readme, base in ((REPORTS / "README.md", REPORTS), (Path("README.md"), Path("."))):
        images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", readme.read_text(encoding="utf8"))
        assert images and all((base / image).is_file() for image in images), images
    shown = [path for figures in shown_figures(REPORTS).values() for path, _ in figures]
    assert all(f"]({path})" in page for path in shown) and len(shown) >= len(PAPERS)


def test_claims_are_read_from_each_notes_form_and_from_typed_data():
    hj = ("Set-up. Claims: TTR cuts A* expansions (on tasks): holds (10 vs 20); BRT raises success: DOES NOT HOLD "
          "(4/4 vs 4/4; paper 4/4 vs 2/4; why: OBS already solves all (see Fig. 7)). Failures: none.")
    surenav = ("x. Claims: a: b first: inconclusive (SuReNav not run) | c: does not hold (0.1 vs 0.2: x0.50; "
               "paper 0.416 vs 0.271; why: personas (see d))")
    pacer = "y. Claim 'PACER beats STERLING (2a)': inconclusive (+0.1, 95% CI [-0.0, 0.2]). Claim 'z': holds (1)."
    got = [claims_of({"notes": n}) for n in (hj, surenav, pacer)]
    assert [(c.claim, c.verdict, c.paper, c.ours, c.why) for c in got[0]] == [
        ("TTR cuts A* expansions (on tasks)", "holds", "", "10 vs 20", ""),
        ("BRT raises success", "does not hold", "4/4 vs 2/4", "4/4 vs 4/4", "OBS already solves all (see Fig. 7)")]
    assert [(c.claim, c.verdict, c.ours, c.paper, c.why) for c in got[1]] == [
        ("a: b first", "inconclusive", "SuReNav not run", "", ""),
        ("c", "does not hold", "0.1 vs 0.2: x0.50", "0.416 vs 0.271", "personas (see d)")]
    older = "x. Claims: a: undecided (SuReNav not run) | c: does not hold (ours: 0.1; why: personas)"  # before issue 27
    assert [(c.claim, c.verdict, c.ours, c.why) for c in claims_of({"notes": older})] == [
        ("a", "inconclusive", "SuReNav not run", ""), ("c", "does not hold", "0.1", "personas")]
    assert [(c.claim, c.verdict) for c in got[2]] == [("PACER beats STERLING (2a)", "inconclusive"), ("z", "holds")]
    typed = {"notes": hj, "claims": [{"claim": "t", "verdict": "Holds", "ours": "1 [0, 2]", "paper": 3}]}
    assert [(c.claim, c.verdict, c.paper, c.why) for c in claims_of(typed)] == [("t", "holds", "3", "")]


def test_a_table_shows_the_papers_columns_with_inline_intervals(tmp_path):
    rows = [{"method": "PACER", "maps": 20, "low": 0.75, "low_ci": [0.4712, 0.9123], "high": 0.1, "loss": 2.0},
            {"method": "Oracle", "maps": 20, "low": 0.9, "low_ci": [0.8, 0.95], "high": 0.0, "loss": 1.0}]
    paper_rows = [{"method": "PACER", "maps": 20, "low": 0.7, "high": None},
                  {"method": "Classifier", "maps": 20, "low": 0.6, "high": None}]
    table = Table("table1_seen", "PACER Table I", ["method", "maps", "low", "low_ci", "high", "loss"], rows, paper_rows,
                  "Claim 'PACER is good': holds (0.75).")
    write_table(tmp_path, table, track="pacer", profile="smoke", seeds=[0])
    page = write_index(tmp_path).read_text()
    assert "| method | maps | low | low (paper) | high |" in page  # loss is ours alone: a diagnostic
    assert "| PACER | 20 | 0.75 [0.471, 0.912] | 0.7 | 0.1 |" in page
    assert "| Oracle | 20 | 0.9 [0.8, 0.95] |  | 0 |" in page and "| Classifier | not run | not run | 0.6 | not run |" in page
    assert "The paper's maps: the same as ours. The paper prints no number for high." in page
    assert "| [table1_seen](pacer/table1_seen.md) | PACER is good |  | 0.75 | holds |  |" in page
