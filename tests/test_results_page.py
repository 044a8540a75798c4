"""The results page and the front door's results block: generated, current, and readable (issue 27)."""

import re
from dataclasses import asdict
from pathlib import Path

from navlab.metrics.claims import Claim, PaperClaim
from navlab.metrics.tables import Table
from navlab.pipeline.reports import write_table
from navlab.pipeline.results import (
    BEGIN,
    END,
    claims_of,
    headline_block,
    paper_claims,
    papers,
    read_tracks,
    registries,
    render_page,
    shown_figures,
    tally_line,
    write_index,
)

REPORTS = Path("reports")


def test_the_committed_results_page_is_current():
    page = render_page(read_tracks(REPORTS), shown_figures(REPORTS), registries()) + "\n"
    assert (REPORTS / "README.md").read_text(encoding="utf8") == page, \
        "reports/README.md is stale: run `python -m navlab reports index`"


def test_the_front_door_block_is_current():
    readme = Path("README.md").read_text(encoding="utf8")
    block = readme[readme.index(BEGIN):readme.index(END) + len(END)]
    assert block == headline_block(read_tracks(REPORTS), shown_figures(REPORTS), "reports/README.md", registries()), \
        "README.md's results block is stale: run `python -m navlab reports index`"


def test_the_page_has_a_claims_table_per_paper_no_empty_pairs_and_only_existing_figures():
    page = (REPORTS / "README.md").read_text(encoding="utf8")
    registered = registries()
    for track, paper in papers().items():
        section = page.split(f"## {paper.name}\n", 1)[1].split("\n## ", 1)[0]
        if track == "stack":  # ours, joining the three: no paper's claims to decide, no tally
            assert track not in registered and f"### {paper.name} claims" not in section
            continue
        assert f"### {paper.name} claims\n\n" in section
        assert track in registered
        assert "| table | claim | where | the paper says | paper | ours | verdict | why |" in section, track
    assert "/ —" not in page and "/ —" not in Path("README.md").read_text(encoding="utf8")
    for readme, base in ((REPORTS / "README.md", REPORTS), (Path("README.md"), Path("."))):
        images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", readme.read_text(encoding="utf8"))
        assert images and all((base / image).is_file() for image in images), images
    shown = [f.path for figures in shown_figures(REPORTS).values() for f in figures]
    assert all(f"]({path})" in page for path in shown) and len(shown) >= len(papers())


def test_claims_are_read_back_typed_and_the_tally_counts_only_the_papers():
    quoted = {"quote": "we find it", "where": "Sec. I"}
    report = {"claims": [asdict(Claim("a", "holds", "1", key="k1", **quoted)),
                         asdict(Claim("b", "inconclusive", "2", key="k2", **quoted)),
                         asdict(Claim("ours", "holds", "3", source="ours"))]}
    assert [(c.claim, c.verdict, c.source) for c in claims_of(report)] == [
        ("a", "holds", "paper"), ("b", "inconclusive", "paper"), ("ours", "holds", "ours")]
    registry = {k: PaperClaim(k, k, "we find it", "Sec. I", report="t") for k in ("k1", "k2", "k3")}
    registry["k4"] = PaperClaim("k4", "robot", "we find it", "Sec. II", not_tested="a real robot")
    claims = paper_claims("hj", [("t", report)], registry)
    assert [(c.key, c.verdict) for _, c in claims] == [
        ("k1", "holds"), ("k2", "inconclusive"), ("k3", "not tested"), ("k4", "not tested")]
    assert "does not decide it" in claims[2][1].why  # a registry claim its report forgot is shown, not dropped
    assert claims[3][1].why == "a real robot"
    assert tally_line([c for _, c in claims]) == (
        "1 of 4 of the paper's claims hold, 1 inconclusive, 2 not tested")


def test_a_table_shows_the_papers_columns_with_inline_intervals(tmp_path):
    rows = [{"method": "PACER", "maps": 20, "low": 0.75, "low_ci": [0.4712, 0.9123], "high": 0.1, "loss": 2.0},
            {"method": "Oracle", "maps": 20, "low": 0.9, "low_ci": [0.8, 0.95], "high": 0.0, "loss": 1.0}]
    paper_rows = [{"method": "PACER", "maps": 20, "low": 0.7, "high": None},
                  {"method": "Classifier", "maps": 20, "low": 0.6, "high": None}]
    table = Table("table1_seen", "PACER Table I", ["method", "maps", "low", "low_ci", "high", "loss"], rows, paper_rows,
                  "set-up", claims=(Claim("PACER is good", "holds", "0.75", source="ours"),))
    write_table(tmp_path, table, track="pacer", profile="smoke", seeds=[0])
    page = write_index(tmp_path).read_text()
    assert "| method | maps | low | low (paper) | high |" in page  # loss is ours alone: a diagnostic
    assert "| PACER | 20 | 0.75 [0.471, 0.912] | 0.7 | 0.1 |" in page
    assert "| Oracle | 20 | 0.9 [0.8, 0.95] |  | 0 |" in page and "| Classifier | not run | not run | 0.6 | not run |" in page
    assert "The paper's maps: the same as ours. The paper prints no number for high." in page
    # a check of ours is listed apart from the paper's claims, which the registry lists (here: not decided)
    ours = page.split("### PACER: our own checks", 1)[1]
    assert "| [table1_seen](pacer/table1_seen.md) | PACER is good | 0.75 | holds |  |" in ours
    assert "0 of " in page.split("### PACER claims", 1)[1].split("### PACER: our own checks")[0]
