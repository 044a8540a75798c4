"""Each paper's claims registry (issue 58): every claim quoted verbatim from the paper's text, where it
stands, and decided by the report it names (or listed as not tested, with the reason); every paper claim a
committed report carries comes from its registry, word for word."""

import re
from pathlib import Path

import pytest

from navlab.pipeline.reports import read_table
from navlab.pipeline.results import claims_of, papers, registries

PAPER_TEXTS = Path(__file__).resolve().parents[2] / "shared" / "papers"  # beside the checkout, not in it
PAPER_FILES = {"surenav": "surenav.md", "hj": "hj_reachability_search.md", "pacer": "pacer.md"}
REPORTS = Path("reports")
REGISTRIES = registries()


def _normal(text: str) -> str:
    return re.sub(r"\s+", " ", text).strip().lower()


def test_every_registry_is_a_papers_with_its_text_named():
    # the stack (ours) is a track with no paper text and no registry: no claim of a paper is decided there
    assert set(REGISTRIES) == set(PAPER_FILES) and set(PAPER_FILES) <= set(papers())


@pytest.mark.parametrize("track", sorted(REGISTRIES))
def test_every_quote_appears_verbatim_in_the_papers_text(track):
    path = PAPER_TEXTS / PAPER_FILES[track]
    if not path.is_file():
        pytest.skip(f"{path} is not here (the papers sit beside the checkout, not in it)")
    text = _normal(path.read_text(encoding="utf8"))
    missing = [c.key for c in REGISTRIES[track].values() if _normal(c.quote) not in text]
    assert not missing, f"{track}: quotes not found verbatim in {path.name}: {missing}"


@pytest.mark.parametrize("track", sorted(REGISTRIES))
def test_every_registry_claim_is_decided_by_its_report_or_says_why_not(track):
    reports = {p.stem: read_table(p) for p in sorted((REPORTS / track).glob("*.json"))}
    for entry in REGISTRIES[track].values():
        assert entry.where and entry.quote, f"{track}/{entry.key}: where and quote"
        if entry.not_tested:
            continue
        assert entry.report in reports, f"{track}/{entry.key}: no committed report {entry.report!r}"
        keys = [c.key for c in claims_of(reports[entry.report])]
        assert entry.key in keys, f"{track}/{entry.key}: {entry.report} does not decide it (re-run its stage)"


@pytest.mark.parametrize("track", sorted(REGISTRIES))
def test_every_papers_claim_in_a_report_is_its_registrys_word_for_word(track):
    registry = REGISTRIES[track]
    for path in sorted((REPORTS / track).glob("*.json")):
        for claim in claims_of(read_table(path)):
            if claim.source == "ours":
                assert not claim.quote, f"{path}: our own check {claim.claim!r} quotes the paper"
                continue
            entry = registry.get(claim.key)
            assert entry is not None, f"{path}: {claim.claim!r} is not in the {track} registry"
            assert (claim.quote, claim.where, claim.paper) == (entry.quote, entry.where, entry.paper), path
