"""What every playground's view shares: the message line, actions run under it, a cache, image output.

Why a message line and not exceptions: a person exploring clicks faster than they read; a refused
choice (a pair naming one terrain twice, a start inside an obstacle) must say in one line what is wrong
and leave the drawing as it was, and an unexpected failure must not bury the widgets under a traceback.
Why images (``ipywidgets.Image``) and not live matplotlib canvases: a result redraws in one message,
the same bytes show in JupyterLab, in papermill's executed notebook and in the browser test, which
compares them before and after a click.
"""

from __future__ import annotations

import html
import io
import statistics
import time
from collections import OrderedDict
from collections.abc import Callable, Hashable, Sequence
from pathlib import Path
from typing import Any, Literal

import ipywidgets as widgets
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.image import imsave

from navlab.core.io import DataError
from navlab.core.params import ParamsError

Kind = Literal["info", "progress", "error"]
ERROR_MARK = "✗"  # leads every refused or failed action's line (the browser test looks for it)
COLOURS = {"info": "#1b5e20", "progress": "#555555", "error": "#b71c1c"}


def require_built(needed: Sequence[tuple[str, Path]], profile: str, data_dir: str | Path,
                   artifacts_dir: str | Path) -> None:
    """Before a playground loads anything: every (stage, output) it reads, in build order; the missing ones
    named at once, as one DataError line with the one command that builds them (this profile and these
    folders), and the smoke path (minutes) for a first look. Loading one at a time named them one per try."""
    missing = list(dict.fromkeys(stage for stage, path in needed if not Path(path).exists()))
    if not missing:
        return
    only = " ".join(f"--only {stage}" for stage in missing)
    smoke = "artifacts/smoke"
    raise DataError(
        f"this playground needs {', '.join(missing)} (profile {profile}, not in {artifacts_dir}): build them with "
        f"`python -m navlab artifacts build --profile {profile} --data-dir {data_dir} --artifacts-dir "
        f"{artifacts_dir} {only}`; or, for a first look in minutes, the smoke profile: `python -m navlab data "
        f"build --profile smoke --data-dir {smoke}/data && python -m navlab artifacts build --profile smoke "
        f"--data-dir {smoke}/data --artifacts-dir {smoke} {only}`, then set profile = \"smoke\", data_dir = "
        f"\"{smoke}/data\", artifacts_dir = \"{smoke}\" in the parameters cell")


class UserError(ValueError):
    """A choice the playground cannot follow; its message is the whole explanation (shown as one line)."""


def one_line(err: BaseException) -> str:
    """``err`` as one line: a UserError's own message, anything else prefixed with its type."""
    text = str(err).strip().splitlines()[0] if str(err).strip() else ""
    return text if isinstance(err, UserError) else f"{type(err).__name__}: {text}".rstrip(": ")


class Memo:
    """Results by key, the ``size`` most recently used kept: a person flips back and forth (invert, invert
    again; map 3, map 4, map 3), and each revisit should redraw without recomputing."""

    def __init__(self, compute: Callable[..., Any], size: int = 32):
        self.compute, self.size = compute, size
        self.hits = self.misses = 0
        self._store: OrderedDict[Hashable, Any] = OrderedDict()

    def __call__(self, *key: Hashable) -> Any:
        if key in self._store:
            self.hits += 1
            self._store.move_to_end(key)
            return self._store[key]
        self.misses += 1
        value = self.compute(*key)
        self._store[key] = value
        if len(self._store) > self.size:
            self._store.popitem(last=False)
        return value


class MessageLine:
    """One line of text under a playground's controls; ``text`` and ``kind`` are what it shows now."""

    def __init__(self):
        self.widget = widgets.HTML()
        self.widget.add_class("navlab-playground-message")
        self.text, self.kind = "", "info"

    def show(self, text: str, kind: Kind = "info") -> None:
        self.text, self.kind = " ".join(text.split()), kind  # one line, whatever it was given
        shown = f"{ERROR_MARK} {self.text}" if kind == "error" else self.text
        self.widget.value = f'<span style="color:{COLOURS[kind]}">{html.escape(shown)}</span>'


class PlaygroundView:
    """Base of a playground's widgets. Subclasses give :meth:`draw` (state -> widgets) and
    :meth:`status` (the line shown after a successful action); every click goes through :meth:`act`."""

    # what the first action waits for, said while it waits (a fresh clone compiles numba code: minutes of a
    # silent "working …" otherwise); "" where nothing is compiled
    first_use = ""

    def __init__(self):
        self.message = MessageLine()
        self.warm = not self.first_use
        # wall and CPU time of the last action, drawing included (the benchmark reads them; CPU time is what
        # the wall time would be on an idle machine, whatever else shares the cores)
        self.last_ms = self.last_cpu_ms = 0.0

    def draw(self) -> None:
        raise NotImplementedError

    def status(self) -> str:
        return "done"

    def start_scenario(self, parameters: str, action: Callable[..., Any], *args: Any) -> None:
        """The notebook's scenario (its papermill parameters), taken as a click is; a refused one stops the
        run with one line naming the parameters (a ParamsError, which the notebook shows without a traceback)
        instead of leaving a later cell to fail on a state that never was."""
        if not self.warm:  # a cell's output while it runs: the message line is not on screen yet
            print(f"{self.first_use} …", flush=True)
        if not self.act(action, *args):
            raise ParamsError(f"notebook parameter {parameters}: {self.message.text}")

    def act(self, action: Callable[..., Any], *args: Any) -> bool:
        """Run ``action(*args)`` on the state, then redraw; False (and one line saying why) when it was
        refused or failed. Actions check their input before they change the state, so a refused one
        leaves the state and the drawing as they were."""
        start, cpu = time.perf_counter(), time.process_time()
        self.message.show("working …" if self.warm else f"working … ({self.first_use})", "progress")
        try:
            action(*args)
            self.draw()
            done = self.warm = True
        except Exception as err:  # noqa: BLE001 - a widget callback must never end in a traceback
            self.message.show(one_line(err), "error")
            done = False
        self.last_ms = 1000 * (time.perf_counter() - start)
        self.last_cpu_ms = 1000 * (time.process_time() - cpu)
        if done:
            self.message.show(f"{self.status()} ({self.last_ms:.0f} ms)")
        return done

    def button(self, description: str, action: Callable[..., Any], *args: Any, css: str = "",
               tooltip: str = "", width: str = "auto") -> widgets.Button:
        """A button whose click runs ``action(*args)`` through :meth:`act`; ``css`` is a class name for
        the browser test to find it by."""
        button = widgets.Button(description=description, tooltip=tooltip, layout=widgets.Layout(width=width))
        if css:
            button.add_class(css)
        button.on_click(lambda _: self.act(action, *args))
        return button


def figure_bytes(fig: Figure, fmt: Literal["png", "jpeg"] = "png", dpi: int = 80) -> bytes:
    """A matplotlib Figure (made with ``Figure()``, not pyplot, so no backend shows it twice) as image
    bytes. JPEG for large results: a photo-like map encodes in a third of PNG's time, at a fifth of its size."""
    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, dpi=dpi)
    return buf.getvalue()


def array_png(image: np.ndarray, scale: int = 1) -> bytes:
    """An (H, W, 3) float image in [0, 1] as PNG, each pixel repeated ``scale`` times (small patches
    stay sharp instead of blurred by the browser)."""
    image = np.clip(np.asarray(image, dtype=np.float32), 0.0, 1.0)
    image = np.repeat(np.repeat(image, scale, axis=0), scale, axis=1)
    buf = io.BytesIO()
    imsave(buf, image, format="png")
    return buf.getvalue()


def latency_line(label: str, times_ms: list[float], width: int = 28) -> str:
    """One line of a playground benchmark: median, 90th percentile and maximum of interaction times (ms),
    the figures issue 28's 1 s median is read against."""
    if not times_ms:
        return f"{label:{width}s} none"
    p90 = statistics.quantiles(times_ms, n=10, method="inclusive")[-1] if len(times_ms) > 1 else times_ms[0]
    return (f"{label:{width}s} median {statistics.median(times_ms):5.0f} ms   p90 {p90:5.0f} ms   "
            f"max {max(times_ms):5.0f} ms   ({len(times_ms)})")
