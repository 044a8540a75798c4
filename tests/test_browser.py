"""Notebooks run top to bottom in JupyterLab, started as `make lab` starts it, driven in Chromium.

What a person does: open the notebook in JupyterLab, Run > Run All Cells, wait for the kernel to go idle.
Which notebooks: those whose outputs only a browser can check (ipympl canvases, meshcat and other HTML
scenes, widgets, Markdown the kernel renders), the quickstart (the front door), and each playground
through its click test; a notebook with tables and static figures only runs its cells in the same kernel
under papermill (tests/test_notebooks.py, every notebook), so a second run here checked nothing new and
cost about 25 s each on the 2-core CI machine. The smoke profile and the smoke dataset/artefacts
(conftest fixtures) reach the interactive kernel through the environment variables that
``resolve_parameters`` reads ($NAVLAB_PROFILE, ...). The test fails on any error output and on a figure
that did not render, and leaves one screenshot per notebook in .screenshots/browser/ (gitignored). A tiny
notebook that raises checks that an error is caught. Chromium is Debian's (`apt-get install -y chromium`;
.ci/run installs it), launched by Playwright; without it the tests skip and say so.
"""

from __future__ import annotations

import contextlib
import json
import os
import secrets
import signal
import subprocess
import time
import urllib.request
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import nbformat
import pytest

import navlab
from navlab.cli import lab_command
from navlab.core.params import repo_root
from navlab.pipeline.notebooks import ENVIRONMENT, PARAMETERS_CELL, RESOLVE_LINES, discover
from navlab.viz.playground import NOTEBOOKS as PLAYGROUNDS
from navlab.viz.playground.common import ERROR_MARK

if TYPE_CHECKING:
    from playwright.sync_api import Page

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync"]
SCREENSHOTS = repo_root() / ".screenshots" / "browser"
STALL_S = 900  # hang guard only (a smoke notebook takes seconds); not a speed limit
# A click's answer: seconds once numba's cache is written, but a click that reaches a compiled function with new
# argument types compiles it first (the HJ playground's first human: 2 min on an idle 2-core machine, more on a
# loaded one; CI of b9e2acf timed out at 120 s). A hang guard, not a speed limit.
CLICK_STALL_S = 600
# JupyterLab settings of the clean settings folder: no autosave (the checkout's notebooks stay as
# committed), no news / update checks (no network), and every cell laid out (windowing mode "none"): the
# default, "contentVisibility", skips laying out cells out of view, so a widget there has no box until a
# scroll renders it, and a click on it waited, on a loaded machine, for a box that never came (CI of
# 7e1c768: the SuReNav map's canvas "not visible" for 30 s, after three earlier scroll-first mends).
# What the tests check (outputs, figures, clicks answered) does not depend on how JupyterLab windows cells;
# `make lab` keeps JupyterLab's default.
LAB_SETTINGS = {
    "@jupyterlab/docmanager-extension/plugin.jupyterlab-settings": {"autosave": False},
    "@jupyterlab/notebook-extension/tracker.jupyterlab-settings": {"windowingMode": "none"},
    "@jupyterlab/apputils-extension/notification.jupyterlab-settings": {"fetchNews": "false",
                                                                        "checkForUpdates": False},
}
pytestmark = pytest.mark.browser


@dataclass
class LabRun:
    """What Run All left in one notebook: (ename, evalue) of each error output, figures, cells run."""

    notebook: str
    errors: list[tuple[str, str]] = field(default_factory=list)
    images: int = 0
    images_rendered: int = 0
    cells_run: int = 0
    code_cells: int = 0
    screenshot: Path | None = None
    seconds: dict[str, float] = field(default_factory=dict)  # page load, kernel start, Run All (printed)


def draws_figures(notebook: Path) -> bool:
    """Does the notebook plot (matplotlib or navlab.viz)? A table-only notebook has no figure to check."""
    source = notebook.read_text(encoding="utf8")
    return "plt." in source or "navlab.viz" in source


def check_clean(run: LabRun, figures: bool = True) -> None:
    """The pass criterion: no error output, every cell ran, and, where it plots, at least one figure and all of
    them drawn."""
    where = f"{run.notebook} in JupyterLab (screenshot: {run.screenshot})"
    assert not run.errors, f"{where}: error output " + "; ".join(f"{n}: {v}" for n, v in run.errors)
    assert run.cells_run == run.code_cells, f"{where}: only {run.cells_run} of {run.code_cells} code cells ran"
    assert run.images > 0 or not figures, f"{where}: no figure in the outputs"
    assert run.images_rendered == run.images, f"{where}: {run.images - run.images_rendered} figures not drawn"


@pytest.fixture(scope="module")
def browser():
    if not os.access(CHROMIUM, os.X_OK):
        pytest.skip(f"{CHROMIUM} not found: install Debian's Chromium (`apt-get install -y chromium`, as .ci/run "
                    "does) to run the JupyterLab browser tests")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.skip("playwright is not installed: `pip install -r environment.txt` (make setup)")
    with sync_playwright() as pw:
        chromium = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_FLAGS, headless=True)
        try:
            yield chromium
        finally:
            chromium.close()


@contextlib.contextmanager
def jupyter_lab(tmp: Path, env: dict[str, str], notebooks: Path | None = None):
    """`make lab`'s command on a free loopback port with a fresh token and clean Jupyter folders; yields its URL."""
    token = secrets.token_hex(16)
    dirs = {name: tmp / name for name in ("config", "data", "runtime", "ipython", "settings", "workspaces",
                                          "checkpoints")}
    for folder in dirs.values():
        folder.mkdir(parents=True)
    for rel, settings in LAB_SETTINGS.items():
        (dirs["settings"] / rel).parent.mkdir(parents=True, exist_ok=True)
        (dirs["settings"] / rel).write_text(json.dumps(settings))
    lib = str(Path(navlab.__file__).resolve().parents[1])  # this checkout's library, in the kernels too
    env = {**os.environ, **env, "JUPYTER_CONFIG_DIR": str(dirs["config"]), "JUPYTER_DATA_DIR": str(dirs["data"]),
           "JUPYTER_RUNTIME_DIR": str(dirs["runtime"]), "IPYTHONDIR": str(dirs["ipython"]),
           "PYTHONPATH": os.pathsep.join([lib, *filter(None, [os.environ.get("PYTHONPATH")])])}
    env.pop("MPLBACKEND", None)
    cmd = lab_command("--no-browser", "--ServerApp.port=0", f"--IdentityProvider.token={token}",
                      f"--LabApp.user_settings_dir={dirs['settings']}",
                      f"--LabApp.workspaces_dir={dirs['workspaces']}",
                      f"--FileCheckpoints.root_dir={dirs['checkpoints']}",  # no .ipynb_checkpoints/ in notebooks/
                      "--LabApp.expose_app_in_browser=True",  # window.jupyterapp: read the notebook model
                      notebooks=notebooks)
    log = (tmp / "lab.log").open("wb")
    proc = subprocess.Popen(cmd, cwd=repo_root(), env=env, stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True)
    url = None
    try:
        url = _wait_for_server(proc, token, dirs["runtime"], tmp / "lab.log")
        yield url, token
    finally:
        if url is not None:  # shut the kernels down cleanly, then the server
            with contextlib.suppress(OSError):
                _api(url, token, "shutdown", method="POST")
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        log.close()


def _api(url: str, token: str, path: str, method: str = "GET") -> bytes:
    req = urllib.request.Request(f"{url}api/{path}", method=method, headers={"Authorization": f"token {token}"})
    with urllib.request.urlopen(req, timeout=10) as response:
        return response.read()


def _wait_for_server(proc, token: str, runtime: Path, log: Path) -> str:
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise RuntimeError(f"jupyter lab exited ({proc.returncode}):\n{log.read_text()[-2000:]}")
        for info in runtime.glob("jpserver-*.json"):
            with contextlib.suppress(ValueError, OSError):
                url = json.loads(info.read_text())["url"]
                _api(url, token, "status")
                return url
        time.sleep(0.3)
    raise RuntimeError(f"jupyter lab did not start within 120 s:\n{log.read_text()[-2000:]}")


# The notebook panel's model, read through the app JupyterLab exposes: per code cell its execution
# count and outputs (types, error names, image outputs).
_STATE_JS = """() => {
  const nb = window.jupyterapp && window.jupyterapp.shell.currentWidget;
  if (!nb || !nb.content || !nb.sessionContext) return null;
  const kernel = nb.sessionContext.session && nb.sessionContext.session.kernel;
  const cells = nb.content.widgets.filter(c => c.model.type === 'code');
  return {
    windowing: nb.content.notebookConfig.windowingMode,
    kernel: kernel ? kernel.status : 'none',
    busy: cells.some(c => c.promptNode && c.promptNode.textContent.includes('*')),
    cells: cells.map(c => ({count: c.model.executionCount,
                            outputs: c.model.outputs.toJSON().map(o => ({type: o.output_type, ename: o.ename,
                              evalue: o.evalue, image: !!(o.data && o.data['image/png'])}))})),
  };
}"""


def run_all(browser, url: str, token: str, notebook: str, screenshot: Path,
            interact: Callable[[Page, LabRun], None] | None = None) -> LabRun:
    """Open ``notebook`` (path under the server's root) in a fresh page, Run All from the menu, wait, read back;
    then ``interact(page, run)`` (a playground's clicks) before the page closes."""
    page = browser.new_page(viewport={"width": 1400, "height": 1100})
    clock = [time.monotonic()]

    def lap():
        clock.append(time.monotonic())
        return round(clock[-1] - clock[-2], 1)

    try:
        page.goto(f"{url}lab/tree/{notebook}?reset&token={token}")
        page.wait_for_selector(".jp-NotebookPanel .jp-Cell", timeout=120_000)
        # JupyterLab's toasts (bottom right) would cover figures and swallow clicks; they stay in its
        # notification centre, unseen by the test either way
        page.add_style_tag(content=".Toastify__toast-container { display: none !important; }")
        load = lap()
        started = _wait(page, "s.kernel === 'idle'", 120)  # the kernel has started
        assert started["windowing"] == "none", f"JupyterLab ignored LAB_SETTINGS: windowing {started['windowing']}"
        kernel = lap()
        page.locator("#jp-menu-panel .lm-MenuBar-item", has_text="Run").first.click()
        page.locator('.lm-Menu-item[data-command="runmenu:run-all"]').click()
        # done: kernel idle, nothing queued, and every cell ran or one failed (Run All stops there)
        state = _wait(page, "s.kernel === 'idle' && !s.busy && (s.cells.every(c => c.count !== null) || "
                            "s.cells.some(c => c.outputs.some(o => o.type === 'error')))", STALL_S)
        run = LabRun(notebook, code_cells=len(state["cells"]),
                     cells_run=sum(c["count"] is not None for c in state["cells"]),
                     seconds={"page load": load, "kernel start": kernel, "Run All": lap()})
        for cell in state["cells"]:
            run.errors += [(o["ename"], o["evalue"]) for o in cell["outputs"] if o["type"] == "error"]
            run.images += sum(o["image"] for o in cell["outputs"])
        images = page.locator(".jp-OutputArea-output img:not(.widget-image)")  # figures; not a widget's images
        for i in range(images.count()):  # scrolled into view, as a reader sees each figure
            images.nth(i).scroll_into_view_if_needed()
            run.images_rendered += images.nth(i).evaluate("img => img.decode().then(() => img.naturalWidth > 0, "
                                                          "() => false)")
        failed = [i for i, c in enumerate(state["cells"]) if any(o["type"] == "error" for o in c["outputs"])]
        if failed:  # the screenshot shows the error, else the last figure
            page.locator(".jp-Notebook .jp-CodeCell").nth(failed[0]).scroll_into_view_if_needed()
        elif images.count():
            images.last.scroll_into_view_if_needed()
        run.screenshot = _screenshot(page, screenshot)
        if interact is not None:
            interact(page, run)
        return run
    except Exception:
        _screenshot(page, screenshot)  # what the page showed when it hung or broke
        raise
    finally:
        page.close()
        shut_down_kernels(url, token, notebook)


def shut_down_kernels(url: str, token: str, notebook: str) -> None:
    """Shut down the kernel of each session of ``notebook`` (closing the page leaves it running: one kernel per
    notebook opened, 21 at once on a fresh clone, until the server stopped)."""
    with contextlib.suppress(OSError):
        for session in json.loads(_api(url, token, "sessions")):
            if session.get("path") == notebook:
                _api(url, token, f"sessions/{session['id']}", method="DELETE")


def _screenshot(page, path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(path))
    return path


def _wait(page, condition: str, timeout_s: float) -> dict:
    """Poll the notebook state until ``condition`` (JS over ``s``) holds; a dead kernel fails at once."""
    deadline = time.monotonic() + timeout_s
    state = None
    while time.monotonic() < deadline:
        state = page.evaluate(_STATE_JS)
        if state is not None:
            assert state["kernel"] != "dead", "the kernel died"
            if page.evaluate(f"s => {condition}", state):
                return state
        time.sleep(0.5)
    raise AssertionError(f"notebook still running after {timeout_s} s (hang guard); last state {state}")


@pytest.fixture(scope="module")
def lab(tmp_path_factory, smoke_data, smoke_artifacts):
    """The checkout's JupyterLab; kernels get the smoke profile, data and artefacts and a temporary reports/."""
    tmp = tmp_path_factory.mktemp("lab")
    env = {ENVIRONMENT["profile"]: "smoke", ENVIRONMENT["data_dir"]: str(smoke_data),
           ENVIRONMENT["artifacts_dir"]: str(smoke_artifacts), ENVIRONMENT["reports_dir"]: str(tmp / "reports")}
    with jupyter_lab(tmp, env) as (url, token):
        yield url, token, tmp / "reports"


BROWSER_OUTPUTS = ("%matplotlib widget", "ipywidgets", "meshcat", "scene_html", "display(Markdown(")  # rendered by Lab


def needs_browser(notebook: Path) -> bool:
    """Run All in JupyterLab checks what papermill cannot where the notebook shows interactive output (or is the
    quickstart); the playgrounds are run, then clicked, by their own tests below."""
    if notebook.parent.name == "playground":
        return False
    source = notebook.read_text(encoding="utf8")
    return notebook.name == "00_quickstart.ipynb" or any(mark in source for mark in BROWSER_OUTPUTS)


def test_the_browser_runs_the_interactive_notebooks():
    """The selection is not empty and holds the notebooks with a meshcat scene (a regression guard on the rule)."""
    chosen = {p.as_posix() for p in discover() if needs_browser(p)}
    assert {"notebooks/00_quickstart.ipynb", "notebooks/hj/00_value_functions.ipynb", "notebooks/hj/04_rooms.ipynb"} <= chosen


@pytest.mark.notebook
@pytest.mark.parametrize("notebook", [p for p in discover() if needs_browser(p)], ids=str)
def test_run_all_in_jupyterlab(notebook, browser, lab):
    url, token, reports = lab
    before, folder = notebook.read_bytes(), sorted(notebook.parent.iterdir())
    rel = notebook.relative_to("notebooks").as_posix()
    run = run_all(browser, url, token, rel, SCREENSHOTS / rel.replace("/", "__").replace(".ipynb", ".png"))
    print(f"{notebook}: {run.seconds}")
    check_clean(run, draws_figures(notebook))
    assert notebook.read_bytes() == before, f"{notebook} was modified by the browser run"
    assert sorted(notebook.parent.iterdir()) == folder, f"the browser run wrote into {notebook.parent}"
    for table in reports.rglob("*.json"):  # the kernel ran the smoke profile it was given
        assert json.loads(table.read_text())["profile"] == "smoke", f"{table} not written with the smoke profile"


# A playground's drawn result: a digest of the bytes its <img> shows (a new value is a new blob URL).
# The drawn result image of the PACER and SuReNav playgrounds has loaded (a condition for ``wait_drawn``).
_RESULT_IMAGE_DRAWN = "{ const i = document.querySelector('img.navlab-result'); return i && i.naturalWidth > 0; }"
_RESULT_DIGEST_JS = """async () => {
  const img = document.querySelector('img.navlab-result');
  if (!img || !img.src) return null;
  const bytes = new Uint8Array(await (await fetch(img.src)).arrayBuffer());
  let h = 2166136261;
  for (const b of bytes) h = Math.imul(h ^ b, 16777619) >>> 0;
  return `${bytes.length}:${h}`;
}"""


def click_widget(page: Page, selector: str, nth: int = 0, redraws: bool = True) -> str | None:
    """A real click on a playground widget; waits for the kernel to answer (the result redrawn when
    ``redraws``, else the message line rewritten) and to go idle. The drawn result's digest after it."""
    before = page.evaluate(_RESULT_DIGEST_JS)
    message = page.locator(".navlab-playground-message").first.inner_text()
    page.locator(selector).nth(nth).click()
    deadline = time.monotonic() + CLICK_STALL_S
    while time.monotonic() < deadline:
        digest = page.evaluate(_RESULT_DIGEST_JS)
        if (digest != before) if redraws else (page.locator(".navlab-playground-message").first.inner_text() != message):
            break
        time.sleep(0.2)
    else:
        raise AssertionError(f"{selector} #{nth}: nothing redrawn within {CLICK_STALL_S} s; message: "
                             f"{page.locator('.navlab-playground-message').first.inner_text()}")
    _wait(page, "s.kernel === 'idle' && !s.busy", 60)
    return page.evaluate(_RESULT_DIGEST_JS)


@pytest.mark.notebook
def playground_paths(name: str) -> tuple[Path, str, Path]:
    """(notebook, its path under notebooks/, the stem of its screenshots) of playground ``name``."""
    notebook = PLAYGROUNDS / f"{name}.ipynb"
    rel = notebook.relative_to("notebooks").as_posix()
    return notebook, rel, SCREENSHOTS / rel.replace("/", "__").replace(".ipynb", "")


def assert_no_error_output(page: Page) -> None:
    """After a playground's clicks: no cell of the notebook shows an error output."""
    state = page.evaluate(_STATE_JS)
    errors = [(o["ename"], o["evalue"]) for c in state["cells"] for o in c["outputs"] if o["type"] == "error"]
    assert not errors, f"error output after the clicks: {errors}"


def assert_each_click_redrew(seen: list[str | None], clicks: int) -> None:
    """``seen``: the drawn result's digest before the clicks and after each one; every click changed it."""
    assert len(seen) == clicks and None not in seen, seen
    assert len(set(seen)) == clicks, f"a click left the drawn result unchanged: {seen}"


def test_pacer_playground_answers_clicks(browser, lab):
    """The PACER playground as a person uses it: Run All, make the context uninformative, click two terrain
    thumbnails (a pair "A over B"), invert it. Each click redraws a different result; no error output, no
    refusal in the message line. Screenshots after Run All, after the pair and after the inversion."""
    url, token, _ = lab
    notebook, rel, shots = playground_paths("pacer")
    seen: list[str] = []

    def interact(page: Page, run: LabRun) -> None:
        check_clean(run)
        wait_drawn(page, _RESULT_IMAGE_DRAWN)
        seen.append(page.evaluate(_RESULT_DIGEST_JS))
        seen.append(click_widget(page, ".navlab-clear"))
        click_widget(page, ".navlab-terrain", 0, redraws=False)
        assert "click the other terrain" in page.locator(".navlab-playground-message").first.inner_text()
        seen.append(click_widget(page, ".navlab-terrain", 1))
        assert page.locator(".navlab-remove").count() == 1, "the pair was not added"
        _screenshot(page, shots.with_name(shots.name + "__pair.png"))
        seen.append(click_widget(page, ".navlab-invert"))
        message = page.locator(".navlab-playground-message").first.inner_text()
        assert ERROR_MARK not in message, f"the playground refused a click: {message}"
        assert_no_error_output(page)
        page.locator("img.navlab-result").scroll_into_view_if_needed()
        _screenshot(page, shots.with_name(shots.name + "__inverted.png"))

    run = run_all(browser, url, token, rel, shots.with_name(shots.name + ".png"), interact=interact)
    print(f"{notebook}: {run.seconds}; result digests {seen}")
    assert_each_click_redrew(seen, 4)


def test_a_failing_cell_fails_the_check(browser, tmp_path):
    """A notebook that draws a figure and then raises: the error is read back and check_clean fails on it."""
    folder = tmp_path / "notebooks"
    folder.mkdir()
    nb = nbformat.v4.new_notebook(metadata={"kernelspec": {"name": "python3", "display_name": "Python 3",
                                                           "language": "python"}})
    nb.cells = [nbformat.v4.new_code_cell(PARAMETERS_CELL, metadata={"tags": ["parameters"]}),
                nbformat.v4.new_code_cell(RESOLVE_LINES),
                nbformat.v4.new_code_cell("import matplotlib.pyplot as plt\nplt.plot([0, 1], [1, 0])"),
                nbformat.v4.new_code_cell("raise RuntimeError('broken on purpose')"),
                nbformat.v4.new_code_cell("print('never reached')")]
    nbformat.write(nb, folder / "broken.ipynb")
    with jupyter_lab(tmp_path / "lab", {ENVIRONMENT["profile"]: "smoke"}, notebooks=folder) as (url, token):
        run = run_all(browser, url, token, "broken.ipynb", tmp_path / "broken.png")
        assert json.loads(_api(url, token, "kernels")) == [], "the notebook's kernel outlived its page"
    assert run.errors == [("RuntimeError", "broken on purpose")]
    assert (run.images, run.images_rendered, run.cells_run, run.code_cells) == (1, 1, 4, 5)
    with pytest.raises(AssertionError, match="error output RuntimeError: broken on purpose"):
        check_clean(run)


# --- HJ playground (issue 28, item 3): real clicks on its ipympl figure ------------------------------------
# The figure's drawn pixels: a digest of the ipympl canvas (it redraws whenever the kernel sends a new image).
_CANVAS_DIGEST_JS = """() => {
  const canvas = document.querySelector('.navlab-result canvas');
  if (!canvas || !canvas.width) return null;
  const url = canvas.toDataURL();
  let h = 2166136261;
  for (let i = 0; i < url.length; i++) h = Math.imul(h ^ url.charCodeAt(i), 16777619) >>> 0;
  return `${url.length}:${h}`;
}"""


def wait_drawn(page: Page, condition: str) -> None:
    """Wait (120 s) until ``condition`` (a JS expression) holds for the playground's drawn result, with the
    widget's cell scrolled into view first, as a reader scrolls up to it after Run All (which leaves the page at
    the last figure). If it never does, the failure says what the widget's cell shows (e.g. "Error displaying
    widget")."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    cell = page.locator(".jp-Notebook .jp-CodeCell", has_text="view.widget").first
    try:
        cell.scroll_into_view_if_needed(timeout=60_000)
        page.wait_for_function(f"() => {condition}", timeout=120_000)
    except PlaywrightTimeout as error:
        shown = cell.locator(".jp-OutputArea").inner_text(timeout=5_000) if cell.count() else "(no such cell)"
        raise AssertionError(f"the playground's result was never drawn; its cell shows: {shown[:500]!r}") from error


def click_room(page: Page, x: float, y: float) -> str:
    """A real click on the HJ playground's left panel at room position (x, y) m (the panel's box is
    ``AXES[0]`` of the figure, the room 9.6 × 5.4 m); waits for the redrawn canvas and the idle kernel."""
    from navlab.viz.playground.hj import AXES

    left, bottom, width, height = AXES[0]
    canvas = page.locator(".navlab-result .jupyter-matplotlib-canvas-div canvas").first
    canvas.scroll_into_view_if_needed()
    box = canvas.bounding_box()
    before = page.evaluate(_CANVAS_DIGEST_JS)
    position = {"x": box["width"] * (left + width * x / 9.6), "y": box["height"] * (1 - bottom - height * y / 5.4)}
    page.locator(".navlab-result .jupyter-matplotlib-canvas-div").first.click(position=position)
    deadline = time.monotonic() + CLICK_STALL_S
    while page.evaluate(_CANVAS_DIGEST_JS) == before:
        message = page.locator(".navlab-playground-message").first.inner_text()
        assert time.monotonic() < deadline, f"the click at ({x:.1f}, {y:.1f}) redrew nothing; message: {message}"
        time.sleep(0.2)
    _wait(page, "s.kernel === 'idle' && !s.busy", 60)
    time.sleep(1.0)  # ipympl sends the image after the kernel's answer; let the last one land
    return page.evaluate(_CANVAS_DIGEST_JS)


@pytest.mark.notebook
def test_hj_playground_answers_clicks(browser, lab):
    """The HJ playground as a person uses it: Run All, then with the mode toggle click a new goal, a new start
    and a human on the room figure. Each click redraws the figure; no error output, no refusal in the
    message line. Screenshots after Run All and after the clicks (docs/notebooks.md shows one,
    docs/playground_hj.png)."""
    url, token, _ = lab
    notebook, rel, shots = playground_paths("hj")
    seen: list[str] = []

    def interact(page: Page, run: LabRun) -> None:
        check_clean(run)
        wait_drawn(page, f"({_CANVAS_DIGEST_JS})() !== null")
        seen.append(page.evaluate(_CANVAS_DIGEST_JS))
        for mode, (x, y) in (("goal", (8.0, 1.6)), ("start", (1.0, 1.0)), ("human", (6.0, 1.2))):
            page.locator(".navlab-mode button", has_text=mode).first.click()
            seen.append(click_room(page, x, y))
            message = page.locator(".navlab-playground-message").first.inner_text()
            assert ERROR_MARK not in message, f"the playground refused the {mode} click: {message}"
            assert f"next click sets the {mode}" in message, message
        assert "1 human(s)" in page.locator(".navlab-playground-message").first.inner_text()
        assert_no_error_output(page)
        page.locator(".navlab-mode").first.scroll_into_view_if_needed()
        _screenshot(page, shots.with_name(shots.name + "__clicked.png"))

    run = run_all(browser, url, token, rel, shots.with_name(shots.name + ".png"), interact=interact)
    print(f"{notebook}: {run.seconds}; canvas digests {seen}")
    assert_each_click_redrew(seen, 4)


# --- SuReNav playground (issue 28 item 1) ------------------------------------------------------------

def click_map(page: Page, fraction: tuple[float, float]) -> str | None:
    """A real mouse click on the playground's ipympl map at figure fraction (fx, fy) from the lower left;
    waits for the result to redraw and the kernel to go idle. The drawn result's digest after it.

    Playwright scrolls the canvas into view and checks that the point hits it (a widget click above may have
    scrolled the map partly out of the viewport). A click the kernel never saw (the message line neither
    rewritten nor "working …" after 20 s) is clicked again: it changed nothing, so a second one is the same
    click, not a toggle undone."""
    before = page.evaluate(_RESULT_DIGEST_JS)
    line = page.locator(".navlab-playground-message").first
    message = line.inner_text()
    canvas = page.locator(".navlab-map .jupyter-matplotlib-canvas-div").first
    canvas.scroll_into_view_if_needed()
    div, box = canvas.bounding_box(), canvas.locator("canvas").last.bounding_box()  # the figure's own pixels
    position = {"x": box["x"] - div["x"] + fraction[0] * box["width"],
                "y": box["y"] - div["y"] + (1 - fraction[1]) * box["height"]}
    canvas.click(position=position)
    clicked, deadline = time.monotonic(), time.monotonic() + CLICK_STALL_S
    while page.evaluate(_RESULT_DIGEST_JS) == before:
        if time.monotonic() > deadline:
            raise AssertionError(f"map click at {fraction}: nothing redrawn within {CLICK_STALL_S} s; message: "
                                 f"{line.inner_text()}")
        if time.monotonic() - clicked > 20 and line.inner_text() == message:  # never reached the kernel
            canvas.click(position=position)
            clicked = time.monotonic()
        time.sleep(0.2)
    _wait(page, "s.kernel === 'idle' && !s.busy", 60)
    return page.evaluate(_RESULT_DIGEST_JS)


def surenav_targets(profile: str, data_dir: Path, artifacts_dir: Path) -> dict[str, tuple[float, float]]:
    """Where to click, as figure fractions of the map: the notebook's default scenario replayed here (same
    data, artefacts and code, so the same paths): the goal halfway along the cautious expert's path, then
    the start a quarter along the new one, then the superpixel halfway along the path after both moves."""
    from navlab.viz.playground.surenav import EXPERTS, MODES, SuReNavPlayground, SuReNavView

    view = SuReNavView(SuReNavPlayground.load(profile, data_dir, artifacts_dir))
    p = view.playground
    view.start()  # a refused scenario raises, saying why
    targets = {}
    for name, mode, share in (("goal", "goal", 0.5), ("start", "start", 0.25), ("close", MODES[2], None)):
        p.set_mode(mode)
        cells = p.outcome().runs[EXPERTS[0]].cells
        cell = p.midway() if share is None else tuple(cells[int(share * (len(cells) - 1))])
        targets[name] = view.figure_fraction(*p.xy(cell))
        assert view.act(p.click, *p.xy(cell)), view.message.text
    return targets


@pytest.mark.notebook
def test_surenav_playground_answers_clicks(browser, lab, smoke_data, smoke_artifacts):
    """The SuReNav playground as a person uses it: Run All, then real clicks on the map (ipympl canvas) and on
    the widgets: goal mode + a click on the map, start mode + a click, close mode + a click on a superpixel,
    then the Psi toggle. Each map click redraws a different result; no error output, no refusal in the
    message line. Screenshots after Run All and after the clicks (docs/notebooks.md shows one,
    docs/playground_surenav.png)."""
    url, token, _ = lab
    notebook, rel, shots = playground_paths("surenav")
    targets = surenav_targets("smoke", smoke_data, smoke_artifacts)
    seen: list[str] = []

    def message(page: Page) -> str:
        """The message line once the kernel's answer arrived (a widget click's wait ends at "working …")."""
        page.wait_for_function("() => !document.querySelector('.navlab-playground-message')"
                               ".innerText.startsWith('working')", timeout=60_000)
        return page.locator(".navlab-playground-message").first.inner_text()

    def interact(page: Page, run: LabRun) -> None:
        check_clean(run)
        wait_drawn(page, _RESULT_IMAGE_DRAWN)
        page.locator(".navlab-map").scroll_into_view_if_needed()
        seen.append(page.evaluate(_RESULT_DIGEST_JS))
        for name, button in (("goal", 1), ("start", 0), ("close", 2)):  # the buttons in MODES order
            click_widget(page, ".navlab-mode button", button, redraws=False)
            assert f"sets: {name}" in message(page), message(page)
            seen.append(click_map(page, targets[name]))
            assert ERROR_MARK not in message(page), f"the playground refused the {name} click: {message(page)}"
        assert "2 superpixel(s) closed" in message(page), message(page)  # the scenario's one, and this one
        _screenshot(page, shots.with_name(shots.name + "__closed.png"))
        click_widget(page, ".navlab-costs", redraws=False)
        assert "Ψ shown" in message(page) and ERROR_MARK not in message(page), message(page)
        assert_no_error_output(page)
        page.locator(".navlab-map").scroll_into_view_if_needed()
        _screenshot(page, shots.with_name(shots.name + "__costs.png"))

    run = run_all(browser, url, token, rel, shots.with_name(shots.name + ".png"), interact=interact)
    print(f"{notebook}: {run.seconds}; result digests {seen}")
    assert_each_click_redrew(seen, 4)
