"""The browser app: how soon the page is ready, how fast the simulator runs in it, its size.

Run by hand, not by pytest::

    python tests/bench/bench_web.py [--quick]

Rows (issue 29), all in headless Chromium from ``file://`` with ``roboscript web build``'s
folder:

* page ready: from the start of loading to Python started and roboscript imported, against
  5 s, the best of several opens, each in a fresh browser. Goal: at most 1.
* real-time factor in the browser: the square mission's simulated seconds per wall second,
  run from the page, against 50. Goal: at least 1 (i.e. at least 50×). The same run in this
  CPython process is reported beside it, for information.
* the folder's size, against 25 MB, for information.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
for _path in (str(HERE), str(HERE.parent), str(HERE.parent.parent)):
    if _path not in sys.path:
        sys.path.insert(0, _path)

from benchlib import Row, at_least, at_most, info, run_alone  # noqa: E402

from roboscript.web.bridge import run_text  # noqa: E402
from roboscript.web.build import build_web_app  # noqa: E402

__all__ = ["measure"]

KEY = "10"
READY_LIMIT_S = 5.0
RTF_GOAL = 50.0
SIZE_NOTE_BYTES = 25_000_000
MISSION = HERE.parent.parent / "missions" / "square.yaml"


def _renderer_cpu_s(root_pid: int) -> tuple[float, float]:
    """CPU seconds used so far by the browser's renderer: its main thread (the page itself)
    and all its threads (the worker where the page's Python runs, and the WebAssembly
    compiler's: about what page ready takes on an idle machine with this CPU, whatever the
    load now)."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rpartition(")")[2].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(stat.parent.name))

    def cpu_s(stat: Path) -> float:
        fields = stat.read_text().rpartition(")")[2].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    main = whole = 0.0
    todo = list(children.get(root_pid, []))
    while todo:
        pid = todo.pop()
        todo += children.get(pid, [])
        try:
            if b"--type=renderer" in Path(f"/proc/{pid}/cmdline").read_bytes():
                main += cpu_s(Path(f"/proc/{pid}/task/{pid}/stat"))
                whole += cpu_s(Path(f"/proc/{pid}/stat"))
        except OSError:
            continue
    return main, whole


def _open(executable: str, page: Path, profile: Path) -> Any:
    """A fresh browser with ``page`` open and ready (a student opening it)."""
    from browser import Browser

    browser = Browser(executable, profile, timeout_s=600)
    browser._call("Page.navigate", {"url": page.as_uri()})
    browser.wait_for("document.body && document.body.dataset.ready === '1'", 600)
    return browser


def _in_browser(
    page: Path, folder: Path, runs: int
) -> tuple[float, float, tuple[float, float], float]:
    """(best ms to ready over ``runs`` opens, ms of it to start the runtime, the renderer's
    CPU seconds to ready in that open, best real-time factor over ``runs`` runs of the
    square)."""
    from browser import chromium

    executable = chromium()
    if executable is None:
        nan = float("nan")
        return nan, nan, (nan, nan), nan
    opens: list[tuple[float, float, tuple[float, float]]] = []
    for index in range(runs):
        browser = _open(executable, page, folder / f"profile-{index}")
        try:
            opens.append(
                (
                    float(browser.evaluate("document.body.dataset.readyMs")),
                    float(browser.evaluate("document.body.dataset.runtimeMs")),
                    _renderer_cpu_s(browser._process.pid),
                )
            )
        finally:
            browser.close()
    ready_ms, runtime_ms, cpu_s = min(opens)
    browser = _open(executable, page, folder / "profile")
    try:
        text = MISSION.read_text(encoding="utf-8")
        best = 0.0
        for _ in range(runs):
            browser.evaluate(
                "document.querySelector('[data-role=name]').value = 'square.yaml';"
                f"document.querySelector('.CodeMirror').CodeMirror.setValue({json.dumps(text)});"
                "document.querySelector('[data-role=result]').removeAttribute('data-outcome');"
            )
            browser.wait_for("!document.querySelector('[data-action=run]').disabled", 600)
            browser.evaluate("document.querySelector('[data-action=run]').click()")
            browser.wait_for("document.querySelector('[data-role=result]').dataset.outcome", 600)
            best = max(best, float(browser.evaluate("document.body.dataset.realTimeFactor")))
        return ready_ms, runtime_ms, cpu_s, best
    finally:
        browser.close()


def measure(quick: bool = False) -> list[Row]:
    """Build the app, open it, run the square in it, and run it here for comparison."""
    runs = 2 if quick else 5
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        built = build_web_app(folder / "app")
        ready_ms, runtime_ms, (main_s, cpu_s), rtf_browser = _in_browser(built.page, folder, runs)
        text = MISSION.read_text(encoding="utf-8")
        best_here = 0.0
        for _ in range(runs):
            started = time.perf_counter()
            answer = json.loads(run_text("square.yaml", text))
            wall_s = time.perf_counter() - started
            best_here = max(best_here, answer["summary"]["duration_s"] / wall_s)
    rows = [
        at_most(
            KEY,
            "web page ready (Python + roboscript) ÷ 5 s",
            ready_ms / 1000 / READY_LIMIT_S,
            1.0,
            f"{ready_ms:.0f} ms from loading to ready: {runtime_ms:.0f} ms to load the page"
            " and start Python,"
            f" {ready_ms - runtime_ms:.0f} ms to unpack and import roboscript"
            + ("" if built.compiled else " (not compiled at build: no node)"),
        ),
        info(
            KEY,
            "web page ready: the page's own CPU time ÷ 5 s",
            cpu_s / READY_LIMIT_S,
            f"{cpu_s:.1f} s of CPU in the page's threads to ready, its Python's worker included"
            f" (about what ready takes on an idle machine like this one); {main_s:.1f} s of it"
            " on the page's main thread",
        ),
        at_least(
            KEY,
            "simulator real-time factor in the browser ÷ 50",
            rtf_browser / RTF_GOAL,
            1.0,
            f"{rtf_browser:.0f}× in the page, {best_here:.0f}× in CPython here",
        ),
        info(
            KEY,
            "web app folder size ÷ 25 MB",
            built.size_bytes / SIZE_NOTE_BYTES,
            f"{built.size_bytes / 1e6:.1f} MB",
        ),
    ]
    return rows


if __name__ == "__main__":
    run_alone(__doc__, measure, "2 runs of the square, not 5")
