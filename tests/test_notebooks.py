"""Every notebook under notebooks/ follows the parameters convention and runs under papermill (smoke)."""

import json
from pathlib import Path

import nbformat
import pytest
import yaml

from navlab.pipeline.notebooks import PARAMETERS_CELL, RESOLVE_LINES, discover, run_notebook

NOTEBOOKS = discover()


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_committed_without_outputs(notebook):
    cells = json.loads(notebook.read_text())["cells"]
    assert not any(c.get("outputs") or c.get("execution_count") for c in cells), "strip outputs (nbstripout)"


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_parameters_convention(notebook):
    """The parameters cell leaves every folder to resolve_parameters, so Run All works from JupyterLab."""
    cells = nbformat.read(notebook, as_version=4).cells
    tagged = [i for i, c in enumerate(cells) if "parameters" in c.metadata.get("tags", [])]
    assert len(tagged) == 1, f"{notebook}: tag exactly one cell 'parameters' (it has {len(tagged)})"
    i = tagged[0]
    how = (f"{notebook}: the cell tagged 'parameters' must read exactly\n{PARAMETERS_CELL}\nand the next cell "
           f"must be a code cell reading exactly\n{RESOLVE_LINES}\n(navlab.pipeline.notebooks; see README, Notebooks)")
    assert cells[i].source.strip() == PARAMETERS_CELL, how
    assert i + 1 < len(cells) and cells[i + 1].cell_type == "code", how
    assert cells[i + 1].source.strip() == RESOLVE_LINES, how


@pytest.mark.notebook
@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_smoke_run(notebook, smoke_data, smoke_artifacts, tmp_path):
    reports = tmp_path / "reports"
    out = run_notebook(notebook, profile="smoke", output=tmp_path / "executed.ipynb", data_dir=smoke_data,
                       artifacts_dir=smoke_artifacts, reports_dir=reports, progress=False)
    assert out.is_file()


def _needs_artifacts(notebook) -> bool:
    """Does the notebook's dvc.yaml stage depend on an artefact (HJ grids, trained models)?"""
    stages = yaml.safe_load(Path("dvc.yaml").read_text(encoding="utf8"))["stages"].values()
    deps = next(s["deps"] for s in stages if notebook.as_posix() in s["deps"])
    return any(d.startswith("artifacts/") for d in deps)


@pytest.mark.notebook
@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_missing_input_names_the_command_in_one_line(notebook, smoke_data, tmp_path):
    """Before `make repro` has built an artefact (or data/), the notebook stops with the command that builds it."""
    from papermill.exceptions import PapermillExecutionError

    empty = tmp_path / "empty"
    artifacts = _needs_artifacts(notebook)
    with pytest.raises(PapermillExecutionError) as err:
        run_notebook(notebook, profile="smoke", output=tmp_path / "executed.ipynb",
                     data_dir=smoke_data if artifacts else empty, artifacts_dir=empty,
                     reports_dir=tmp_path / "reports", progress=False)
    message = err.value.evalue
    assert err.value.ename == "DataError", f"{notebook}: {err.value.ename}: {message}"
    assert str(empty) in message
    assert ("`python -m navlab artifacts build --only " if artifacts else "`python -m navlab data build") in message
    assert err.value.traceback == [f"DataError: {message}"]  # the error output: one line, no traceback
