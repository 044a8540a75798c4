"""Every notebook under notebooks/ runs under papermill with the smoke profile, writes every report its\ndvc.yaml stage declares, each valid under the report contract; none is committed with outputs."""

import json
from pathlib import Path

import pytest
import yaml

from navlab.pipeline.notebooks import PARAMETERS, discover, run_notebook
from navlab.pipeline.reports import read_table

NOTEBOOKS = discover()


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_committed_without_outputs_and_parameterised(notebook):
    cells = json.loads(notebook.read_text())["cells"]
    assert not any(c.get("outputs") or c.get("execution_count") for c in cells), "strip outputs (nbstripout)"
    tagged = [c for c in cells if "parameters" in c.get("metadata", {}).get("tags", [])]
    assert len(tagged) == 1, "exactly one cell tagged 'parameters'"
    source = "".join(tagged[0]["source"])
    for name in PARAMETERS:
        assert f"{name} =" in source, f"parameters cell lacks {name}"


def declared_reports(notebook) -> list[str]:
    """The report JSONs (paths under reports/) that the notebook's dvc.yaml stage lists as metrics."""
    stages = yaml.safe_load(Path("dvc.yaml").read_text(encoding="utf8"))["stages"]
    stage = next(s for s in stages.values() if f"notebook run {notebook.as_posix()}" in s["cmd"])
    paths = [next(iter(m)) if isinstance(m, dict) else m for m in stage.get("metrics", [])]
    return [p.removeprefix("reports/") for p in paths if p.startswith("reports/")]


def check_report(path: Path, profile: str) -> None:
    """The DESIGN.md report contract: required keys, rows within the columns, numbers or null, every
    ``<column>_ci`` an interval [lo, hi] (or null) beside its column, and a Markdown twin."""
    report = read_table(path)
    assert report["profile"] == profile and report["rows"], f"{path}: empty or from another profile"
    assert report["table_id"] == path.stem and path.with_suffix(".md").is_file()
    assert isinstance(report["notes"], str) and report["notes"].strip(), f"{path}: notes say what differs"
    for row in report["rows"] + report["paper"]:
        assert set(row) <= set(report["columns"]), f"{path}: row keys {sorted(row)} outside the columns"
        for column, value in row.items():
            if column.endswith("_ci"):
                assert column.removesuffix("_ci") in report["columns"], f"{path}: {column} has no column"
                assert value is None or (len(value) == 2 and value[0] <= value[1] + 1e-12), f"{path}: {column}={value}"
            else:
                assert value is None or isinstance(value, (str, int, float)), f"{path}: {column}={value!r}"


@pytest.mark.notebook
@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_smoke_run(notebook, smoke_data, smoke_artifacts, tmp_path):
    reports = tmp_path / "reports"
    out = run_notebook(notebook, profile="smoke", output=tmp_path / "executed.ipynb", data_dir=smoke_data,
                       artifacts_dir=smoke_artifacts, reports_dir=reports, progress=False)
    assert out.is_file()
    for declared in declared_reports(notebook):  # every table its dvc stage promises, valid
        assert (reports / declared).is_file(), f"{notebook} did not write {declared} (declared in dvc.yaml)"
        check_report(reports / declared, "smoke")
