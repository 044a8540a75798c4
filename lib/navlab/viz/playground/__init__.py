"""Interactive playgrounds (issue 28): ask a track "what if?" in JupyterLab without writing code.

Each playground is a notebook under ``notebooks/playground/`` that only builds a view from this package
and displays it. The state and every rule about what a person may choose live here, in plain classes
that the tests drive without a browser; the widgets (``ipywidgets``) only forward clicks to them.
Shared by every playground (:mod:`navlab.viz.playground.common`): a one-line message under the controls
(what was done and how long it took, or why a choice was refused, never a traceback), a small cache so
that going back to an earlier choice redraws at once, and PNG rendering of results, which the browser
test can compare before and after a click.

Playground notebooks reproduce no table, so no dvc stage runs them (``is_playground``); the smoke
notebook tests and the JupyterLab browser test run them like every other notebook.
"""

from __future__ import annotations

from pathlib import Path

NOTEBOOKS = Path("notebooks") / "playground"


def is_playground(notebook: str | Path) -> bool:
    """Is ``notebook`` (checkout-relative) an interactive playground, not a reproduction with a dvc stage?"""
    return Path(notebook).parent == NOTEBOOKS
