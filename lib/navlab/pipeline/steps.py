"""The build steps behind the pipeline's commands: ``data build`` and ``artifacts build``.

Why here: the stage registry (``navlab.pipeline.dvc_yaml``) derives each stage's code deps from the
step it runs, so the steps sit in the pipeline layer, below the CLI that dispatches to them.
"""

from __future__ import annotations


def data_steps():
    """The steps of ``data build``, in order; each writes under its own folder of data/: the real inputs and
    the maps, then each track's own (its manifest's ``data_steps``: SuReNav's demonstrations)."""
    from navlab.maps.dataset import build_maps
    from navlab.pipeline.sources import build_raw

    return [("raw", build_raw), ("maps", build_maps), *_tracks_steps("data_steps")]


def artifact_steps():
    """The artefact builders (DVC stage outputs under artifacts/), by name: every track's, each track's in
    its dependency order (its manifest's ``steps`` provider, ``navlab.tracks.TRACKS``).

    Each is ``fn(params, data_dir, artifacts_dir)``; `dvc repro` runs them one stage each
    (``artifacts build --only NAME``) and the notebook smoke tests run them all for ``smoke``.
    """
    return _tracks_steps("steps")


def _tracks_steps(provider: str) -> list:
    """Every track's steps from its manifest's ``provider`` field (a reference to a function returning them),
    in ``navlab.tracks.TRACKS`` order (read when called, so a track added there reaches the build)."""
    import navlab.tracks
    from navlab.core.track import resolve

    return [step for track in navlab.tracks.TRACKS if getattr(track, provider)
            for step in resolve(getattr(track, provider))()]
