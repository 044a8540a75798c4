import json

from navlab.pipeline.reports import read_table, write_index, write_table


def test_table_round_trip_markdown_and_index(tmp_path):
    path = write_table(
        tmp_path, "surenav", "table1_human_likeness", paper_ref="SuReNav Table I", profile="smoke", seeds=[0],
        columns=["method", "frechet", "relaxation_iou"],
        rows=[{"method": "SuReNav", "frechet": 0.5, "relaxation_iou": float("nan")}],
        paper_rows=[{"method": "SuReNav", "frechet": 0.334, "relaxation_iou": 0.416},
                    {"method": "COA*", "frechet": 0.6, "relaxation_iou": 0.1}],
        notes="smoke run",
    )
    report = read_table(path)
    assert report["rows"][0]["relaxation_iou"] is None  # a failed number is null, never made up
    assert report["metrics"] == {"SuReNav": {"frechet": 0.5, "relaxation_iou": None}}
    md = path.with_suffix(".md").read_text()
    assert "| SuReNav | **0.5** / 0.334 | **—** / 0.416 |" in md
    assert "| COA* | **not run** / 0.6 | **not run** / 0.1 |" in md
    index = write_index(tmp_path).read_text()
    assert "SuReNav Table I" in index and "surenav/table1_human_likeness.md" in index
    json.loads(path.read_text())


def test_rows_with_the_same_key_are_an_error_not_a_lost_row(tmp_path):
    import pytest

    rows = [{"method": "A*", "eps": 1.0, "cost": 3.0}, {"method": "A*", "eps": 2.0, "cost": 2.5}]
    with pytest.raises(ValueError, match="two rows share the key {'method': 'A\\*'}"):
        write_table(tmp_path, "hj", "t", paper_ref="x", profile="smoke", seeds=[0], columns=["method", "eps", "cost"],
                    rows=rows, paper_rows=[], notes="")
    assert not (tmp_path / "hj").exists()
