"""What a paper track declares about itself: the manifest the pipeline reads (issue 62).

Why a manifest: a track used to be registered by hand in about seven central places (the stage list, the
build steps, the results page's papers, figures and headline rows, the claims registries, `params check`),
none of which the track's own package mentioned, so a missing entry showed only as a failing test or a
results page without a headline. Now each track package holds one ``track.py`` with a :class:`Track`, the
list ``navlab.tracks.TRACKS`` names each once, and ``navlab.pipeline`` iterates over that list.

A manifest is data. Code it points to (artefact builders, profile checks, the claims registry) is named
by a dotted reference, ``"package.module:function"`` or a module name, and imported only where it is
used: the results page's stage depends on the manifests it reads, and importing a track's training code
there would make every training change re-index the page.
"""

from __future__ import annotations

import dataclasses
from importlib import import_module
from typing import Any


@dataclasses.dataclass(frozen=True)
class Paper:
    name: str
    title: str
    link: str


@dataclasses.dataclass(frozen=True)
class Stage:
    """One DVC stage: what the code cannot derive. Notebook stages also depend on their notebook."""

    name: str
    cmd: str
    params: tuple[str, ...]
    inputs: tuple[str, ...] = ()      # data and artefacts the command reads (outputs of other stages)
    outs: tuple[str, ...] = ()        # DVC-cached outputs (but a figure the results page shows is committed)
    persist: tuple[str, ...] = ()     # outs holding a resumable checkpoint: kept while the command runs
    metrics: tuple[str, ...] = ()     # report JSONs, committed to git (cache: false)


def notebook_stage(name: str, path: str, params: tuple[str, ...], inputs: tuple[str, ...], outs: tuple[str, ...] = (),
                   metrics: tuple[str, ...] = ()) -> Stage:
    """A notebook stage: papermill runs ``path``; the executed copy is kept in artifacts/notebooks/."""
    executed = "artifacts/notebooks/" + path.removeprefix("notebooks/")
    return Stage(name, f"python -m navlab notebook run {path}", params, inputs, (executed, *outs), metrics=metrics)


def artifact_stage(name: str, params: tuple[str, ...], inputs: tuple[str, ...], outs: tuple[str, ...],
                   persist: bool = False) -> Stage:
    """An artefact stage: ``artifacts build --only NAME`` runs the builder a track's ``steps`` names NAME."""
    return Stage(name, f"python -m navlab artifacts build --only {name}", params, inputs, outs,
                 persist=outs if persist else ())


@dataclasses.dataclass(frozen=True)
class Figure:
    """A reproduced figure the results page shows: ``path`` under reports/ (a PNG or GIF, or an HTML scene the page
    links), its caption (with the paper's figure number), and the table it sits beside (``beside``, a table id;
    "" at the head of the paper's section)."""

    path: str
    caption: str
    beside: str = ""


Headline = tuple[str, tuple[str, ...], tuple[str, ...]]  # (table id, row key, columns) on the front door


@dataclasses.dataclass(frozen=True)
class Track:
    """One paper's place in the house. ``name`` is its package and its report folder (reports/<name>/)."""

    name: str
    paper: Paper
    stages: tuple[Stage, ...]
    # the artefact builders' provider: returns [(stage name, fn(params, data_dir, artifacts_dir))], in order
    steps: str = ""
    # the data build's steps of this track, after the house's raw inputs and maps: [(folder, fn(params, data_dir))]
    data_steps: str = ""
    claims: str = ""  # the module holding the paper's claims registry (CLAIMS)
    figures: tuple[Figure, ...] = ()  # the first is also the front door's; the stage that draws each commits it
    headline: tuple[Headline, ...] = ()
    before: tuple[str, ...] = ()  # reports the page shows before the paper's first table (figures it reads first)
    shown: tuple[tuple[str, tuple[str, ...]], ...] = ()  # (table id, columns) where the paper prints no table
    profile_checks: tuple[str, ...] = ()  # fn(params, notes) -> problems, run by `params check` on every profile
    plots: tuple[tuple[str, str, tuple[str, ...], str], ...] = ()  # training curves: (file, x, y columns, title)


def resolve(reference: str) -> Any:
    """The object ``"package.module:attribute"`` names (a module for a plain module name)."""
    module, _, attribute = reference.partition(":")
    found = import_module(module)
    return getattr(found, attribute) if attribute else found
