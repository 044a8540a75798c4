"""Artefact steps of SuReNav's context benchmark (issue 25, steps 2-3): ``surenav_context_demos``
(``dataset``: the context demonstrations on real train / validation tiles and the test tiles) and
``surenav_context_estimator`` (``training``: the estimator trained on them)."""

from __future__ import annotations

from navlab.surenav.context.dataset import build_context_demos
from navlab.surenav.context.training import build_context_estimators


def artifact_steps() -> list:
    """(name, fn(params, data_dir, artifacts_dir)), in dependency order."""
    return [("surenav_context_demos", build_context_demos), ("surenav_context_estimator", build_context_estimators)]
