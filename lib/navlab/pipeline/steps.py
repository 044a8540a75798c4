"""The build steps behind the pipeline's commands: ``data build`` and ``artifacts build``.

Why here: the stage registry (``navlab.pipeline.dvc_yaml``) derives each stage's code deps from the
step it runs, so the steps sit in the pipeline layer, below the CLI that dispatches to them.
"""

from __future__ import annotations


def data_steps():
    """The steps of ``data build``, in order; each writes under its own folder of data/."""
    from navlab.maps.dataset import build_maps
    from navlab.pipeline.sources import build_raw
    from navlab.surenav.experts import build_demos

    return [("raw", build_raw), ("maps", build_maps), ("demos", build_demos)]


def artifact_steps():
    """The artefact builders (DVC stage outputs under artifacts/), by name, in dependency order.

    Each is ``fn(params, data_dir, artifacts_dir)``; `dvc repro` runs them one stage each
    (``artifacts build --only NAME``) and the notebook smoke tests run them all for ``smoke``.
    """
    from navlab.hj.sweeps import build_sweep
    from navlab.pacer.artifacts import artifact_steps as pacer_steps
    from navlab.reach.brt_margin import build_brt_margins
    from navlab.reach.precompute import build_hj_grids
    from navlab.surenav.artifacts import artifact_steps as surenav_steps
    from navlab.surenav.context.artifacts import artifact_steps as context_steps
    from navlab.surenav.episodes import build_episodes

    return [
        ("hj_grids", build_hj_grids),
        ("hj_margins", build_brt_margins),  # reads hj_grids' static BRTs
        ("hj_sweep", build_sweep),  # issue 26's sensitivity points (one per queued experiment: pipeline.experiments)
        ("surenav_episodes", build_episodes),
        *pacer_steps(),  # pacer_phase1..3, pacer_sterling, pacer_classifier
        *surenav_steps(),  # surenav_estimator (GPS and MPNN-ablation seeds)
        *context_steps(),  # surenav_context_demos, surenav_context_estimator (issue 25's context benchmark)
    ]
