"""The page says plainly, in a student's words, what this browser cannot do.

Headless Chromium stands in for the other browsers: a script run before the page's own deletes
what that browser lacks (Web Serial, Web Bluetooth, JSPI) and the user agent is the other
browser's. The simulator still runs where a robot cannot be reached. Nothing here is timed.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from browser import Browser, chromium
from web_app import LONG_S, open_offline

pytestmark = pytest.mark.timeout(1200)


FIREFOX = "Mozilla/5.0 (X11; Linux x86_64; rv:128.0) Gecko/20100101 Firefox/128.0"
IPAD = (
    "Mozilla/5.0 (iPad; CPU OS 17_5 like Mac OS X) AppleWebKit/605.1.15 (KHTML, like Gecko)"
    " CriOS/126.0.6478.54 Mobile/15E148 Safari/604.1"
)
NO_PORTS = "delete Navigator.prototype.serial; delete Navigator.prototype.bluetooth;"


def _open(page: Path, profile: Path, *, before: str = "", agent: str = "") -> Browser:
    """The page in a browser that lacks what ``before`` deletes, with user agent ``agent``."""
    browser = open_offline(page, profile, before=before, agent=agent)
    browser.wait_for("document.body.dataset.platformNotes !== undefined", LONG_S)
    return browser


def _notes(browser: Browser) -> dict[str, str]:
    return dict(
        browser.evaluate(
            "Array.from(document.querySelectorAll('[data-role=platform] li'))"
            ".map(function (li) { return [li.dataset.feature, li.textContent]; })"
        )
    )


def test_firefox_is_told_it_cannot_reach_a_robot_and_the_simulator_still_runs(
    app: Path, tmp_path: Path
) -> None:
    browser = _open(app, tmp_path, before=NO_PORTS, agent=FIREFOX)
    try:
        assert _notes(browser) == {
            "firefox": "Firefox cannot talk to a robot over USB or Bluetooth (it has no Web"
            " Serial or Web Bluetooth). The simulator and the practice grade work here; for a"
            " real robot use Chrome or Edge on a computer or a Chromebook."
        }
        browser.wait_for("document.body.dataset.ready", LONG_S)
        assert browser.evaluate("document.body.dataset.ready") == "1"
        browser.wait_for("!document.querySelector('[data-action=run]').disabled", LONG_S)
        browser.evaluate("document.querySelector('[data-action=run]').click()")
        browser.wait_for("document.querySelector('[data-role=result]').dataset.outcome", LONG_S)
        outcome = browser.evaluate("document.querySelector('[data-role=result]').dataset.outcome")
        assert outcome == "success"
        assert browser.errors == []
    finally:
        browser.close()


def test_an_ipad_is_told_no_browser_there_reaches_a_robot(app: Path, tmp_path: Path) -> None:
    browser = _open(app, tmp_path, before=NO_PORTS, agent=IPAD)
    try:
        notes = _notes(browser)
        assert list(notes) == ["ipad"]
        assert notes["ipad"].startswith(
            "On an iPad or iPhone no browser can talk to a robot over USB or Bluetooth"
        )
        assert "not even in Chrome" in notes["ipad"] and "use a Chromebook" in notes["ipad"]
    finally:
        browser.close()


def test_a_browser_without_jspi_is_told_to_update(app: Path, tmp_path: Path) -> None:
    browser = _open(
        app, tmp_path, before="delete WebAssembly.Suspending; delete WebAssembly.promising;"
    )
    try:
        notes = _notes(browser)
        if not browser.evaluate("'serial' in navigator || 'bluetooth' in navigator"):
            pytest.skip("this Chromium has neither Web Serial nor Web Bluetooth")
        assert notes["jspi"].startswith(
            "This browser is too old to drive a robot from Python in a page (it lacks JSPI"
        )
        assert "update Chrome or Edge to version 137 or later" in notes["jspi"]
    finally:
        browser.close()


def test_a_browser_without_web_serial_alone_is_told_to_use_bluetooth(
    app: Path, tmp_path: Path
) -> None:
    stand_in = "delete Navigator.prototype.serial; Navigator.prototype.bluetooth = {};"
    browser = _open(app, tmp_path, before=stand_in)
    try:
        notes = _notes(browser)
        assert notes["serial"].startswith(
            "This browser cannot talk to a robot over a USB cable (it has no Web Serial)"
        )
        assert "bluetooth" not in notes
    finally:
        browser.close()


def test_a_page_opened_without_its_folder_says_to_extract_it(app: Path, tmp_path: Path) -> None:
    alone = tmp_path / "zip-view"
    alone.mkdir()
    shutil.copy(app, alone / "index.html")  # what opening it from inside a .zip gives
    browser = Browser(chromium() or "", tmp_path / "profile", timeout_s=LONG_S)
    try:
        browser._call("Page.navigate", {"url": (alone / "index.html").as_uri()})
        browser.wait_for("document.body && document.body.dataset.ready === 'missing'")
        status = browser.evaluate("document.querySelector('[data-role=status]').textContent")
        assert status == (
            "This page's files are missing (the roboscript-web folder beside it). If you opened"
            " it from inside a .zip file, extract the whole folder first (right-click, Extract"
            " all), then open index.html from the extracted folder."
        )
    finally:
        browser.close()
