"""Notebook parameters and headless runs: the same notebook works in JupyterLab, papermill and `dvc repro`.

Every navlab notebook starts with a papermill ``parameters`` cell that leaves all four parameters
``None`` (``PARAMETERS_CELL``) and a next code cell whose first lines resolve them
(``RESOLVE_LINES``). ``None`` means "the interactive default": an environment variable
(``ENVIRONMENT``) if set, else the checkout's own folder found from ``params.yaml`` (``repo_root``), so
Run All in JupyterLab works whatever folder the kernel starts in (JupyterLab starts it in the
notebook's folder). A value papermill passes (``run_notebook``: absolute paths) always wins.
"""

from __future__ import annotations

import os
from pathlib import Path

from navlab.core.io import DataError, atomic_path
from navlab.core.params import PROFILES, ParamsError, load_params, repo_root

PARAMETERS = ("profile", "data_dir", "artifacts_dir", "reports_dir")
ENVIRONMENT = {
    "profile": "NAVLAB_PROFILE",
    "data_dir": "NAVLAB_DATA_DIR",
    "artifacts_dir": "NAVLAB_ARTIFACTS_DIR",
    "reports_dir": "NAVLAB_REPORTS_DIR",
}
PARAMETERS_CELL = """\
profile = None        # None: $NAVLAB_PROFILE, else the `profile` key of params.yaml
data_dir = None       # None: $NAVLAB_DATA_DIR, else <checkout>/data
artifacts_dir = None  # None: $NAVLAB_ARTIFACTS_DIR, else <checkout>/artifacts
reports_dir = None    # None: $NAVLAB_REPORTS_DIR, else <checkout>/reports"""
RESOLVE_LINES = """\
from navlab.pipeline.notebooks import resolve_parameters

profile, data_dir, artifacts_dir, reports_dir = resolve_parameters(profile, data_dir, artifacts_dir, reports_dir)"""


def resolve_parameters(
    profile: str | None = None,
    data_dir: str | Path | None = None,
    artifacts_dir: str | Path | None = None,
    reports_dir: str | Path | None = None,
) -> tuple[str, Path, Path, Path]:
    """The notebook's profile and absolute folders: given value, else ``$NAVLAB_*``, else the checkout's.

    Relative folders (given or from the environment) are taken from the checkout root, like the
    paths in dvc.yaml. In an IPython kernel, a DataError or ParamsError is then shown as its one-line
    message (which names the file and the command that builds it) instead of a long traceback: installed
    first, so that a bad ``profile`` given to papermill (``-p profile nope``) is one line too.
    """
    _show_input_errors_in_one_line()
    root = repo_root()
    given = {"data_dir": data_dir, "artifacts_dir": artifacts_dir, "reports_dir": reports_dir}
    folders = []
    for name, value in given.items():
        value = value if value is not None else os.environ.get(ENVIRONMENT[name]) or name.removesuffix("_dir")
        folders.append((root / Path(value).expanduser()).resolve())
    if profile is None and os.environ.get(ENVIRONMENT["profile"]):
        profile = os.environ[ENVIRONMENT["profile"]]
        if profile not in PROFILES:
            raise ParamsError(f"{ENVIRONMENT['profile']}={profile!r}: allowed profiles are {', '.join(PROFILES)}; "
                              f"unset it to use the `profile` key of params.yaml")
    profile = load_params(profile).profile
    return (profile, *folders)


def _show_input_errors_in_one_line() -> None:
    """In IPython, print a DataError / ParamsError as ``Name: message`` (the CLI's one line), no traceback."""
    try:
        from IPython import get_ipython
    except ImportError:
        return
    shell = get_ipython()
    if shell is None:
        return

    def one_line(shell, etype, value, tb, tb_offset=None):
        lines = [f"{etype.__name__}: {value}"]
        shell._showtraceback(etype, value, lines)  # the display hook ipykernel overrides (an error output)
        return lines

    shell.set_custom_exc((DataError, ParamsError), one_line)


def discover(root: str | Path | None = None) -> list[Path]:
    """Every notebook under notebooks/, relative to the checkout root, in a stable order."""
    root = Path(root) if root is not None else repo_root()
    return sorted(p.relative_to(root) for p in (root / "notebooks").rglob("*.ipynb")
                  if ".ipynb_checkpoints" not in p.parts)


def run_notebook(
    notebook: str | Path,
    *,
    profile: str,
    output: str | Path | None = None,
    data_dir: str | Path = "data",
    artifacts_dir: str | Path = "artifacts",
    reports_dir: str | Path = "reports",
    progress: bool = True,
) -> Path:
    """Execute ``notebook`` with papermill; the executed copy goes to ``output`` (atomically).

    The kernel starts in the notebook's own folder, as JupyterLab starts it, so every headless run
    also checks that the notebook does not depend on the working directory.
    """
    import papermill
    from papermill.exceptions import PapermillExecutionError

    root = repo_root()
    notebook = Path(notebook)
    source = notebook if notebook.is_absolute() else root / notebook
    if not source.is_file() or source.suffix != ".ipynb":
        raise DataError(f"{notebook}: no such notebook (a .ipynb file); list them with `ls notebooks/`")
    rel = source.relative_to(root / "notebooks") if source.is_relative_to(root / "notebooks") else Path(source.name)
    output = Path(output) if output is not None else Path(artifacts_dir) / "notebooks" / rel
    parameters = {
        "profile": profile,
        "data_dir": os.path.abspath(data_dir),
        "artifacts_dir": os.path.abspath(artifacts_dir),
        "reports_dir": os.path.abspath(reports_dir),
    }
    with atomic_path(output, suffix=".ipynb") as tmp:
        try:
            papermill.execute_notebook(
                str(source), str(tmp), parameters=parameters, cwd=str(source.parent), kernel_name="python3",
                progress_bar=progress, log_output=False,
            )
        except PapermillExecutionError as err:  # keep what ran: it shows the failing cell
            failed = output.with_suffix(".failed.ipynb")
            os.replace(tmp, failed)
            raise DataError(f"{notebook} failed in cell {err.exec_count} ({err.ename}: {err.evalue}); the executed "
                            f"notebook is kept at {failed}") from None
    return output
