"""Issue 26's sensitivity curves: success rate (Wilson 95% band) of each row against one swept setting, one
panel per room or scenario (rows from ``hj.sensitivity``)."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt

from navlab.viz.hj_closed_loop import COLORS


def sensitivity_figure(rows: Sequence[dict], x: str, panel: str, xlabel: str, title: str, *, log_x: bool = False):
    """Success rate of each ``method`` against ``x``, one axes per value of ``panel``."""
    panels = sorted({r[panel] for r in rows})
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels), 3.4), squeeze=False, sharey=True)
    for ax, name in zip(axes[0], panels, strict=True):
        for method in dict.fromkeys(r["method"] for r in rows):
            pts = sorted((r[x], r["success_rate"], r["success_rate_ci"]) for r in rows
                         if r[panel] == name and r["method"] == method)
            xs = [p[0] for p in pts]
            color = COLORS.get(method)
            ax.plot(xs, [p[1] for p in pts], "o-", color=color, label=method)
            ax.fill_between(xs, [p[2][0] for p in pts], [p[2][1] for p in pts], color=color, alpha=0.15)
        if log_x:
            ax.set_xscale("log")
        ax.set(title=name, xlabel=xlabel, ylim=(-0.03, 1.03))
    axes[0][0].set_ylabel("success rate")
    axes[0][-1].legend(fontsize=8, loc="lower right")
    fig.suptitle(title)
    fig.tight_layout()
    return fig
