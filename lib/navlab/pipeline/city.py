"""``python -m navlab city run``: a user's extract -> SuReNav test set -> Table I / Fig. 4 reports (docs/your_city.md).

Why here: the reports are written as the notebooks write theirs (``pipeline.reports.write_table``), which
the surenav layer may not import; the test set and the evaluation themselves are ``surenav.any_city``.

Layout: ``<out_root>/<name>/testset/`` (tiles, networks, superpixels, demonstrations, episodes,
``index.json``) and ``<out_root>/<name>/reports/surenav/`` (``table1_human_likeness`` and
``fig4_safety_efficiency`` JSON + Markdown, and ``figures/fig4_safety_efficiency.png``).
"""

from __future__ import annotations

import re
from pathlib import Path

from navlab.core.params import Params
from navlab.pipeline.reports import write_table
from navlab.surenav.any_city import DEFAULT_MAX_TILES, build_test_set, evaluate, load_test_set

OUT_ROOT = Path("cities")
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")


def check_name(name: str) -> str:
    """A name usable as a folder and a tile prefix, else one line naming it and the fix."""
    if not _NAME.fullmatch(name):
        raise ValueError(f"--name {name!r}: use letters, digits, '_', '.' or '-' (it names the folder "
                         f"{OUT_ROOT}/NAME and the tiles), starting with a letter or digit")
    return name


def run_city(extract: str | Path, name: str, params: Params, artifacts_dir: str | Path,
             out_root: str | Path = OUT_ROOT, max_tiles: int = DEFAULT_MAX_TILES, progress: bool = True) -> list[Path]:
    """Build (or resume) the test set of ``extract`` and write its Table I and Fig. 4 reports; returns the JSON
    reports and the figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from navlab.viz.surenav_benchmark import draw_safety_efficiency

    out = Path(out_root, check_name(name))
    build_test_set(extract, name, params, out / "testset", max_tiles)
    table1, fig4 = evaluate(load_test_set(out / "testset"), params, artifacts_dir, name, progress)
    reports = out / "reports"
    seeds = list(params.surenav.train.seeds)
    written = [write_table(reports, t, track="surenav", profile=params.profile, seeds=seeds) for t in (table1, fig4)]
    figure = reports / "surenav" / "figures" / "fig4_safety_efficiency.png"
    figure.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
    draw_safety_efficiency(ax, fig4.rows)
    fig.savefig(figure, dpi=120)
    plt.close(fig)
    return [*written, figure]
