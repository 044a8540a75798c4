"""``python -m navlab params check``: does each profile of params.yaml *fit*, before hours are spent on it?

Loading params.yaml already checks every key's type and range and the rules tying keys of different
sections together (navlab.core.params.constraints: aerial maps no larger than the test maps they are
cut from, batches no larger than what they are drawn from). This dry-runs the shapes of each stage on
the CPU in seconds, without data/ and without training (issue 23 item 4, issue 24 item 6): it exists
because the ``gpu`` profile once trained for ~2 h and then stopped at the tables (its 512-px aerial
maps did not fit in the 500-px SuReNav test maps). Each check calls the code that would fail at run
time on stand-in inputs (models on the ``meta`` device: shapes, no memory; the validations the stages
themselves run), and compares memory estimates with the budget of the machine the profile targets.
The one real input it reads: the photographs of your own that ``pacer.data`` lists (``terrain_photos/``,
in git), each checked as the bank will read it.

The checks live with their tracks (each manifest's ``profile_checks``, e.g. ``navlab.pacer.profile_check``):
each covers one stage family and returns one line per problem, naming the params key; it may append what it
measured to ``notes`` (parameter counts, sizes, memory). The budgets are ``navlab.core.budgets``.
"""

from __future__ import annotations

import navlab.tracks
from navlab.core.params import Params
from navlab.core.track import resolve


def check_profile(params: Params) -> tuple[list[str], list[str]]:
    """(problems, notes) of one loaded profile, every stage family checked.

    On one torch thread (restored after): the few CPU ops are tiny, and on a shared 2-core machine two
    OpenMP threads spinning against other jobs made the three-node SuReNav forward 0.7 s instead of 3 ms.
    """
    import torch

    problems: list[str] = []
    notes: list[str] = []
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        for check in (resolve(ref) for track in navlab.tracks.TRACKS for ref in track.profile_checks):
            problems += check(params, notes)
    finally:
        torch.set_num_threads(threads)
    return problems, notes
