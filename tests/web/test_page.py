"""The browser app in a real headless Chromium, opened from file:// with the network off.

A student's loop: the page starts Python, a mistake typed in the editor is shown at its line,
the fixed mission runs on the simulator to its final state with the same JSON as the command
line gives for that seed, and the run replays. Waits are long enough for a machine whose every
core is busy; nothing here is timed (tests/bench/bench_web.py measures).
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
from browser import Browser, chromium
from helpers import run_cli

pytestmark = pytest.mark.timeout(1200)

LONG_S = 600.0  # Python in WebAssembly on a saturated machine takes its time; never a limit


@pytest.fixture(scope="module")
def page(app: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Browser]:
    browser = Browser(chromium() or "", tmp_path_factory.mktemp("profile"), timeout_s=LONG_S)
    try:
        browser._call("Network.enable")
        browser._call(
            "Network.emulateNetworkConditions",
            {"offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1},
        )
        browser._call("Page.navigate", {"url": app.as_uri()})
        browser.wait_for("document.body && document.body.dataset.ready !== undefined", LONG_S)
        yield browser
    finally:
        browser.close()


def _editor(browser: Browser, text: str) -> None:
    browser.evaluate(
        f"document.querySelector('.CodeMirror').CodeMirror.setValue({json.dumps(text)})"
    )


def _hello(browser: Browser) -> str:
    return str(browser.evaluate("window.rsExamples['hello.yaml']"))


def test_the_page_starts_python_offline_from_a_file(page: Browser) -> None:
    assert page.evaluate("document.body.dataset.ready") == "1"
    assert page.evaluate("location.protocol") == "file:"
    assert page.errors == []


def test_the_page_itself_carries_no_python_only_its_worker_does(page: Browser) -> None:
    # every run, on the simulator or a robot, is the worker's: the page loads no runtime
    assert page.evaluate("typeof window.loadPyodide") == "undefined"
    assert page.evaluate("typeof window.rsCreatePyodide") == "undefined"
    assert page.evaluate("typeof window.rsRobotPort") == "function"


def test_a_mistake_is_shown_at_its_line_as_it_is_typed(page: Browser) -> None:
    _editor(page, _hello(page).replace("{rotate:", "{rotat:"))
    page.wait_for("document.querySelector('[data-role=problems]').dataset.errors === '1'", LONG_S)
    shown = page.evaluate("document.querySelector('[data-role=problems] li').textContent")
    assert shown == "hello.yaml:9:10: error: unknown action 'rotat' (did you mean 'rotate'?)"
    assert page.evaluate("document.querySelector('[data-action=run]').disabled") is True
    marked = page.evaluate("document.querySelector('.CodeMirror').CodeMirror.lineInfo(8).bgClass")
    assert marked == "rs-bad-line"


def test_the_fixed_mission_runs_to_its_final_state_as_on_the_command_line(
    page: Browser, tmp_path: Path
) -> None:
    hello = _hello(page)
    _editor(page, hello)
    page.wait_for("document.querySelector('[data-role=problems]').dataset.errors === '0'", LONG_S)
    page.evaluate("document.querySelector('[data-action=run]').click()")
    page.wait_for("document.querySelector('[data-role=result]').dataset.outcome", LONG_S)
    in_browser = json.loads(
        page.evaluate("document.querySelector('[data-role=result]').dataset.json")
    )
    (tmp_path / "hello.yaml").write_text(hello, encoding="utf-8")
    in_cpython = json.loads(run_cli("run", "hello.yaml", "--json", cwd=tmp_path).stdout)
    assert in_browser == in_cpython
    assert in_browser["outcome"] == "success" and in_browser["final_state"] == "beep"


def test_the_run_replays_in_the_page(page: Browser) -> None:
    page.wait_for("document.querySelector('.rs-viewer') !== null", LONG_S)
    page.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'", LONG_S)
    states = page.evaluate(
        "Array.from(document.querySelectorAll('[data-role=timeline] [data-state]'))"
        ".map(function (b) { return b.dataset.state; })"
    )
    assert states == ["out", "turn", "back", "beep"]
    page.click("[data-role=timeline] [data-state=back]")
    assert page.evaluate("document.querySelector('[data-role=why]').textContent") == ("rotate done")
    assert page.errors == []


def test_the_page_says_when_the_browser_cannot_reach_a_robot(page: Browser) -> None:
    note = page.evaluate("document.querySelector('[data-role=hardware]').textContent")
    serial = page.evaluate("'serial' in navigator")
    bluetooth = page.evaluate("'bluetooth' in navigator")
    if serial or bluetooth:
        assert note.startswith("This browser can reach robots over ")
        assert ("USB (Web Serial)" in note) == serial
    else:
        assert note.startswith("This browser cannot reach a robot over USB or Bluetooth")
    assert "the simulator works here" in note.lower()


def test_a_world_opened_as_the_mission_is_answered_with_the_pages_advice_that_works(
    page: Browser,
) -> None:
    ring = "world: ring\nstart: {x: 300, y: 500, heading: 0}\nwalls:\n"
    ring += "  - box: {x: 0, y: 0, width: 2000, height: 1000}\n"
    page.evaluate("document.querySelector('[data-role=name]').value = 'ring.yaml'")
    _editor(page, ring)
    page.wait_for("document.querySelector('[data-role=problems]').dataset.errors === '1'", LONG_S)
    shown = page.evaluate("document.querySelector('[data-role=problems] li').textContent")
    assert shown.startswith("ring.yaml:1:1: error: this is a world file, not a mission (it is a")
    assert 'set World to "the mission\'s own"' in shown and "'world: ring.yaml' in YAML" in shown
    assert "--world" not in shown
    # as advised: the mission names the world, and World stays on "the mission's own"
    page.evaluate("document.querySelector('[data-role=name]').value = 'hello.yaml'")
    _editor(page, _hello(page).replace("initial:", "world: ring.yaml\ninitial:"))
    page.wait_for("document.querySelector('[data-role=problems]').dataset.errors === '0'", LONG_S)
    page.evaluate("document.querySelector('[data-role=result]').removeAttribute('data-outcome')")
    page.evaluate("document.querySelector('[data-action=run]').click()")
    page.wait_for("document.querySelector('[data-role=result]').dataset.outcome", LONG_S)
    ran = json.loads(page.evaluate("document.querySelector('[data-role=result]').dataset.json"))
    assert ran["sim"]["world"] == "ring"
    assert page.errors == []
