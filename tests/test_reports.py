import json

from navlab.core.reports import read_table, write_index, write_table


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
