"""Run a notebook headlessly with papermill, the way `dvc repro`, the tests and a user all do.

Every navlab notebook has a papermill ``parameters`` cell with ``profile``, ``data_dir``,
``artifacts_dir`` and ``reports_dir``; paths are handed over absolute and the kernel starts in the
checkout root, so a notebook behaves the same from JupyterLab, the CLI or pytest.
"""

from __future__ import annotations

import os
from pathlib import Path

from navlab.core.io import DataError, atomic_path
from navlab.core.params import repo_root

PARAMETERS = ("profile", "data_dir", "artifacts_dir", "reports_dir")


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
    """Execute ``notebook`` with papermill; the executed copy goes to ``output`` (atomically)."""
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
                str(source), str(tmp), parameters=parameters, cwd=str(root), kernel_name="python3",
                progress_bar=progress, log_output=False,
            )
        except PapermillExecutionError as err:  # keep what ran: it shows the failing cell
            failed = output.with_suffix(".failed.ipynb")
            os.replace(tmp, failed)
            raise DataError(f"{notebook} failed in cell {err.exec_count} ({err.ename}: {err.evalue}); the executed "
                            f"notebook is kept at {failed}") from None
    return output
