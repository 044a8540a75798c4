"""Every notebook under notebooks/ follows the parameters convention, runs under papermill with the smoke
profile and writes every report its dvc.yaml stage declares, each valid under the report contract."""

import json
import re
from pathlib import Path

import nbformat
import pytest
import yaml

from navlab.pipeline.notebooks import PARAMETERS_CELL, RESOLVE_LINES, discover, run_notebook
from navlab.pipeline.reports import read_table
from navlab.viz.playground import is_playground

NOTEBOOKS = discover()


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_committed_without_outputs(notebook):
    cells = json.loads(notebook.read_text())["cells"]
    assert not any(c.get("outputs") or c.get("execution_count") for c in cells), "strip outputs (nbstripout)"


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_parameters_convention(notebook):
    """The parameters cell leaves every folder to resolve_parameters, so Run All works from JupyterLab. A
    playground's parameters cell may go on with its default scenario (what papermill runs headlessly)."""
    cells = nbformat.read(notebook, as_version=4).cells
    tagged = [i for i, c in enumerate(cells) if "parameters" in c.metadata.get("tags", [])]
    assert len(tagged) == 1, f"{notebook}: tag exactly one cell 'parameters' (it has {len(tagged)})"
    i = tagged[0]
    how = (f"{notebook}: the cell tagged 'parameters' must read exactly\n{PARAMETERS_CELL}\nand the next cell "
           f"must be a code cell reading exactly\n{RESOLVE_LINES}\n(navlab.pipeline.notebooks; docs/notebooks.md)")
    source = cells[i].source.strip()
    assert source == PARAMETERS_CELL or (is_playground(notebook) and source.startswith(PARAMETERS_CELL + "\n")), how
    assert i + 1 < len(cells) and cells[i + 1].cell_type == "code", how
    assert cells[i + 1].source.strip() == RESOLVE_LINES, how


def declared_reports(notebook) -> list[str]:
    """The report JSONs (paths under reports/) that the notebook's dvc.yaml stage lists as metrics (none for
    a playground, which has no stage)."""
    if is_playground(notebook):
        return []
    stages = yaml.safe_load(Path("dvc.yaml").read_text(encoding="utf8"))["stages"]
    stage = next(s for s in stages.values() if f"notebook run {notebook.as_posix()}" in s["cmd"])
    paths = [next(iter(m)) if isinstance(m, dict) else m for m in stage.get("metrics", [])]
    return [p.removeprefix("reports/") for p in paths if p.startswith("reports/")]


def check_report(path: Path, profile: str) -> None:
    """The report contract (docs/design.md): required keys, rows within the columns, numbers or null, every
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


def upstream_notebooks(notebook) -> list[Path]:
    """The notebooks whose reports the notebook's dvc.yaml stage reads (the sensitivity curves read Table VI's
    own points from its report): a smoke run runs them first into the same reports folder."""
    if is_playground(notebook):
        return []
    stages = yaml.safe_load(Path("dvc.yaml").read_text(encoding="utf8"))["stages"].values()
    made_by = {next(iter(m)) if isinstance(m, dict) else m: Path(s["cmd"].split("notebook run ")[-1])
               for s in stages if "notebook run " in s["cmd"] for m in s.get("metrics", [])}
    deps = next(s["deps"] for s in stages if f"notebook run {notebook.as_posix()}" in s["cmd"])
    return [made_by[d] for d in deps if d in made_by]


@pytest.mark.notebook
@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_smoke_run(notebook, smoke_data, smoke_artifacts, tmp_path):
    reports = tmp_path / "reports"
    for upstream in upstream_notebooks(notebook):
        run_notebook(upstream, profile="smoke", output=tmp_path / f"{upstream.stem}.ipynb", data_dir=smoke_data,
                     artifacts_dir=smoke_artifacts, reports_dir=reports, progress=False)
    out = run_notebook(notebook, profile="smoke", output=tmp_path / "executed.ipynb", data_dir=smoke_data,
                       artifacts_dir=smoke_artifacts, reports_dir=reports, progress=False)
    assert out.is_file()
    for declared in declared_reports(notebook):  # every table its dvc stage promises, valid
        assert (reports / declared).is_file(), f"{notebook} did not write {declared} (declared in dvc.yaml)"
        check_report(reports / declared, "smoke")


def _needs_artifacts(notebook) -> bool:
    """Does the notebook's dvc.yaml stage depend on an artefact (HJ grids, trained models)? Every playground
    explores trained artefacts."""
    if is_playground(notebook):
        return True
    stages = yaml.safe_load(Path("dvc.yaml").read_text(encoding="utf8"))["stages"].values()
    deps = next(s["deps"] for s in stages if notebook.as_posix() in s["deps"])
    return any(d.startswith("artifacts/") for d in deps)


@pytest.mark.notebook
@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=str)
def test_missing_input_names_the_command_in_one_line(notebook, smoke_data, tmp_path):
    """Before `make repro` has built an artefact (or data/), the notebook stops with the command that builds it,
    and the kept executed notebook (``*.failed.ipynb``) shows it as a one-line error output."""
    import nbformat

    from navlab.core.io import DataError

    empty = tmp_path / "empty"
    artifacts = _needs_artifacts(notebook)
    with pytest.raises(DataError, match="failed in cell"):
        run_notebook(notebook, profile="smoke", output=tmp_path / "executed.ipynb",
                     data_dir=smoke_data if artifacts else empty, artifacts_dir=empty,
                     reports_dir=tmp_path / "reports", progress=False)
    executed = nbformat.read(tmp_path / "executed.failed.ipynb", as_version=4)
    errors = [o for c in executed.cells if c.cell_type == "code" for o in c.get("outputs", []) if o.output_type == "error"]
    assert len(errors) == 1, f"{notebook}: {len(errors)} error outputs"
    error, message = errors[0], errors[0].evalue
    assert error.ename == "DataError", f"{notebook}: {error.ename}: {message}"
    assert str(empty) in message
    # an artefact: the one command for every missing stage (a playground names the profile and folders too)
    assert re.search(r"`python -m navlab artifacts build (--profile smoke --data-dir \S+ --artifacts-dir \S+ )?--only "
                     if artifacts else r"`python -m navlab data build", message), message
    assert error.traceback == [f"DataError: {message}"]  # the error output: one line, no traceback


@pytest.mark.notebook
def test_a_bad_profile_given_to_papermill_is_one_line(tmp_path):
    """`papermill notebooks/00_quickstart.ipynb o.ipynb -p profile nope` (issue 63): the error output names
    the value and the profiles in one line, no traceback (the display is installed before the profile loads)."""
    import nbformat
    import papermill

    source = Path("notebooks/00_quickstart.ipynb").resolve()
    with pytest.raises(papermill.PapermillExecutionError):
        papermill.execute_notebook(str(source), str(tmp_path / "o.ipynb"), parameters={"profile": "nope"},
                                   cwd=str(source.parent), kernel_name="python3", progress_bar=False)
    executed = nbformat.read(tmp_path / "o.ipynb", as_version=4)
    (error,) = [o for c in executed.cells if c.cell_type == "code" for o in c.get("outputs", [])
                if o.output_type == "error"]
    assert error.ename == "ParamsError" and "nope" in error.evalue and "smoke" in error.evalue
    assert error.traceback == [f"ParamsError: {error.evalue}"]
