import json

from navlab.metrics.claims import Claim
from navlab.metrics.tables import Table
from navlab.pipeline.reports import read_table, write_table
from navlab.pipeline.results import claims_of, write_index


def test_table_round_trip_markdown_and_index(tmp_path):
    table = Table("table1_human_likeness", "SuReNav Table I", ["method", "frechet", "relaxation_iou"],
                  [{"method": "SuReNav", "frechet": 0.5, "relaxation_iou": float("nan")}],
                  [{"method": "SuReNav", "frechet": 0.334, "relaxation_iou": 0.416},
                   {"method": "COA*", "frechet": 0.6, "relaxation_iou": 0.1}], "smoke run",
                  claims=(Claim("SuReNav is closer to people", "does not hold", "0.5", quote="closer", where="Table I",
                                paper="0.334", why="smoke"),))
    path = write_table(tmp_path, table, track="surenav", profile="smoke", seeds=[0])
    report = read_table(path)
    assert report["rows"][0]["relaxation_iou"] is None  # a failed number is null, never made up
    assert report["metrics"] == {"SuReNav": {"frechet": 0.5, "relaxation_iou": None}}
    md = path.with_suffix(".md").read_text()
    assert "| SuReNav | **0.5** / 0.334 | **—** / 0.416 |" in md
    assert "| COA* | **not run** / 0.6 | **not run** / 0.1 |" in md
    index = write_index(tmp_path).read_text()
    assert "SuReNav Table I" in index and "surenav/table1_human_likeness.md" in index
    json.loads(path.read_text())
    assert claims_of(report) == list(table.claims)  # typed in the JSON, read back as written
    assert "| SuReNav is closer to people | 0.334 | 0.5 | **does not hold** | smoke |" in md


def test_rows_with_the_same_key_are_an_error_not_a_lost_row(tmp_path):
    import pytest

    rows = [{"method": "A*", "eps": 1.0, "cost": 3.0}, {"method": "A*", "eps": 2.0, "cost": 2.5}]
    with pytest.raises(ValueError, match="two rows share the key {'method': 'A\\*'}"):
        write_table(tmp_path, Table("t", "x", ["method", "eps", "cost"], rows, [], ""),
                    track="hj", profile="smoke", seeds=[0])
    assert not (tmp_path / "hj").exists()


def test_index_lists_every_design_table_without_a_report(tmp_path):
    write_table(tmp_path, Table("table1_seen", "PACER Table I", ["method", "low"], [{"method": "PACER", "low": 0.3}], [], ""),
                track="pacer", profile="smoke", seeds=[0])
    index = write_index(tmp_path).read_text()
    pending = index.split("## Not reproduced yet", 1)[1]
    assert "`pacer/table1_seen`" not in pending and "`pacer/table2_unseen`" in pending
    assert "`surenav/table1_human_likeness`" in pending and "`hj/table9_humans`" in pending


def _report(value, ci=None, other=0.5):
    row = {"method": "PACER", "low": value, "high": other}
    if ci is not None:
        row["low_ci"] = ci
    return {"table_id": "t", "columns": ["method", "low", "low_ci", "high"], "rows": [row], "paper": []}


def test_diff_flags_numbers_outside_their_interval_and_any_change_without_one():
    from navlab.pipeline.report_diff import diff_reports

    assert diff_reports(_report(0.33, [0.30, 0.36]), _report(0.34, [0.31, 0.37])) == []  # inside both
    moved = diff_reports(_report(0.3336, [0.32, 0.34]), _report(0.30, [0.28, 0.31]))
    assert [(m.column, m.interval) for m in moved] == [("low", (0.32, 0.34))]
    moved = diff_reports(_report(0.3), _report(0.3, other=0.6))  # no interval: any change is shown
    assert [(m.row, m.column, m.interval) for m in moved] == [("PACER", "high", None)]
    assert "0.5 -> 0.6 (changed; no interval)" in str(moved[0])
