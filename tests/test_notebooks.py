"""Every notebook under notebooks/ runs under papermill with the smoke profile; none has outputs."""

import json

import pytest

from navlab.pipeline.notebooks import PARAMETERS, discover, run_notebook

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


@pytest.mark.notebook
@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_smoke_run(notebook, smoke_data, smoke_artifacts, tmp_path):
    reports = tmp_path / "reports"
    out = run_notebook(notebook, profile="smoke", output=tmp_path / "executed.ipynb", data_dir=smoke_data,
                       artifacts_dir=smoke_artifacts, reports_dir=reports, progress=False)
    assert out.is_file()
